//! The preview window as a user runs it, under a private Xvfb server started by each test, on
//! the Vulkan device (lavapipe in CI) with validation on: the converged accumulation equals the
//! headless render, a click focuses on the surface under the cursor, a resize storm passes
//! without a validation message, the keys that print or save work, and a keyframed shot's
//! frames are the sequence's (`preview/keyframes.rs`).

#[path = "preview/adaptive.rs"]
mod adaptive;
#[path = "preview/animated.rs"]
mod animated;
#[path = "preview/flare.rs"]
mod flare;
mod gpu_support;
#[path = "preview/keyframes.rs"]
mod keyframes;
#[path = "preview/motion_blur.rs"]
mod motion_blur;

use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use glam::{UVec2, Vec2};
use lensray_core::reference::Renderer;
use lensray_core::sampler::CameraSample;
use lensray_core::settings::shot;

/// An Xvfb server on a free display (it picks one and tells us, `-displayfd`), stopped on drop.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Xvfb {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x1024x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("cannot start Xvfb (scripts/test.sh installs the package xvfb)");
        let mut out = child.stdout.take().expect("piped");
        let mut number = String::new();
        let mut byte = [0u8; 1];
        while out.read(&mut byte).unwrap_or(0) == 1 && byte[0] != b'\n' {
            number.push(byte[0] as char);
        }
        assert!(!number.is_empty(), "Xvfb did not report its display");
        Xvfb {
            child,
            display: format!(":{}", number.trim()),
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Runs lensray in `dir` on `x`'s display; kills it after `limit`.
fn lensray(x: &Xvfb, dir: &Path, args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run lensray");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().expect("output");
            panic!(
                "lensray {args:?} still ran after {limit:?}; stderr:\n{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

const LIMIT: Duration = Duration::from_secs(120);

/// The preview's options of these tests: small, few samples, depth of field on.
const VIEW: [&str; 12] = [
    "--width",
    "160",
    "--height",
    "120",
    "--spp",
    "4",
    "--seed",
    "3",
    "--aperture-radius",
    "0.15",
    "--focus-distance",
    "8",
];

/// Runs `preview --validate` with `script` and `extra`; `None` after recording a skip.
fn preview(test: &str, dir: &Path, script: &str, extra: &[&str]) -> Option<Output> {
    preview_with(test, dir, script, &VIEW, extra)
}

/// [`preview`] with the view options `view` instead of [`VIEW`].
fn preview_with(
    test: &str,
    dir: &Path,
    script: &str,
    view: &[&str],
    extra: &[&str],
) -> Option<Output> {
    std::fs::write(dir.join("script.txt"), script).unwrap();
    let x = Xvfb::start();
    let mut args = vec!["preview", "--validate", "--script", "script.txt"];
    args.extend_from_slice(view);
    args.extend_from_slice(extra);
    let out = lensray(&x, dir, &args, LIMIT);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    if !out.status.success() {
        gpu_support::skip_or_fail(test, &stderr);
        return None;
    }
    assert!(
        !stderr.contains("vulkan:"),
        "{test}: validation messages:\n{stderr}"
    );
    Some(out)
}

/// Runs `lensray render ARGS` in `dir` (no window), which must succeed.
fn headless(dir: &Path, args: &[&str]) {
    let render = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .arg("render")
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        render.status.success(),
        "lensray render {args:?}: {}",
        String::from_utf8_lossy(&render.stderr)
    );
}

fn read_exr(path: &Path) -> image::Rgb32FImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb32f()
}

/// With a fixed camera, the screenshot after convergence is the headless render of the same
/// camera, spp, seed and path, float for float (the same samples summed in the same order),
/// whichever path traces the samples. The hybrid too: the preview's plan, made on the device
/// from its G-buffer, is the render's (the same pass; tests/hybrid.rs holds both to the host's
/// reference plan). The raster path too (one raster pass per sample, whole samples per frame).
/// `--hide-ray-query` pins the hybrid's and the lit raster path's traversal to `software` in
/// both commands (else each picks the faster by a timed calibration, which may differ).
#[test]
fn converged_preview_equals_the_headless_render() {
    for (path, shading, extra) in [
        ("rayquery", "unlit", &[][..]),
        ("rayquery", "lit", &[]),
        ("software", "lit", &[]),
        ("cpu", "lit", &[]),
        ("hybrid", "unlit", &["--hide-ray-query"]),
        ("hybrid", "lit", &["--hide-ray-query"]),
        ("raster", "unlit", &[]),
        ("raster", "lit", &["--hide-ray-query"]),
    ] {
        let dir = tempfile::tempdir().unwrap();
        // The hybrid's and raster path's camera goes orthographic and back (key O) first: each
        // restart plans (hybrid) or projects (raster) again, and the last is the render's.
        let script = if path == "hybrid" || path == "raster" {
            "0 wait converged\n0 key O\n0 wait converged\n0 key O\n0 wait converged\n0 quit\n"
        } else {
            "0 wait converged\n0 quit\n"
        };
        let mut options = vec![
            "--path",
            path,
            "--shading",
            shading,
            "--screenshot",
            "preview.exr",
        ];
        options.extend_from_slice(extra);
        let Some(out) = preview(
            "converged_preview_equals_the_headless_render",
            dir.path(),
            script,
            &options,
        ) else {
            return;
        };
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            stdout.contains("4 of 4 samples per pixel reached"),
            "{stdout}"
        );
        // Each frame is one submission, waits only for the frame before last (frames in
        // flight) and reads back its timestamps alone.
        let per_frame: Vec<f64> = stdout
            .split_once("; per frame ")
            .map(|(_, rest)| {
                rest.split(' ')
                    .filter_map(|w| w.trim_end_matches(',').parse().ok())
                    .collect()
            })
            .unwrap_or_default();
        let [submits, waits, bytes] = per_frame[..] else {
            panic!("{path}: no per-frame counters in: {stdout}");
        };
        assert!(
            submits <= 1.0 && waits <= 1.0 && bytes <= 64.0,
            "{path}: {stdout}"
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains(&format!("preview: path {path}")),
            "{path}: {stderr}"
        );
        let mut args = vec!["render", "--path", path, "--shading", shading];
        args.extend_from_slice(&VIEW);
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", "render.exr"]);
        headless(dir.path(), &args[1..]);
        let a = read_exr(&dir.path().join("preview.exr"));
        let b = read_exr(&dir.path().join("render.exr"));
        assert_eq!(a.dimensions(), b.dimensions(), "window size");
        let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
        let worst = a
            .pixels()
            .zip(b.pixels())
            .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
            .fold(0.0f32, f32::max);
        if differing > 0 {
            let keep =
                gpu_support::output_dir().join(format!("preview-vs-render-{path}-{shading}"));
            let _ = std::fs::create_dir_all(&keep);
            for f in ["preview.exr", "render.exr"] {
                let _ = std::fs::copy(dir.path().join(f), keep.join(f));
            }
            panic!(
                "{path}, {shading}: {differing} pixels differ (by up to {worst}); images in {}",
                keep.display()
            );
        }
    }
}

/// The view depth the preview's camera sees through the centre of `pixel`, traced on the CPU.
fn traced_depth(pixel: UVec2) -> f32 {
    let description = lensray_core::scene::builtin::default_scene();
    let args = lensray::cli::args::ViewArgs {
        width: Some(160),
        height: Some(120),
        aperture_radius: Some(0.15),
        focus_distance: Some(8.0),
        ..Default::default()
    };
    let settings =
        lensray::cli::render::merged_settings(&description.settings, description.units, &args);
    let camera = shot(&settings, &description.scene).unwrap().camera;
    let ray = camera.first_order_ray(CameraSample::new(
        pixel.as_vec2() + Vec2::splat(0.5),
        Vec2::splat(0.5),
    ));
    let hit = Renderer::new(&description.scene)
        .intersect(&ray)
        .expect("a surface under the test pixel");
    camera.view_depth(ray.at(hit.t))
}

/// A scripted click sets the focus distance to the depth of the object under the cursor
/// (read from the G-buffer), within 1%.
#[test]
fn click_focuses_on_the_surface_under_the_cursor() {
    // The first sphere (left, near) and the floor further back.
    for pixel in [UVec2::new(25, 90), UVec2::new(120, 110)] {
        let dir = tempfile::tempdir().unwrap();
        let script = format!(
            "0 click {}.5 {}.5\n0 wait converged\n0 quit\n",
            pixel.x, pixel.y
        );
        let Some(out) = preview(
            "click_focuses_on_the_surface_under_the_cursor",
            dir.path(),
            &script,
            &[],
        ) else {
            return;
        };
        let stderr = String::from_utf8_lossy(&out.stderr);
        let focus: f32 = stderr
            .lines()
            .find_map(|l| l.strip_prefix("focus: "))
            .and_then(|r| r.split_whitespace().next())
            .and_then(|d| d.parse().ok())
            .unwrap_or_else(|| panic!("no focus line: {stderr}"));
        let expected = traced_depth(pixel);
        assert!(
            (focus / expected - 1.0).abs() < 0.01,
            "pixel {pixel}: focused at {focus}, the surface there is at {expected}"
        );
    }
}

/// Resizing to 1x1, minimising, back and forth, partly in views the view pass draws (albedo,
/// circle of confusion) and with a click there (a G-buffer frame among them): no crash, no
/// validation message, and the window still converges at its last size.
#[test]
fn a_resize_storm_passes_without_validation_messages() {
    let dir = tempfile::tempdir().unwrap();
    let script = "\
0.1 resize 1x1
0.1 resize 0x0
0.1 resize 320x200
0 key 2
0 resize 64x64
0.05 resize 7x300
0.05 click 3 150
0 key 5
0.1 resize 0x0
0.1 resize 200x150
0.05 key 1
0 wait converged
0 quit
";
    let Some(out) = preview(
        "a_resize_storm_passes_without_validation_messages",
        dir.path(),
        script,
        &["--screenshot", "after.png"],
    ) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("4 of 4 samples"), "{stdout}");
    let shot = image::open(dir.path().join("after.png")).expect("screenshot");
    assert_eq!((shot.width(), shot.height()), (200, 150));
}

/// C prints the camera as a scene-file snippet, a render command and (no keyframes: frame 1)
/// a `[[keyframe]]`; P saves the accumulation; V switches the view; Enter, with no keyframes
/// to play, says so.
#[test]
fn keys_print_the_camera_and_save_screenshots() {
    let dir = tempfile::tempdir().unwrap();
    let script = "0 wait converged\n0 key C\n0 key P\n0 key V\n0.1 key 1\n0 key Enter\n0 quit\n";
    let Some(out) = preview(
        "keys_print_the_camera_and_save_screenshots",
        dir.path(),
        script,
        &[],
    ) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("[camera]") && stdout.contains("lensray render"),
        "{stdout}"
    );
    assert!(
        stdout.contains("# keyframe (frame 1):\n[[keyframe]]\nframe = 1\nfocus_distance = 8.0\n"),
        "{stdout}"
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("playback: the scene has no [[keyframe]]s"),
        "{stderr}"
    );
    let shot = image::open(dir.path().join("lensray-preview-001.png")).expect("P screenshot");
    assert_eq!((shot.width(), shot.height()), (160, 120));
}

#[test]
fn help_lists_the_controls() {
    let out = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(["preview", "--help"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "Controls:",
        "left drag",
        "Escape",
        "--present-mode",
        "--script",
    ] {
        assert!(text.contains(needle), "no {needle} in:\n{text}");
    }
}

#[test]
fn bad_scripts_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.txt"), "0 jump\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(["preview", "--script", "bad.txt"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bad.txt") && err.contains("line 1"), "{err}");
}

/// The options of the real-lens tests: small, few samples; the lens frames the default scene.
const REAL_VIEW: [&str; 8] = [
    "--width", "160", "--height", "120", "--spp", "4", "--seed", "3",
];

/// The `lensray render` line the C key printed, run with `extra` in `dir`.
fn render_printed(stdout: &str, dir: &Path, extra: &[&str]) {
    let command = stdout
        .lines()
        .find(|l| l.starts_with("lensray render "))
        .unwrap_or_else(|| panic!("no render command printed: {stdout}"));
    let mut args: Vec<&str> = command.split_whitespace().skip(1).collect();
    args.extend_from_slice(extra);
    let render = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(&args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        render.status.success(),
        "{command}: {}",
        String::from_utf8_lossy(&render.stderr)
    );
}

/// Both images, pixel for pixel (float for float).
fn assert_same_image(dir: &Path, a: &str, b: &str, what: &str) {
    let (x, y) = (read_exr(&dir.join(a)), read_exr(&dir.join(b)));
    assert_eq!(x.dimensions(), y.dimensions(), "{what}: window size");
    let differing = x.pixels().zip(y.pixels()).filter(|(p, q)| p != q).count();
    if differing > 0 {
        let keep = gpu_support::output_dir().join(format!("preview-vs-render-{what}"));
        let _ = std::fs::create_dir_all(&keep);
        for f in [a, b] {
            let _ = std::fs::copy(dir.join(f), keep.join(f));
        }
        panic!(
            "{what}: {differing} pixels differ; images in {}",
            keep.display()
        );
    }
}

/// A real lens in the preview: opened with `--lens double-gauss-50`, stopped down a stop (two
/// `-` keys and a Shift+wheel step, third stops each) and focused by a click, the converged
/// window is the headless render of the command C printed (which names the lens, its
/// f-number, focus and sensor), float for float.
#[test]
fn real_lens_preview_stops_down_focuses_and_equals_the_headless_render() {
    let test = "real_lens_preview_stops_down_focuses_and_equals_the_headless_render";
    let dir = tempfile::tempdir().unwrap();
    let script = "0 wait converged\n0 key -\n0 key -\n0 scroll -1 shift\n\
                  0 click 40.5 80.5\n0 wait converged\n0 key C\n0 quit\n";
    let extra = [
        "--lens",
        "double-gauss-50",
        "--path",
        "rayquery",
        "--screenshot",
        "preview.exr",
    ];
    let Some(out) = preview_with(test, dir.path(), script, &REAL_VIEW, &extra) else {
        return;
    };
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(stderr.contains("preview: path rayquery"), "{stderr}");
    assert!(
        stdout.contains("4 of 4 samples per pixel reached"),
        "{stdout}"
    );
    let focus: f64 = stderr
        .lines()
        .find_map(|l| l.strip_prefix("focus: "))
        .and_then(|r| r.split_whitespace().next())
        .and_then(|d| d.parse().ok())
        .unwrap_or_else(|| panic!("no focus line: {stderr}"));
    let command = stdout
        .lines()
        .find(|l| l.starts_with("lensray render "))
        .unwrap_or_else(|| panic!("no render command: {stdout}"));
    let value = |option: &str| -> f64 {
        let words: Vec<&str> = command.split_whitespace().collect();
        let at = words.iter().position(|w| *w == option);
        at.and_then(|i| words.get(i + 1)?.parse().ok())
            .unwrap_or_else(|| panic!("no {option} in: {command}"))
    };
    assert!(command.contains("--lens double-gauss-50 "), "{command}");
    assert!(stdout.contains("[camera.lens]"), "{stdout}");
    let lens = lensray_core::optics::builtin::lens("double-gauss-50").unwrap();
    let widest = lensray_core::optics::paraxial::FirstOrder::of(&lens).f_number;
    let f_number = value("--f-number");
    assert!(
        (f_number / (widest * 2f64.sqrt()) - 1.0).abs() < 1e-12,
        "one stop down from f/{widest}: f/{f_number}"
    );
    assert!(
        (value("--focus-distance") - focus).abs() < 1e-4,
        "{command} vs focus {focus}"
    );
    assert_eq!(value("--sensor-height-mm"), 24.0);
    render_printed(
        &stdout,
        dir.path(),
        &["--path", "rayquery", "--out", "render.exr"],
    );
    assert_same_image(dir.path(), "preview.exr", "render.exr", "real-lens");
}

/// A real lens picked (the panel's picker, scripted) while the hybrid draws: the hybrid
/// cannot trace it, so the window switches to its traversal path and says so; the converged
/// image is the headless render of the printed command on that path. Back to the thin lens,
/// the hybrid draws again.
#[test]
fn a_lens_picked_mid_session_leaves_the_hybrid_for_a_traced_path() {
    let test = "a_lens_picked_mid_session_leaves_the_hybrid_for_a_traced_path";
    let dir = tempfile::tempdir().unwrap();
    let script = "0 wait converged\n0 lens cooke-triplet-50\n0 wait converged\n0 key C\n\
                  0 screenshot real.exr\n0 lens thin\n0 wait converged\n0 quit\n";
    // `--hide-ray-query` pins the traversal to software (see the convergence test above).
    let extra = ["--path", "hybrid", "--hide-ray-query"];
    let Some(out) = preview(test, dir.path(), script, &extra) else {
        return;
    };
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        stderr.contains(
            "preview: path software (path hybrid does not trace real lenses: lens cooke-triplet-50)"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("preview: path hybrid again"), "{stderr}");
    assert!(stdout.contains("--lens cooke-triplet-50 "), "{stdout}");
    render_printed(
        &stdout,
        dir.path(),
        &["--path", "software", "--out", "render.exr"],
    );
    assert_same_image(dir.path(), "real.exr", "render.exr", "picked-lens");
}

/// `--path hybrid` with a real lens is refused in one line, as `lensray render` refuses it.
#[test]
fn the_hybrid_refuses_a_real_lens_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let x = Xvfb::start();
    let out = lensray(
        &x,
        dir.path(),
        &[
            "preview", "--lens", "wide-22", "--path", "hybrid", "--frames", "1",
        ],
        LIMIT,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    if err.contains("cannot open a window") || err.contains("Vulkan") && !err.contains("hybrid") {
        gpu_support::skip_or_fail("the_hybrid_refuses_a_real_lens_in_one_line", &err);
        return;
    }
    assert!(!out.status.success(), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("--path hybrid does not trace real lenses (--lens wide-22)"),
        "{err}"
    );
}
