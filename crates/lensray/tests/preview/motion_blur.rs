//! Motion blur in the preview: a frame of a keyframed camera move, motion blur turned on by its
//! key (B) and the shutter open for half a frame, converges to the frame `render --frames`
//! renders with `--motion-blur on`, float for float (validation on); the still frame differs
//! from it.

use super::{assert_same_image, headless, preview_with};

#[test]
fn a_blurred_frame_in_the_window_is_the_frame_the_sequence_renders() {
    let test = "a_blurred_frame_in_the_window_is_the_frame_the_sequence_renders";
    let dir = tempfile::tempdir().unwrap();
    // A 0.2 m square 10 m ahead, the camera sliding past it 1 m a frame.
    std::fs::write(
        dir.path().join("quad.obj"),
        "v 4.9 -0.1 -10\nv 5.1 -0.1 -10\nv 5.1 0.1 -10\nv 4.9 0.1 -10\nf 1 2 3 4\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("sliding.toml"),
        "mesh = \"quad.obj\"\n[camera]\nvfov_degrees = 40.0\n\
         [image]\nfps = 24.0\n[render]\nshading = \"unlit\"\nbackground = [0.0, 0.0, 0.0]\n\
         [[keyframe]]\nframe = 0\neye = [0.0, 0.0, 0.0]\ntarget = [0.0, 0.0, -10.0]\n\
         [[keyframe]]\nframe = 10\neye = [10.0, 0.0, 0.0]\ntarget = [10.0, 0.0, -10.0]\n",
    )
    .unwrap();
    let view = [
        "--scene",
        "sliding.toml",
        "--width",
        "96",
        "--height",
        "64",
        "--spp",
        "16",
    ];
    let script = "0 frame 5\n0 key B\n0 wait converged\n0 screenshot p5.exr\n0 quit\n";
    let Some(out) = preview_with(test, dir.path(), script, &view, &["--path", "software"]) else {
        return;
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("motion blur: on"), "{test}: {stderr}");
    let mut args = vec!["--path", "software", "--frames", "5", "--out", "r.#.exr"];
    args.extend(view);
    args.extend(["--motion-blur", "on"]);
    headless(dir.path(), &args);
    assert_same_image(dir.path(), "p5.exr", "r.5.exr", "motion-blur-5");
    let mut args = vec![
        "--path",
        "software",
        "--frames",
        "5",
        "--out",
        "still.#.exr",
    ];
    args.extend(view);
    headless(dir.path(), &args);
    let (blurred, still) = (
        crate::read_exr(&dir.path().join("r.5.exr")),
        crate::read_exr(&dir.path().join("still.5.exr")),
    );
    assert_ne!(
        blurred.as_raw(),
        still.as_raw(),
        "{test}: motion blur changed nothing"
    );
}
