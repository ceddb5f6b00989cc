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

/// A device's first use (no pipeline cache file of this build yet) says in one line that the
/// driver compiles the shaders, and the summary counts that time apart from the render's time
/// and rays per second; the next run says nothing, and neither does `--progress none`.
#[test]
fn first_use_of_a_device_says_it_compiles_shaders() {
    let test = "first_use_of_a_device_says_it_compiles_shaders";
    let dir = tempfile::tempdir().unwrap();
    let (cache, mesa_cache) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let args = [
        "render", "--path", "software", "--width", "160", "--height", "120", "--spp", "8", "--out",
        "a.png",
    ];
    let run = |extra: &[&str], cache: &Path| {
        Command::new(env!("CARGO_BIN_EXE_lensray"))
            .args(args.iter().chain(extra))
            .current_dir(dir.path())
            .env("LENSRAY_CACHE_DIR", cache)
            // Mesa's own shader cache, empty: lavapipe compiles as on a first install.
            .env("MESA_SHADER_CACHE_DIR", mesa_cache.path())
            .output()
            .expect("run lensray")
    };
    let announced = |out: &Output| {
        stderr(out)
            .lines()
            .filter(|l| l.starts_with("compiling shaders for "))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let first = run(&[], cache.path());
    if !first.status.success() {
        skip_or_fail(test, &stderr(&first));
        return;
    }
    let lines = announced(&first);
    assert_eq!(lines.len(), 1, "{}", stderr(&first));
    assert!(
        lines[0].ends_with("(first use; cached after)"),
        "{}",
        lines[0]
    );
    let summary = String::from_utf8_lossy(&first.stdout).into_owned();
    let rate = |summary: &str| -> f64 {
        let before = summary.rsplit_once(" Mrays/s").expect("a rate").0;
        before
            .rsplit(' ')
            .next()
            .unwrap()
            .parse()
            .expect("a number")
    };
    if lines[0].contains("llvmpipe") {
        // lavapipe compiles for seconds from an empty cache, in the pipeline's first dispatch.
        assert!(summary.contains(" s of it compiling shaders)"), "{summary}");
    }
    let second = run(&[], cache.path());
    assert!(second.status.success(), "{}", stderr(&second));
    assert!(announced(&second).is_empty(), "{}", stderr(&second));
    // The compiler's seconds are not in the rate: the first run's is near the second's (a
    // first dispatch that compiled made it 0.00 Mrays/s).
    let (first_rate, second_rate) = (
        rate(&summary),
        rate(&String::from_utf8_lossy(&second.stdout)),
    );
    assert!(
        first_rate > 0.3 * second_rate,
        "first use {first_rate} Mrays/s, then {second_rate}: {summary}"
    );
    let quiet_cache = tempfile::tempdir().unwrap();
    let quiet = run(&["--progress", "none"], quiet_cache.path());
    assert!(quiet.status.success(), "{}", stderr(&quiet));
    assert!(announced(&quiet).is_empty(), "{}", stderr(&quiet));
}
