//! The `lensray` command as a user runs it: good renders, and one clear line for bad input.

mod gpu_support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use gpu_support::skip_or_fail;

fn lensray(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run lensray")
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

/// Runs a render that must fail: non-zero exit, exactly one stderr line mentioning `needle`,
/// no panic, and no output file left behind.
fn assert_rejected(extra: &[&str], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mut args = extra.to_vec();
    if !extra.contains(&"--out") {
        args.extend(["--out", "out.png"]);
    }
    let out = lensray(&render_args(&args), dir.path());
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

#[test]
fn default_scene_renders_png_and_exr() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["a.png", "b.exr"] {
        let out = lensray(&render_args(&["--out", name]), dir.path());
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let img = image::open(dir.path().join(name)).expect("readable image");
        assert_eq!((img.width(), img.height()), (48, 32), "{name} size");
        let summary = String::from_utf8_lossy(&out.stdout);
        assert!(summary.contains("Mrays/s"), "summary line: {summary}");
        assert!(
            summary.contains("(sobol sampler)"),
            "summary line: {summary}"
        );
    }
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "only the two images remain: {names:?}");
}

#[test]
fn sampler_option_picks_the_sampler() {
    let dir = tempfile::tempdir().unwrap();
    let out = lensray(
        &render_args(&["--sampler", "independent", "--out", "i.png"]),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(
        summary.contains("(independent sampler)"),
        "summary line: {summary}"
    );
}

#[test]
fn bare_obj_is_framed_from_the_front() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let out = lensray(
        &render_args(&["--scene", "tri.obj", "--shading", "unlit", "--out", "t.png"]),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("t.png")).unwrap().to_rgb8();
    // The triangle is framed: the centre pixel shows it, in focus and fully covered (the
    // default material, 0.8 grey), a corner the default background (0.1 grey); PNG is sRGB.
    let srgb8 = |linear: f64| {
        let v = if linear <= 0.003_130_8 {
            12.92 * linear
        } else {
            1.055 * linear.powf(1.0 / 2.4) - 0.055
        };
        (v * 255.0).round() as u8
    };
    let centre = img.get_pixel(24, 16).0;
    let corner = img.get_pixel(0, 0).0;
    assert_eq!(centre, [srgb8(0.8); 3], "centre: the triangle's grey");
    assert_eq!(corner, [srgb8(0.1); 3], "corner: the background");
}

#[test]
fn bad_numbers_are_rejected_with_one_line() {
    assert_rejected(&["--vfov", "nan"], "field of view");
    assert_rejected(&["--vfov", "0"], "field of view");
    assert_rejected(&["--vfov", "180"], "field of view");
    assert_rejected(&["--aperture-radius", "-0.1"], "aperture");
    assert_rejected(&["--aperture-radius", "inf"], "aperture");
    assert_rejected(&["--focus-distance", "-2"], "focus distance");
    assert_rejected(&["--focus-distance", "0"], "focus distance");
    assert_rejected(
        &["--projection", "orthographic", "--ortho-height", "0"],
        "height",
    );
    assert_rejected(&["--spp", "0"], "spp");
    assert_rejected(&["--sampler", "bogus"], "sampler");
    assert_rejected(&["--width", "0"], "0x32");
    assert_rejected(&["--height", "20000"], "48x20000");
    assert_rejected(&["--width", "abc"], "width");
    assert_rejected(&["--eye", "1,2"], "three");
    assert_rejected(&["--eye", "1,2,3", "--target", "1,2,3"], "eye and target");
    assert_rejected(
        &["--eye", "0,0,5", "--target", "0,0,0", "--up", "0,0,1"],
        "parallel",
    );
    assert_rejected(&["--near", "-1"], "near");
    assert_rejected(&["--near", "5", "--far", "1"], "far");
    assert_rejected(&["--background", "nan,0,0"], "background");
    assert_rejected(&["--light-intensity", "-1,1,1"], "light intensity");
    assert_rejected(
        &["--focal-length-mm", "0", "--focus-distance", "2"],
        "focal length",
    );
    assert_rejected(&["--focal-length-mm", "50", "--f-number", "-2"], "f-number");
    assert_rejected(
        &["--focal-length-mm", "50", "--focus-distance", "0.04"],
        "focal length",
    );
    assert_rejected(&["--f-number", "2"], "focal length");
}

#[test]
fn bad_aperture_shapes_are_rejected_with_one_line() {
    assert_rejected(&["--aperture-blades", "2"], "aperture blades");
    assert_rejected(&["--aperture-blades", "33"], "aperture blades");
    assert_rejected(&["--aperture-blades", "-1"], "aperture-blades");
    assert_rejected(
        &["--aperture-blades", "6", "--aperture-roundness", "1.5"],
        "roundness",
    );
    assert_rejected(&["--aperture-roundness", "-0.1"], "roundness");
    assert_rejected(&["--aperture-aspect", "0"], "aperture aspect");
    assert_rejected(&["--aperture-aspect", "nan"], "aperture aspect");
    assert_rejected(&["--aperture-rotation", "inf"], "aperture rotation");
    // Aperture images: all black, missing, not an image, not PNG or EXR, beside blades.
    let images = tempfile::tempdir().unwrap();
    let path = |name: &str| images.path().join(name).to_str().unwrap().to_owned();
    image::GrayImage::new(8, 8).save(path("black.png")).unwrap();
    image::GrayImage::from_pixel(8, 8, image::Luma([255]))
        .save(path("white.png"))
        .unwrap();
    std::fs::write(path("text.png"), "not a PNG").unwrap();
    std::fs::write(path("mask.txt"), "1 1\n1 1\n").unwrap();
    assert_rejected(&["--aperture-image", &path("black.png")], "all black");
    assert_rejected(&["--aperture-image", &path("missing.png")], "missing.png");
    assert_rejected(&["--aperture-image", &path("text.png")], "text.png");
    assert_rejected(&["--aperture-image", &path("mask.txt")], "png or .exr");
    assert_rejected(
        &[
            "--aperture-image",
            &path("white.png"),
            "--aperture-blades",
            "6",
        ],
        "either aperture blades or an aperture image",
    );
}

#[test]
fn bad_files_are_rejected_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    std::fs::write(p.join("bad.obj"), "v 1 2\nf 1 2 3\n").unwrap();
    std::fs::write(p.join("empty.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    std::fs::write(
        p.join("nomtl.obj"),
        "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(p.join("bad.toml"), "mesh = \"bad.obj\"\n[camera\n").unwrap();
    std::fs::write(p.join("unknown.toml"), "mesh = \"empty.obj\"\nzoom = 3\n").unwrap();
    for (scene, needle) in [
        ("missing.obj", "missing.obj"),
        ("bad.obj", "bad.obj"),
        ("empty.obj", "no triangles"),
        ("nomtl.obj", "missing.mtl"),
        ("bad.toml", "bad.toml"),
        ("unknown.toml", "zoom"),
        ("scene.txt", "scene.txt"),
    ] {
        let dir2 = tempfile::tempdir().unwrap();
        let full = p.join(scene);
        let out = lensray(
            &render_args(&["--scene", full.to_str().unwrap(), "--out", "o.png"]),
            dir2.path(),
        );
        let err = stderr(&out);
        assert!(!out.status.success(), "{scene} accepted");
        assert!(!err.contains("panicked"), "{scene}: {err}");
        assert_eq!(err.lines().count(), 1, "{scene}: {err}");
        assert!(
            err.contains(needle),
            "{scene}: '{err}' does not name '{needle}'"
        );
        assert!(
            !dir2.path().join("o.png").exists(),
            "{scene}: output written"
        );
    }
}

#[test]
fn bad_outputs_are_rejected_before_rendering() {
    assert_rejected(&["--out", "image.jpg"], "extension");
    // The reason, not the name of the temporary file the check made.
    assert_rejected(
        &["--out", "/nonexistent-dir/x.png"],
        "/nonexistent-dir/x.png: cannot write there: no such folder",
    );
    let under_a_file = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml/x.png");
    assert_rejected(&["--out", under_a_file], "a parent is not a folder");
}

/// Runs lensray with the Vulkan loader pointed at no driver at all: the machine "has no GPU".
fn lensray_without_vulkan(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .env("VK_ICD_FILENAMES", "/nonexistent/lensray-no-driver.json")
        .env("VK_DRIVER_FILES", "/nonexistent/lensray-no-driver.json")
        .output()
        .expect("run lensray")
}

#[test]
fn device_gpu_without_a_vulkan_device_is_one_clear_line() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = render_args(&["--out", "g.png"]);
    args[2] = "gpu";
    let out = lensray_without_vulkan(&args, dir.path());
    let err = stderr(&out);
    assert!(!out.status.success(), "accepted without a device: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("--device gpu") && err.contains("Vulkan"),
        "{err}"
    );
    assert!(!dir.path().join("g.png").exists());
}

#[test]
fn device_auto_falls_back_to_the_cpu_with_a_notice() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = render_args(&["--out", "a.png"]);
    args[2] = "auto";
    let out = lensray_without_vulkan(&args, dir.path());
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(err.lines().count(), 1, "one notice line: {err}");
    assert!(err.starts_with("notice: rendering on the CPU"), "{err}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("path cpu (auto: no usable Vulkan device) on CPU"),
        "{text}"
    );
    assert!(dir.path().join("a.png").exists());
}

#[test]
fn device_gpu_renders_and_autofocuses_with_validation() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = render_args(&["--validate", "--focus-at", "40,14", "--out", "g.exr"]);
    args[2] = "gpu";
    let out = lensray(&args, dir.path());
    let err = stderr(&out);
    if !out.status.success() {
        skip_or_fail("device_gpu_renders_and_autofocuses_with_validation", &err);
        return;
    }
    assert!(err.contains("autofocus: pixel 40,14"), "{err}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        ["rayquery", "software", "hybrid", "raster"]
            .iter()
            .any(|path| text.contains(&format!("path {path} (auto: "))),
        "{text}"
    );
    let img = image::open(dir.path().join("g.exr")).expect("EXR written");
    assert_eq!((img.width(), img.height()), (48, 32));
}

/// Killed in the middle of a render (after its first progress line, long before its end), lensray
/// leaves nothing behind: no image, no temporary file.
#[test]
fn interrupted_render_leaves_no_file() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    // ~1.3 G rays: minutes of work, so the kill below lands mid-render on any machine.
    let mut child = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args([
            "render",
            "--device",
            "cpu",
            "--spp",
            "4096",
            "--progress",
            "lines",
            "--out",
            "big.png",
        ])
        .current_dir(dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start lensray");
    let mut lines = std::io::BufReader::new(child.stderr.take().unwrap()).lines();
    let first = lines
        .next()
        .expect("a progress line before the end")
        .expect("read stderr");
    assert!(first.starts_with("progress: "), "unexpected: {first}");
    let listing = || -> Vec<PathBuf> {
        std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect()
    };
    assert!(listing().is_empty(), "mid-render files: {:?}", listing());
    child.kill().expect("kill");
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "the render finished before it was killed"
    );
    assert!(
        listing().is_empty(),
        "an interrupted render left {:?}",
        listing()
    );
}

#[test]
fn progress_lines_count_up_to_100_percent() {
    let dir = tempfile::tempdir().unwrap();
    let out = lensray(&render_args(&["--progress", "lines"]), dir.path());
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    let percents: Vec<u64> = err
        .lines()
        .map(|l| {
            l.strip_prefix("progress: ")
                .and_then(|r| r.split('%').next())
                .and_then(|p| p.parse().ok())
                .unwrap_or_else(|| panic!("not a progress line: {l}"))
        })
        .collect();
    assert!(percents.windows(2).all(|w| w[0] < w[1]), "{percents:?}");
    assert_eq!(percents.last(), Some(&100), "{err}");
}

/// `--validate` validates the Vulkan renderer and `--gpu` picks a Vulkan device: with the CPU
/// renderer both are errors, never silently ignored.
#[test]
fn gpu_options_with_device_cpu_are_errors() {
    assert_rejected(&["--validate"], "--validate");
    assert_rejected(&["--validate"], "--device cpu");
    assert_rejected(&["--gpu", "0"], "--gpu 0");
    assert_rejected(&["--gpu", "0"], "--device cpu");
}

/// A bad `--gpu` fails under `auto` too (instead of rendering on the CPU).
#[test]
fn bad_gpu_index_under_auto_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = render_args(&["--gpu", "99", "--out", "a.png"]);
    args[2] = "auto";
    let out = lensray(&args, dir.path());
    let err = stderr(&out);
    assert!(!out.status.success(), "accepted --gpu 99: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("--gpu 99"), "{err}");
    assert!(!dir.path().join("a.png").exists());
}

/// With `--validate` and no validation layer, `auto` does not fall back to an unvalidated CPU
/// render: one line naming the package to install.
#[test]
fn validate_without_the_layer_names_the_package() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = render_args(&["--validate", "--out", "a.png"]);
    args[2] = "auto";
    let out = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(&args)
        .current_dir(dir.path())
        // The loader then searches only this (empty) folder for explicit layers.
        .env("VK_LAYER_PATH", dir.path().join("no-layers"))
        .output()
        .expect("run lensray");
    let err = stderr(&out);
    assert!(!out.status.success(), "rendered without validation: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("--validate") && err.contains("vulkan-validationlayers"),
        "{err}"
    );
    assert!(!dir.path().join("a.png").exists());
}

/// `bench --device auto` without a Vulkan device benches the CPU path alone, with a notice.
#[test]
fn bench_auto_falls_back_to_the_cpu() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "bench",
        "--device",
        "auto",
        "--width",
        "16",
        "--height",
        "12",
        "--spp",
        "1",
        "--runs",
        "1",
        "--reference-spp",
        "8",
    ];
    let out = lensray_without_vulkan(&args, dir.path());
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.starts_with("notice: benchmarking the CPU path only"),
        "{err}"
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("path cpu: CPU"), "{text}");
    assert!(!text.contains("rayquery"), "{text}");
}

/// An AOV bench times what it measures, one pass per image (GPU paths: the raster G-buffer, by
/// timestamps), and reports passes per second, not 0 Mrays/s.
#[test]
fn aov_bench_reports_passes_per_second() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "bench",
        "--shading",
        "depth",
        "--width",
        "32",
        "--height",
        "24",
        "--repeat",
        "3",
        "--no-cache",
    ];
    let out = lensray(&args, dir.path());
    let err = stderr(&out);
    if !out.status.success() {
        skip_or_fail("aov_bench_reports_passes_per_second", &err);
        return;
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let rows: Vec<&str> = text.lines().filter(|l| l.contains(" passes/s")).collect();
    assert!(rows.len() >= 2, "a GPU path and the CPU path: {text}");
    for row in rows {
        let rate: f64 = row
            .split_whitespace()
            .collect::<Vec<_>>()
            .windows(2)
            .find(|w| w[1] == "passes/s")
            .map(|w| w[0].parse().unwrap())
            .unwrap();
        assert!(rate > 0.0 && rate.is_finite(), "{row}");
    }
    assert!(
        text.contains("rayquery") || text.contains("software"),
        "{text}"
    );
}

/// `lensray` with its cache (auto's calibration) in `cache`.
fn lensray_cached(args: &[&str], dir: &Path, cache: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .env("LENSRAY_CACHE_DIR", cache)
        .output()
        .expect("run lensray")
}

/// The path the summary line names, and the reason in the parentheses after it.
fn summary_path(out: &Output) -> (String, String) {
    let summary = String::from_utf8_lossy(&out.stdout).into_owned();
    let rest = summary
        .split_once(", path ")
        .unwrap_or_else(|| panic!("no path in the summary: {summary}"))
        .1;
    let (path, why) = rest.split_once(' ').expect("a reason");
    (path.to_string(), why.to_string())
}

/// Whether the Vulkan device `auto` would open is a CPU implementation (lavapipe); `None`
/// without a usable device.
fn vulkan_device_is_cpu(dir: &Path) -> Option<bool> {
    let out = lensray(&["info"], dir);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let first = text.lines().find(|l| l.starts_with("[0] "))?;
    Some(first.ends_with("(CPU)"))
}

/// On a CPU implementation of Vulkan (lavapipe), `--device auto --path auto` renders on the
/// CPU reference without timing anything, and so picks it every run; the summary says why.
#[test]
fn auto_renders_on_the_cpu_on_a_cpu_vulkan_device_every_time() {
    let dir = tempfile::tempdir().unwrap();
    let cache = tempfile::tempdir().unwrap();
    if vulkan_device_is_cpu(dir.path()) == Some(false) {
        println!("the Vulkan device is a GPU: auto calibrates it instead (not this test)");
        return;
    }
    let args = [
        "render", "--width", "48", "--height", "32", "--spp", "2", "--out", "a.png",
    ];
    for run in 0..3 {
        let out = lensray_cached(&args, dir.path(), cache.path());
        assert!(out.status.success(), "{}", stderr(&out));
        let (path, why) = summary_path(&out);
        assert_eq!(path, "cpu", "run {run}: {why}");
        assert!(
            why.contains("is a CPU implementation of Vulkan") || why.contains("no usable Vulkan"),
            "run {run}: {why}"
        );
    }
}

/// `lensray calibrate` measures the CPU reference and the device's traversals and caches their
/// costs; `auto` then decides from them (saying so), every run alike; a corrupt cache file is
/// one notice, and the render goes on.
#[test]
fn calibrate_caches_the_costs_auto_decides_from() {
    let test = "calibrate_caches_the_costs_auto_decides_from";
    let dir = tempfile::tempdir().unwrap();
    let cache = tempfile::tempdir().unwrap();
    let out = lensray_cached(&["calibrate"], dir.path(), cache.path());
    if !out.status.success() {
        skip_or_fail(test, &stderr(&out));
        return;
    }
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    for line in [
        "  cpu ",
        "ns per pixel-sample",
        "--path auto renders",
        "cached in",
    ] {
        assert!(text.contains(line), "calibrate printed:\n{text}");
    }
    let file = cache.path().join("calibration.json");
    assert!(file.is_file(), "no {}", file.display());
    let args = [
        "render", "--width", "48", "--height", "32", "--spp", "2", "--out", "c.png",
    ];
    let mut chosen = Vec::new();
    for _ in 0..3 {
        let out = lensray_cached(&args, dir.path(), cache.path());
        assert!(out.status.success(), "{}", stderr(&out));
        let (path, why) = summary_path(&out);
        assert!(why.contains("calibration (cached)"), "{path}: {why}");
        chosen.push(path);
    }
    assert!(chosen.iter().all(|p| *p == chosen[0]), "{chosen:?}");

    std::fs::write(&file, "{ this is not a calibration").unwrap();
    let out = lensray_cached(&args, dir.path(), cache.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    let notices: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("notice: ignoring"))
        .collect();
    assert_eq!(notices.len(), 1, "stderr: {err}");
    assert!(notices[0].contains("calibration.json"), "{err}");
}

/// Vulkan pipelines go through a cache kept on disk per device and driver: the first GPU run
/// writes it, later runs use it silently, and a damaged file is one notice, then replaced.
#[test]
fn the_pipeline_cache_is_kept_and_a_damaged_one_is_replaced() {
    let test = "the_pipeline_cache_is_kept_and_a_damaged_one_is_replaced";
    let dir = tempfile::tempdir().unwrap();
    let cache = tempfile::tempdir().unwrap();
    let args = [
        "render",
        "--path",
        "software",
        "--width",
        "32",
        "--height",
        "24",
        "--spp",
        "1",
        "--validate",
        "--out",
        "p.png",
    ];
    let out = lensray_cached(&args, dir.path(), cache.path());
    if !out.status.success() {
        skip_or_fail(test, &stderr(&out));
        return;
    }
    let files: Vec<PathBuf> = std::fs::read_dir(cache.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("pipelines-")
        })
        .collect();
    assert_eq!(files.len(), 1, "one cache file per device: {files:?}");
    let saved = std::fs::read(&files[0]).unwrap();
    // VkPipelineCacheHeaderVersionOne: 32 bytes, version 1.
    assert!(saved.len() >= 32, "{} bytes", saved.len());
    assert_eq!(&saved[0..8], &[32, 0, 0, 0, 1, 0, 0, 0]);

    let out = lensray_cached(&args, dir.path(), cache.path());
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stderr(&out).contains("notice"), "{}", stderr(&out));

    std::fs::write(&files[0], b"not a pipeline cache").unwrap();
    let out = lensray_cached(&args, dir.path(), cache.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    assert_eq!(
        err.lines().filter(|l| l.contains("notice")).count(),
        1,
        "{err}"
    );
    assert!(err.contains("ignoring the pipeline cache"), "{err}");
    assert_eq!(
        std::fs::read(&files[0]).unwrap(),
        saved,
        "replaced by the device's"
    );
}
