//! `--noise-threshold` (adaptive sampling, docs/adaptive.md) as a user runs it: the same
//! arguments give the same file, a scene file's `[render] noise_threshold` the same image as
//! the flag, a cap at the minimum is the uniform render, the summary line counts the samples,
//! the traced GPU paths take the CPU's samples, and the raster and hybrid paths refuse it in
//! one line.

use std::path::Path;

use crate::gpu_support::{compare, skip_or_fail};
use crate::{lensray, read_exr, stderr};

/// 48 x 32 pixels of the spheres scene, lit, on the CPU path.
fn render(dir: &Path, out: &str, extra: &[&str]) -> (Vec<u8>, String) {
    render_on("cpu", dir, out, extra).expect("the CPU path renders")
}

/// [`render`] on `path` (a GPU path with validation on); `None` where the GPU command failed
/// on a machine that may skip GPU tests (the skip recorded).
fn render_on(path: &str, dir: &Path, out: &str, extra: &[&str]) -> Option<(Vec<u8>, String)> {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/spheres/spheres.obj");
    let mut args = vec![
        "render",
        "--scene",
        mesh.to_str().unwrap(),
        "--width",
        "48",
        "--height",
        "32",
        "--path",
        path,
        "--out",
        out,
    ];
    if path != "cpu" {
        args.push("--validate");
    }
    args.extend_from_slice(extra);
    let run = lensray(&args, dir);
    if !run.status.success() && path != "cpu" {
        skip_or_fail(&format!("adaptive on {path}"), &stderr(&run));
        return None;
    }
    assert!(run.status.success(), "{args:?}: {}", stderr(&run));
    let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
    Some((std::fs::read(dir.join(out)).unwrap(), stdout))
}

/// The samples the summary line's adaptive line counts.
fn samples_taken(summary: &str) -> u64 {
    let line = summary
        .lines()
        .find(|l| l.contains("adaptive: noise threshold"))
        .unwrap_or_else(|| panic!("no adaptive line: {summary}"));
    let words: Vec<&str> = line.split_whitespace().collect();
    let at = words.iter().position(|w| w.starts_with("samples")).unwrap();
    words[at - 1].parse().unwrap_or_else(|_| panic!("{line}"))
}

#[test]
fn adaptive_renders_are_deterministic_and_count_their_samples() {
    let dir = tempfile::tempdir().unwrap();
    let adaptive = ["--spp", "128", "--noise-threshold", "0.05"];
    let (a, summary) = render(dir.path(), "a.exr", &adaptive);
    let (b, _) = render(dir.path(), "b.exr", &adaptive);
    assert!(a == b, "two adaptive renders differ");
    // Every pixel takes the minimum (32 at 0.05) and at most the cap; the flat background
    // stops early.
    let samples = samples_taken(&summary);
    let pixels = 48 * 32;
    assert!(
        (32 * pixels..128 * pixels * 3 / 4).contains(&samples),
        "{samples} samples: {summary}"
    );
}

#[test]
fn the_scene_files_threshold_is_the_flags() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/spheres/spheres.obj");
    let scene = dir.path().join("adaptive.toml");
    let text = format!(
        "mesh = {:?}\n[render]\nnoise_threshold = 0.05\n",
        mesh.to_str().unwrap()
    );
    std::fs::write(&scene, text).unwrap();
    let run = lensray(
        &[
            "render",
            "--scene",
            scene.to_str().unwrap(),
            "--width",
            "48",
            "--height",
            "32",
            "--spp",
            "128",
            "--path",
            "cpu",
            "--out",
            "file.exr",
        ],
        dir.path(),
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let from_file = std::fs::read(dir.path().join("file.exr")).unwrap();
    let (from_flag, _) = render(
        dir.path(),
        "flag.exr",
        &["--spp", "128", "--noise-threshold", "0.05"],
    );
    let (uniform, _) = render(dir.path(), "uniform.exr", &["--spp", "128"]);
    assert!(
        from_file == from_flag,
        "the file's threshold differs from the flag's"
    );
    assert!(from_flag != uniform, "the threshold changed nothing");
}

/// At 0.05 every pixel first takes 32 samples: with a cap of 32 the render is the uniform one.
#[test]
fn a_cap_at_the_minimum_is_the_uniform_render() {
    let dir = tempfile::tempdir().unwrap();
    let (adaptive, _) = render(
        dir.path(),
        "a.exr",
        &["--spp", "32", "--noise-threshold", "0.05"],
    );
    let (uniform, _) = render(dir.path(), "u.exr", &["--spp", "32"]);
    assert!(adaptive == uniform);
}

/// The traced GPU paths follow the CPU's rounds: the same arguments give the same file, the
/// CPU's sample count, and its image within the bounds of the GPU == CPU tests.
#[test]
fn traced_gpu_paths_sample_adaptively_as_the_cpu() {
    let dir = tempfile::tempdir().unwrap();
    let adaptive = ["--spp", "128", "--noise-threshold", "0.05"];
    let (_, cpu_summary) = render(dir.path(), "cpu.exr", &adaptive);
    let cpu_samples = samples_taken(&cpu_summary);
    let cpu = read_exr(&dir.path().join("cpu.exr"));
    for path in ["software", "rayquery"] {
        let (out, again) = (format!("{path}.exr"), format!("{path}-again.exr"));
        let Some((a, summary)) = render_on(path, dir.path(), &out, &adaptive) else {
            return;
        };
        let Some((b, _)) = render_on(path, dir.path(), &again, &adaptive) else {
            return;
        };
        assert!(a == b, "{path}: two adaptive renders differ");
        let samples = samples_taken(&summary);
        assert_eq!(samples, cpu_samples, "{path}: {summary}");
        let diff = compare(&read_exr(&dir.path().join(&out)), &cpu, 1.0 / 255.0);
        println!("{path}: {samples} samples as the CPU; {diff:?}");
        assert!(
            diff.within >= 0.999 && diff.mean_abs < 1e-3,
            "{path}: {diff:?}"
        );
    }
}

/// Through a real, dispersive lens (the d line and the checked wavelengths, real_lens.glsl) the
/// GPU's rounds take the CPU's samples too.
#[test]
fn a_real_lens_samples_adaptively_on_the_gpu_as_on_the_cpu() {
    let dir = tempfile::tempdir().unwrap();
    let adaptive = [
        "--spp",
        "64",
        "--noise-threshold",
        "0.1",
        "--lens",
        "double-gauss-50",
        "--f-number",
        "2",
    ];
    let (_, cpu_summary) = render(dir.path(), "cpu.exr", &adaptive);
    let Some((_, summary)) = render_on("software", dir.path(), "gpu.exr", &adaptive) else {
        return;
    };
    assert_eq!(
        samples_taken(&summary),
        samples_taken(&cpu_summary),
        "{summary}"
    );
    let cpu = read_exr(&dir.path().join("cpu.exr"));
    let diff = compare(&read_exr(&dir.path().join("gpu.exr")), &cpu, 1.0 / 255.0);
    println!("real lens: {diff:?}");
    assert!(diff.within >= 0.999 && diff.mean_abs < 1e-3, "{diff:?}");
}

#[test]
fn raster_and_hybrid_refuse_adaptive_sampling_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for path in ["raster", "hybrid"] {
        let run = lensray(
            &[
                "render",
                "--path",
                path,
                "--noise-threshold",
                "0.01",
                "--out",
                "x.png",
            ],
            dir.path(),
        );
        let err = stderr(&run);
        assert!(!run.status.success(), "{path} accepted it");
        assert_eq!(err.trim().lines().count(), 1, "{path}: {err}");
        assert!(err.contains("does not sample adaptively"), "{path}: {err}");
        assert!(!dir.path().join("x.png").exists());
    }
}

/// `lensray bench --noise-threshold`: the paths that sample adaptively run it (the others are
/// left out with a notice, or refused in one line when named) against the uniform reference,
/// and the traced GPU paths measure the CPU's error: they take its samples.
#[test]
fn the_bench_samples_adaptively_on_the_paths_that_can() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec![
        "bench",
        "--width",
        "32",
        "--height",
        "24",
        "--spp",
        "32",
        "--noise-threshold",
        "0.1",
        "--repeat",
        "1",
        "--reference-spp",
        "128",
        "--no-cache",
    ];
    let refused = lensray(
        &[args.as_slice(), &["--paths", "raster"]].concat(),
        dir.path(),
    );
    let err = stderr(&refused);
    assert!(!refused.status.success(), "raster accepted it");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("does not sample adaptively"), "{err}");
    args.extend(["--device", "auto", "--validate", "--json", "bench.json"]);
    let run = lensray(&args, dir.path());
    if !run.status.success() {
        skip_or_fail("the_bench_samples_adaptively", &stderr(&run));
        return;
    }
    assert!(
        stderr(&run).contains("leaving out hybrid and raster"),
        "{}",
        stderr(&run)
    );
    let bytes = std::fs::read(dir.path().join("bench.json")).unwrap();
    let json: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(json["settings"]["noise_threshold"], 0.1, "{json}");
    let results = json["points"][0]["results"].as_array().unwrap();
    let rmse = |path: &str| {
        let m = results.iter().find(|m| m["path"] == path);
        m.map(|m| m["rmse"].as_f64().unwrap())
    };
    let cpu = rmse("cpu").expect("the CPU path runs");
    for path in ["software", "rayquery"] {
        let gpu = rmse(path).unwrap_or_else(|| panic!("{path} did not run: {json}"));
        assert!(
            (gpu / cpu - 1.0).abs() < 0.01,
            "{path}: RMSE {gpu}, CPU's {cpu}"
        );
    }
    for path in ["hybrid", "raster"] {
        assert!(rmse(path).is_none(), "{path} ran: {json}");
    }
}
