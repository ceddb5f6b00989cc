//! Sequences on the GPU paths whose keys change the lens: one process (validation on) renders
//! every frame with its own focal length or prescription, and each frame is what the CPU path
//! renders for that frame.

use std::fs;
use std::path::Path;

use crate::gpu_support::{compare, skip_or_fail, write_comparison};
use crate::{lensray, read_exr, render_args, stderr};

/// The spheres at 48x32, lit, with `keyframes` over frames 1 to 3.
fn keyed_scene(dir: &Path, keyframes: &str) -> String {
    let mesh = crate::spheres_beside(dir);
    let text = format!(
        "mesh = {mesh:?}\n\
         [camera]\neye = [0.0, 1.2, 6.5]\ntarget = [0.0, 0.4, 0.0]\nvfov_degrees = 40.0\n\
         focus_distance = 6.5\n\
         [render]\nshading = \"lit\"\nbackground = [0.5, 0.65, 0.85]\n\
         [light]\nposition = [3.0, 8.0, 6.0]\nintensity = [300.0, 300.0, 300.0]\n{keyframes}",
    );
    let path = dir.join("keyed.toml");
    fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_owned()
}

/// Renders frames 1 to 3 of `keyframes` on the CPU and, each in one process, on the `software`
/// and `rayquery` paths; every GPU frame must agree with the CPU's within 1/255 on 99.9 % of
/// pixels with a mean difference under 1e-3 (the bound of `assert_gpu_paths_match_cpu`), and
/// frames 1 and 3 must differ.
fn assert_gpu_frames_match_cpu(test: &str, keyframes: &str) {
    let dir = tempfile::tempdir().unwrap();
    let scene = keyed_scene(dir.path(), keyframes);
    let run = |device: &str, path: &str, out: &str| {
        let mut args = render_args(&["--scene", &scene, "--frames", "1-3", "--out", out]);
        args[2] = device;
        if device == "gpu" {
            args.extend(["--path", path, "--validate"]);
        }
        lensray(&args, dir.path())
    };
    let cpu = run("cpu", "cpu", "cpu.####.exr");
    assert!(cpu.status.success(), "cpu: {}", stderr(&cpu));
    let frame = |prefix: &str, n: u32| read_exr(&dir.path().join(format!("{prefix}.{n:04}.exr")));
    let first_and_last = compare(&frame("cpu", 1), &frame("cpu", 3), 1.0 / 255.0);
    assert!(
        first_and_last.within < 0.9,
        "{test}: the keys change nothing: frames 1 and 3 differ by {first_and_last:?}"
    );
    for path in ["software", "rayquery"] {
        let gpu = run("gpu", path, &format!("{path}.####.exr"));
        if !gpu.status.success() {
            skip_or_fail(test, &stderr(&gpu));
            return;
        }
        let summary = String::from_utf8_lossy(&gpu.stdout);
        assert_eq!(summary.matches("start-up").count(), 1, "{summary}");
        for n in 1..=3 {
            let (image, reference) = (frame(path, n), frame("cpu", n));
            let diff = compare(&image, &reference, 1.0 / 255.0);
            println!("{test} {path} frame {n}: {diff:?}");
            if diff.within < 0.999 || diff.mean_abs >= 1e-3 {
                let name = format!("{test}-{path}-frame{n}-vs-cpu");
                let files = write_comparison(&image, &reference, &name);
                panic!("{test}: {path} frame {n} differs from the CPU: {diff:?}; wrote {files}");
            }
        }
    }
}

/// A zoom on the thin lens, 35 mm to 85 mm at f/2.8: the field of view and the blur change
/// from frame to frame in one process.
#[test]
fn a_gpu_sequence_follows_focal_length_keys() {
    assert_gpu_frames_match_cpu(
        "a_gpu_sequence_follows_focal_length_keys",
        "[[keyframe]]\nframe = 1\nfocal_length_mm = 35.0\nf_number = 2.8\n\
         [[keyframe]]\nframe = 3\nfocal_length_mm = 85.0\n",
    );
}

/// A real lens changed for another mid-sequence (double Gauss 50 mm held over frames 1 and 2,
/// then the wide 22 mm), stopped down from f/2 to f/4: each frame traces its own prescription.
#[test]
fn a_gpu_sequence_follows_lens_keys() {
    assert_gpu_frames_match_cpu(
        "a_gpu_sequence_follows_lens_keys",
        "[[keyframe]]\nframe = 1\nlens = \"double-gauss-50\"\nf_number = 2.0\n\
         [[keyframe]]\nframe = 3\nlens = \"wide-22\"\nf_number = 4.0\n",
    );
}
