//! Choosing the device: `--device gpu`, `auto` without a Vulkan device or validation layer,
//! `--gpu`, the benches' device handling, and the devices `info` lists.

use std::path::Path;
use std::process::{Command, Output};

use crate::gpu_support::{may_skip, record_skip, skip_or_fail};
use crate::{lensray, render_args, stderr};

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

/// `--path rtpipeline` on a device without the ray-tracing pipeline (hidden, as on a GPU without
/// ray tracing) is one line that names the extension, and a non-zero exit.
#[test]
fn rtpipeline_without_the_extension_is_one_clear_line() {
    let test = "rtpipeline_without_the_extension_is_one_clear_line";
    let dir = tempfile::tempdir().unwrap();
    let mut args = render_args(&["--path", "rtpipeline", "--hide-ray-query", "--out", "r.png"]);
    args[2] = "gpu";
    let out = lensray(&args, dir.path());
    let err = stderr(&out);
    assert!(
        !out.status.success(),
        "accepted without the extension: {err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!dir.path().join("r.png").exists());
    if !err.contains("VK_KHR_ray_tracing_pipeline") {
        // No Vulkan device at all: the line says that instead.
        skip_or_fail(test, &err);
        return;
    }
    assert!(err.contains("--path rtpipeline"), "{err}");
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

/// `info`'s list of the Vulkan devices (lensray-vulkan's tests check the reports themselves):
/// a ray-query device, by name, with its ray queries and every path it runs.
#[test]
fn info_lists_a_ray_query_device() {
    let test = "info_lists_a_ray_query_device";
    let devices = match lensray_vulkan::list_devices() {
        Ok(d) => d,
        Err(e) if may_skip(&e) => {
            record_skip(test, &e.to_string());
            return;
        }
        Err(e) => panic!("list_devices: {e}"),
    };
    let Some(usable) = devices.iter().find(|d| d.ray_query) else {
        if std::env::var("LENSRAY_SKIP_GPU_TESTS").as_deref() == Ok("1") {
            record_skip(test, "no Vulkan device with ray queries");
            return;
        }
        panic!("no ray-query device in {devices:#?}");
    };
    let text = lensray::cli::info::format_devices(&devices, |_| None);
    let (rt_pipeline, paths) = if usable.rt_pipeline {
        ("rt pipeline        yes", "rayquery, rtpipeline, software")
    } else {
        ("rt pipeline        no: missing", "rayquery, software")
    };
    assert!(
        text.contains(&usable.name)
            && text.contains("ray queries        yes")
            && text.contains(rt_pipeline)
            && text.contains(&format!(
                "paths              {paths}, hybrid, raster (tracing with the faster of rayquery and software, timed at their first render), cpu"
            )),
        "{text}"
    );
    let calibrated =
        lensray::cli::info::format_devices(&devices, |_| Some(lensray_vulkan::Traversal::Software));
    assert!(
        calibrated.contains("raster (tracing with software: this device's calibration)"),
        "{calibrated}"
    );
}
