//! Renders that succeed: image formats, the sampler option, framing a bare OBJ, progress
//! lines, and an interrupted render that leaves nothing behind.

use std::path::PathBuf;
use std::process::Command;

use crate::{lensray, render_args, stderr};

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
        // No tone map: the bytes are the colours' sRGB encoding.
        &render_args(&[
            "--scene",
            "tri.obj",
            "--shading",
            "unlit",
            "--tonemap",
            "none",
            "--out",
            "t.png",
        ]),
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

/// `--timings` names every phase once, in order, and they sum to the total (the total is the
/// command's own clock, read after the others: "other" holds what no phase does); the time
/// beyond tracing is given per sample pass. On the CPU and, where there is one, on a GPU path.
#[test]
fn timings_name_every_phase_and_sum_to_the_total() {
    let phases = [
        "load",
        "device and pipelines",
        "scene upload and acceleration structures",
        "tracing",
        "beyond tracing",
        "read-back",
        "encode and write",
        "other",
        "total",
    ];
    for device in ["cpu", "gpu"] {
        let dir = tempfile::tempdir().unwrap();
        let mut args = render_args(&["--timings", "--spp", "4", "--out", "t.png"]);
        args[2] = device;
        let out = lensray(&args, dir.path());
        if !out.status.success() {
            crate::gpu_support::skip_or_fail("timings_name_every_phase", &stderr(&out));
            continue;
        }
        let text = String::from_utf8_lossy(&out.stdout);
        let lines: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with("timings: "))
            .collect();
        assert_eq!(lines.len(), phases.len(), "{device}: {text}");
        let seconds: Vec<f64> = lines
            .iter()
            .zip(phases)
            .map(|(line, phase)| {
                let rest = line
                    .strip_prefix(&format!("timings: {phase} "))
                    .unwrap_or_else(|| panic!("{device}: '{line}' is not phase '{phase}'"));
                rest.split(' ').next().unwrap().parse().unwrap()
            })
            .collect();
        let (named, total) = (&seconds[..phases.len() - 1], seconds[phases.len() - 1]);
        assert!(named.iter().all(|&s| s >= 0.0), "{device}: {text}");
        let sum: f64 = named.iter().sum();
        assert!(
            total > 0.0 && (sum - total).abs() <= 0.002,
            "{device}: {sum} against {total}: {text}"
        );
        assert!(
            lines[4].contains(" ms per pass, 4 passes"),
            "{device}: {}",
            lines[4]
        );
        // The path's tracing is most of a render of the built-in scene on either device.
        assert!(seconds[3] > 0.0, "{device}: {text}");
    }
}
