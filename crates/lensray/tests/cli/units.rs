//! `--scene-units` and a scene file's `units`: a card modelled in millimetres, seen through a
//! 50 mm f/1.4 lens focused nearer than it, blurs by the circle of confusion of a real camera
//! once read as millimetres; read as metres (a card 400 m wide, 1 km away) its edge stays sharp.

use std::path::Path;

use crate::{assert_rejected, lensray, stderr};

/// A card 400 x 600 mm in the plane z = 0, its right edge on the view axis (x = 0).
const CARD_OBJ: &str = "v -400 -300 0\nv 0 -300 0\nv 0 300 0\nv -400 300 0\nf 1 2 3\nf 1 3 4\n";

/// The shot in the card's units: 1000 away, focused at 300, through a 50 mm f/1.4 lens.
const SHOT: [&str; 22] = [
    "render",
    "--device",
    "cpu",
    "--width",
    "64",
    "--height",
    "48",
    "--spp",
    "16",
    "--shading",
    "unlit",
    "--eye",
    "0,0,1000",
    "--target",
    "0,0,0",
    "--focal-length-mm",
    "50",
    "--f-number",
    "1.4",
    "--focus-distance",
    "300",
    "--progress=none",
];

/// Renders the shot with `extra` options in `dir` to `out`; returns stderr.
fn render(dir: &Path, extra: &[&str], out: &str) -> String {
    let mut args = SHOT.to_vec();
    args.extend_from_slice(extra);
    args.extend(["--out", out]);
    let output = lensray(&args, dir);
    let err = stderr(&output);
    assert!(output.status.success(), "{args:?}: {err}");
    err
}

/// Columns across the card's edge whose brightness (the mean over the middle rows) lies
/// strictly between 10 % and 90 % of the way from the background's to the card's: the edge's
/// width in pixels.
fn edge_width(png: &Path) -> usize {
    let image = image::open(png).unwrap().to_luma8();
    let rows = image.height() / 4..3 * image.height() / 4;
    let profile: Vec<f64> = (0..image.width())
        .map(|x| {
            let sum: f64 = rows
                .clone()
                .map(|y| f64::from(image.get_pixel(x, y)[0]))
                .sum();
            sum / rows.len() as f64
        })
        .collect();
    // The card fills the left columns, the background the right ones.
    let (card, background) = (profile[0], profile[profile.len() - 1]);
    assert!(card > background + 50.0, "no card to measure: {profile:?}");
    let level = |t: f64| background + t * (card - background);
    profile
        .iter()
        .filter(|&&v| v > level(0.1) && v < level(0.9))
        .count()
}

#[test]
fn millimetre_scene_blurs_as_a_real_lens_does() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("card.obj"), CARD_OBJ).unwrap();
    let err = render(dir.path(), &["--scene", "card.obj"], "m.png");
    assert!(
        !err.contains("scene units"),
        "metres need no scaling: {err}"
    );
    let err = render(
        dir.path(),
        &["--scene", "card.obj", "--scene-units", "mm"],
        "mm.png",
    );
    assert!(
        err.contains("scene units: mm: the scene and its lengths scaled by 0.001 to metres"),
        "{err}"
    );
    // 1 km away and focused at 300 m the circle of confusion is 1/100 of a pixel; 1 m away and
    // focused at 0.3 m, 5 mm on the 24 mm sensor: 10 pixels of the 48, over which an edge
    // rises from 10 % to 90 % in 0.69 of the circle's diameter.
    let (sharp, blurred) = (
        edge_width(&dir.path().join("m.png")),
        edge_width(&dir.path().join("mm.png")),
    );
    assert!(
        sharp <= 1,
        "read as metres the edge is sharp: {sharp} px wide"
    );
    assert!(
        (6..=8).contains(&blurred),
        "read as millimetres the edge blurs over the circle of confusion: {blurred} px wide"
    );

    // A scene file says the same with `units`, and `--scene-units` wins over it.
    std::fs::write(
        dir.path().join("card.toml"),
        "mesh = \"card.obj\"\nunits = \"mm\"\n",
    )
    .unwrap();
    render(dir.path(), &["--scene", "card.toml"], "file.png");
    assert_eq!(edge_width(&dir.path().join("file.png")), blurred);
    render(
        dir.path(),
        &["--scene", "card.toml", "--scene-units", "m"],
        "file-m.png",
    );
    assert_eq!(edge_width(&dir.path().join("file-m.png")), sharp);
}

#[test]
fn unknown_units_are_one_line_errors() {
    assert_rejected(&["--scene-units", "furlong"], "furlong");
    assert_rejected(&["--scene-units", "furlong"], "m, cm, mm or in");
}

/// A glTF of one triangle, its bounds' centre at (0.5, 0.5, 0), and a camera 1.4248992 m in
/// front of it on +z: metres, as glTF is.
fn write_triangle_with_camera(dir: &Path) -> std::path::PathBuf {
    let floats = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let bin: Vec<u8> = floats.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.join("triangle.bin"), bin).unwrap();
    let json = r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 1.4248992]}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.001}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "buffers": [{"uri": "triangle.bin", "byteLength": 36}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}]}"#;
    let path = dir.join("camera.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

/// A focus distance inside the focal length is one error line that names what chose it, with
/// its numbers rounded, and points at --scene-units; the command fails and writes nothing.
#[test]
fn a_focus_within_the_focal_length_names_what_chose_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_triangle_with_camera(dir.path());
    let scene = scene.to_str().unwrap();
    let cases: [(&[&str], &str); 2] = [
        // Read as centimetres, the file's camera stands 1.425 cm from the triangle.
        (
            &["--scene-units", "cm", "--focal-length-mm", "50"],
            "focus distance 0.01425 m is within the focal length (50 mm): no image forms; \
             the depth of the camera's target (the file's camera, or --eye and --target) chose it \
             (does --scene-units match the scene's units?)",
        ),
        (
            &["--focus-distance", "0.0123456", "--focal-length-mm", "85"],
            "focus distance 0.01235 m is within the focal length (85 mm): no image forms; \
             the focus distance setting (--focus-distance or the scene file's) chose it",
        ),
    ];
    for (extra, says) in cases {
        let mut args = vec!["render", "--device", "cpu", "--scene", scene];
        args.extend_from_slice(extra);
        args.extend(["--out", "out.png"]);
        let output = lensray(&args, dir.path());
        let err = stderr(&output);
        assert!(!output.status.success(), "{extra:?} was accepted: {err}");
        assert!(!err.contains("panicked"), "{extra:?} panicked: {err}");
        let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error")).collect();
        assert_eq!(errors.len(), 1, "{extra:?}: one error line: {err}");
        assert!(errors[0].contains(says), "{extra:?}: {err}");
        assert!(
            !dir.path().join("out.png").exists(),
            "{extra:?} wrote an image"
        );
    }
}
