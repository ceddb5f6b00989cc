//! The `lensray` command as a user runs it: good renders, and one clear line for bad input.
//!
//! Run with `cargo test --test cli`.

mod gpu_support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[path = "cli/adaptive.rs"]
mod adaptive;
#[path = "cli/animated_nodes.rs"]
mod animated_nodes;
#[path = "cli/caches.rs"]
mod caches;
#[path = "cli/camera_animation.rs"]
mod camera_animation;
#[path = "cli/devices.rs"]
mod devices;
#[path = "cli/environment.rs"]
mod environment;
#[path = "cli/exposure.rs"]
mod exposure;
#[path = "cli/flare.rs"]
mod flare;
#[path = "cli/frames.rs"]
mod frames;
#[path = "cli/frames_gpu.rs"]
mod frames_gpu;
#[path = "cli/isa.rs"]
mod isa;
#[path = "cli/motion_blur.rs"]
mod motion_blur;
#[path = "cli/movements.rs"]
mod movements;
#[path = "cli/moving_objects.rs"]
mod moving_objects;
#[path = "cli/rejected.rs"]
mod rejected;
#[path = "cli/render.rs"]
mod render;
#[path = "cli/units.rs"]
mod units;
#[path = "cli/untrusted.rs"]
mod untrusted;
#[path = "cli/video.rs"]
mod video;

fn lensray(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run lensray")
}

/// Copies the spheres scene's mesh and library into `dir` and names the mesh as a scene file
/// there does: a file beside it, read without a note (`scene::reads`).
fn spheres_beside(dir: &Path) -> &'static str {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/spheres");
    for file in ["spheres.obj", "spheres.mtl"] {
        std::fs::copy(assets.join(file), dir.join(file)).expect("copy the spheres");
    }
    "spheres.obj"
}

/// The linear RGB of an EXR a render wrote.
fn read_exr(path: &Path) -> lensray_core::film::Image {
    let rgb = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb32f();
    lensray_core::film::Image {
        width: rgb.width(),
        height: rgb.height(),
        pixels: rgb.pixels().map(|p| glam::Vec3::from(p.0)).collect(),
    }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Small and quick: every render in these tests uses it.
const SMALL: [&str; 6] = ["--width", "48", "--height", "32", "--spp", "2"];

fn render_args<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["render", "--device", "cpu"];
    v.extend_from_slice(&SMALL);
    v.extend_from_slice(extra);
    v
}

/// Runs `args` (a `render --device cpu ...`) on `path` in `dir`: `cpu` as given, a GPU path
/// with `--device gpu --path PATH --validate`. A CPU failure fails `test`; a GPU path that
/// cannot run here skips it (or fails, `gpu_support::skip_or_fail`): `false`.
fn render_on_path<'a>(test: &str, path: &'a str, mut args: Vec<&'a str>, dir: &Path) -> bool {
    assert_eq!(&args[..3], ["render", "--device", "cpu"]);
    if path != "cpu" {
        args[2] = "gpu";
        args.extend(["--path", path, "--validate"]);
    }
    let run = lensray(&args, dir);
    if !run.status.success() {
        if path == "cpu" {
            panic!("{test}: {args:?}: {}", stderr(&run));
        }
        gpu_support::skip_or_fail(test, &stderr(&run));
        return false;
    }
    true
}

/// Runs a render that must fail: non-zero exit, exactly one stderr line mentioning `needle`,
/// no panic, and no output file left behind.
fn assert_rejected(extra: &[&str], needle: &str) {
    assert_rejected_on("cpu", extra, needle);
}

/// [`assert_rejected`] with `--device device`.
fn assert_rejected_on(device: &str, extra: &[&str], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mut args = extra.to_vec();
    // A sequence's video alone has no --out.
    if !extra.contains(&"--out") && !extra.contains(&"--video") {
        args.extend(["--out", "out.png"]);
    }
    let mut args = render_args(&args);
    args[2] = device;
    let out = lensray(&args, dir.path());
    let err = stderr(&out);
    assert!(
        !out.status.success(),
        "{extra:?} was accepted; stderr: {err}"
    );
    assert!(!err.contains("panicked"), "{extra:?} panicked: {err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{extra:?}: expected one line, got: {err}");
    assert!(
        err.to_lowercase().contains(&needle.to_lowercase()),
        "{extra:?}: message does not name '{needle}': {err}"
    );
    let leftovers: Vec<PathBuf> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            !p.extension()
                .is_some_and(|e| e == "obj" || e == "mtl" || e == "toml")
        })
        .collect();
    assert!(leftovers.is_empty(), "{extra:?} left files: {leftovers:?}");
}
