//! Adaptive sampling in the preview (`--noise-threshold`, docs/adaptive.md): on a traced GPU
//! path and on the CPU path the window goes through the render's rounds, and once every pixel
//! converged (or reached the cap) it is the headless adaptive render, float for float.

use std::process::Command;

use super::{assert_same_image, preview_with};

/// The preview's options here: small, lit, depth of field, a cap of 64 samples at T = 0.05
/// (rounds end at 32, 48 and 64).
const ADAPTIVE: [&str; 16] = [
    "--width",
    "96",
    "--height",
    "72",
    "--spp",
    "64",
    "--noise-threshold",
    "0.05",
    "--seed",
    "3",
    "--aperture-radius",
    "0.15",
    "--focus-distance",
    "8",
    "--shading",
    "lit",
];

#[test]
fn converged_adaptive_preview_equals_the_adaptive_render() {
    for path in ["rayquery", "cpu"] {
        let test = "converged_adaptive_preview_equals_the_adaptive_render";
        let dir = tempfile::tempdir().unwrap();
        let options = ["--path", path, "--screenshot", "preview.exr"];
        let script = "0 wait converged\n0 quit\n";
        let Some(out) = preview_with(test, dir.path(), script, &ADAPTIVE, &options) else {
            return;
        };
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            stdout.contains("adaptive: every pixel converged or at the cap"),
            "{path}: {stdout}"
        );
        let mut args = vec!["render", "--path", path];
        args.extend_from_slice(&ADAPTIVE);
        args.extend_from_slice(&["--out", "render.exr"]);
        let render = Command::new(env!("CARGO_BIN_EXE_lensray"))
            .args(&args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&render.stderr);
        assert!(render.status.success(), "{path}: {stderr}");
        let summary = String::from_utf8_lossy(&render.stdout);
        assert!(
            summary.contains("adaptive: noise threshold 0.05"),
            "{summary}"
        );
        let what = format!("adaptive-{path}");
        assert_same_image(dir.path(), "preview.exr", "render.exr", &what);
    }
}
