//! A keyframed shot in the preview: a frame the script sets is the frame `render --frames`
//! renders, float for float; C prints that frame's `[[keyframe]]`, whose focus is the
//! keyframes' dioptre curve there; Enter plays at the scene's 24 fps and pauses.

use std::path::Path;

use super::{assert_same_image, headless, preview_with};
use lensray_core::settings::Keyframes;

/// The spheres with a focus pull from 3 m to 12 m and the eye moving over frames 1 to
/// 240 (10 s at 24 fps), eased.
fn shot_scene(dir: &Path) -> String {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/spheres/spheres.obj");
    let text = format!(
        "mesh = {mesh:?}\n\
         [camera]\neye = [0.0, 1.2, 6.5]\ntarget = [0.0, 0.4, 0.0]\nvfov_degrees = 40.0\n\
         aperture_radius = 0.3\nfocus_distance = 6.5\n\
         [render]\nshading = \"lit\"\nbackground = [0.5, 0.65, 0.85]\n\
         [light]\nposition = [3.0, 8.0, 6.0]\nintensity = [300.0, 300.0, 300.0]\n\
         [[keyframe]]\nframe = 1\nfocus_distance = 3.0\neye = [0.0, 1.2, 6.5]\n\
         interpolation = \"smooth\"\n\
         [[keyframe]]\nframe = 240\nfocus_distance = 12.0\neye = [1.5, 0.8, 6.0]\n",
        mesh = mesh.to_str().unwrap()
    );
    std::fs::write(dir.join("shot.toml"), text).unwrap();
    "shot.toml".into()
}

/// The focus of frame `frame` of the pull: smooth in dioptres from 1/3 to 1/12 over 1-240.
fn pull_focus(frame: u32) -> f64 {
    let t = f64::from(frame - 1) / 239.0;
    let w = t * t * (3.0 - 2.0 * t);
    1.0 / ((1.0 - w) / 3.0 + w / 12.0)
}

/// The `[[keyframe]]` table C printed.
fn printed_keyframe(stdout: &str) -> Keyframes {
    let table = stdout
        .split_once("# keyframe (frame 200):\n")
        .map(|(_, rest)| rest.split("\n\n").next().unwrap_or(rest))
        .unwrap_or_else(|| panic!("no keyframe printed for frame 200: {stdout}"));
    let document: toml::Table = table.parse().unwrap_or_else(|e| panic!("{e}: {table}"));
    let tables: Vec<toml::Table> = document["keyframe"]
        .as_array()
        .expect("[[keyframe]]")
        .iter()
        .map(|t| t.as_table().unwrap().clone())
        .collect();
    Keyframes::parse(&tables, Path::new(".")).unwrap_or_else(|e| panic!("{e}: {table}"))
}

#[test]
fn a_frame_of_a_keyframed_shot_is_the_frame_the_sequence_renders() {
    let test = "a_frame_of_a_keyframed_shot_is_the_frame_the_sequence_renders";
    let dir = tempfile::tempdir().unwrap();
    let scene = shot_scene(dir.path());
    let view = [
        "--scene", &scene, "--width", "96", "--height", "54", "--spp", "4",
    ];
    let script = "0 frame 30\n0 wait converged\n0 screenshot p30.exr\n\
                  0 frame 200\n0 wait converged\n0 screenshot p200.exr\n0 key C\n\
                  0 key Enter\n0.3 key Enter\n0 quit\n";
    let Some(out) = preview_with(test, dir.path(), script, &view, &["--path", "rayquery"]) else {
        return;
    };
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        stderr.contains("preview: keyframes from frame 1 to 240 at 24 fps"),
        "{stderr}"
    );
    let mut args = vec![
        "--path",
        "rayquery",
        "--frames",
        "30-200:170",
        "--out",
        "r.####.exr",
    ];
    args.extend(view);
    headless(dir.path(), &args);
    assert_same_image(dir.path(), "p30.exr", "r.0030.exr", "keyframe-30");
    assert_same_image(dir.path(), "p200.exr", "r.0200.exr", "keyframe-200");

    // C's keyframe, read back, is frame 200 of the shot.
    let keys = printed_keyframe(&stdout);
    assert_eq!(keys.range(), Some((200, 200)));
    let camera = keys.settings_at(&Default::default(), 200).camera;
    let focus = camera.focus_distance.expect("focus_distance");
    assert!(
        (focus / pull_focus(200) - 1.0).abs() < 1e-12,
        "printed focus {focus}, the pull's at frame 200 {}",
        pull_focus(200)
    );
    let t = 199.0 / 239.0;
    let w = t * t * (3.0 - 2.0 * t);
    let eye = [1.5 * w, 1.2 - 0.4 * w, 6.5 - 0.5 * w];
    let printed = camera.eye.expect("eye");
    assert!(
        (0..3).all(|i| (printed[i] - eye[i]).abs() < 1e-12),
        "printed eye {printed:?}, the keyed eye at frame 200 {eye:?}"
    );

    // Played for at least 0.3 s at 24 fps: at least 7 frames on from 200,
    // looping over 1-240 (10 s).
    let paused: u32 = stderr
        .lines()
        .find_map(|l| l.strip_prefix("playback: paused at frame "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("no pause line: {stderr}"));
    let advanced = (paused + 240 - 200) % 240;
    assert!(
        (1..=240).contains(&paused) && advanced >= 7,
        "paused at frame {paused}: {advanced} frames on from 200 (mod 240)"
    );
}
