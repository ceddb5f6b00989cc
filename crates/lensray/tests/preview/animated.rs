//! An animated glTF in the preview: Khronos's BoxAnimated (`assets/BoxAnimated`) plays over its
//! animation's frames, and a frame the script sets is the frame `render --frames` renders,
//! float for float, the inner box posed there (the scene handed to the path again on each
//! frame, validation on).

use super::{assert_same_image, headless, preview_with};

fn box_animated() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/BoxAnimated/BoxAnimated.gltf")
}

/// The view and light of every window and render here (the default camera and light follow
/// the scene's bounds, which the poses change).
fn view(file: &std::path::Path) -> [&str; 18] {
    [
        "--scene",
        file.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
        "--spp",
        "4",
        "--eye",
        "0,3,7",
        "--target",
        "0,1.5,0",
        "--up",
        "0,1,0",
        "--light-position",
        "2,6,5",
        "--light-intensity",
        "60,60,60",
    ]
}

#[test]
fn a_frame_of_an_animated_file_is_the_frame_the_sequence_renders() {
    let test = "a_frame_of_an_animated_file_is_the_frame_the_sequence_renders";
    let dir = tempfile::tempdir().unwrap();
    let file = box_animated();
    let view = view(&file);
    let script = "0 frame 18\n0 wait converged\n0 screenshot p18.exr\n\
                  0 frame 42\n0 wait converged\n0 screenshot p42.exr\n0 quit\n";
    let Some(out) = preview_with(test, dir.path(), script, &view, &["--path", "software"]) else {
        return;
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    // The animation's keys run from 0 to 3.708 s: frames 0 to 89 at 24 fps.
    assert!(
        stderr.contains("preview: frames 0 to 89 at 24 fps"),
        "{stderr}"
    );
    let mut args = vec![
        "--path",
        "software",
        "--frames",
        "18-42:24",
        "--out",
        "r.####.exr",
    ];
    args.extend(view);
    headless(dir.path(), &args);
    assert_same_image(dir.path(), "p18.exr", "r.0018.exr", "animated-18");
    assert_same_image(dir.path(), "p42.exr", "r.0042.exr", "animated-42");
}

/// With motion blur on, a frame of BoxAnimated in the preview is the blurred frame the
/// sequence renders, float for float: the inner box turns 36 degrees while the shutter is open
/// (4 fps, a 360-degree shutter, frame 7 at 1.75 s), and the window hands the path its steps.
#[test]
fn a_blurred_frame_of_an_animated_file_is_the_frame_the_sequence_renders() {
    let test = "a_blurred_frame_of_an_animated_file_is_the_frame_the_sequence_renders";
    let dir = tempfile::tempdir().unwrap();
    let file = box_animated();
    let mut view = view(&file).to_vec();
    view.extend(["--fps", "4", "--shutter-angle", "360"]);
    let blur = ["--motion-blur", "on"];
    let script = "0 frame 7\n0 wait converged\n0 screenshot p7.exr\n0 quit\n";
    let mut window = view.to_vec();
    window.extend(blur);
    let Some(_) = preview_with(test, dir.path(), script, &window, &["--path", "software"]) else {
        return;
    };
    let mut args = vec!["--path", "software", "--frames", "7", "--out", "r.#.exr"];
    args.extend(&view);
    args.extend(blur);
    headless(dir.path(), &args);
    assert_same_image(dir.path(), "p7.exr", "r.7.exr", "animated-blurred-7");
    // The blur is there: the sequence's still frame differs.
    let mut still = vec!["--path", "software", "--frames", "7", "--out", "s.#.exr"];
    still.extend(&view);
    headless(dir.path(), &still);
    let (blurred, sharp) = (
        std::fs::read(dir.path().join("r.7.exr")).unwrap(),
        std::fs::read(dir.path().join("s.7.exr")).unwrap(),
    );
    assert_ne!(blurred, sharp, "{test}: motion blur changed nothing");
}
