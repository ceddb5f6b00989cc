//! What lensray keeps on disk between runs: `auto`'s calibration and the Vulkan pipeline
//! cache.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::gpu_support::skip_or_fail;
use crate::{lensray, stderr};

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
/// costs; `auto` then decides the device from them (saying so), every run alike (on the GPU,
/// `auto` still times its paths on the shot, which a loaded machine may order differently); a
/// corrupt cache file is one notice, and the render goes on.
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
    let on_cpu = |path: &String| path == "cpu";
    assert!(
        chosen.iter().all(|p| on_cpu(p) == on_cpu(&chosen[0])),
        "{chosen:?}"
    );

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
