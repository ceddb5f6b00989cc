//! The bench's report as text: a few lines on what was measured, then one row per path and
//! point.

use std::fmt::Write;

use super::options::SweepKind;
use super::report::{BenchReport, PointReport};
use super::runs::Measurement;
use crate::paths::Clock;

/// The report as text: the header, the references and focus, the results table, then the
/// sweep's own section.
pub fn render(report: &BenchReport) -> String {
    let mut out = String::new();
    header(&mut out, report);
    references(&mut out, report);
    results(&mut out, report);
    if report.sweep == Some(SweepKind::Aperture) {
        aperture_section(&mut out, report);
    }
    if report.sweep == Some(SweepKind::Lens) {
        lens_section(&mut out, report);
    }
    if report.sweep == Some(SweepKind::Movements) {
        movements_section(&mut out, report);
    }
    flare_section(&mut out, report);
    out
}

/// `--flare`, `--starburst`: each path's time for the lens's own light after its render (its
/// ghosts traced on its device), against the render's.
fn flare_section(out: &mut String, report: &BenchReport) {
    let flared: Vec<&Measurement> = report
        .points
        .iter()
        .flat_map(|p| &p.results)
        .filter(|m| m.flare_vs_render.is_some())
        .collect();
    if flared.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "flare (the lens's own light after each render, median of the runs):"
    );
    let mut rows = vec![["path", "render", "flare", "flare / render"].map(String::from)];
    for m in flared {
        let (render, flare) = (m.wall_seconds.median, m.phases.flare_seconds);
        rows.push([
            m.path.to_string(),
            Unit::for_seconds(render).show(render, true),
            Unit::for_seconds(flare).show(flare, true),
            format!("{:.3}x", m.flare_vs_render.unwrap_or(f64::NAN)),
        ]);
    }
    write_rows(out, &rows, 1, "  ");
}

/// What was measured: the shot and the runs, the machine, each path's device.
fn header(out: &mut String, report: &BenchReport) {
    let s = &report.settings;
    let _ = writeln!(
        out,
        "bench: {} ({} triangles), {}x{} px, {} spp{}, {:?} shading, aperture radius {} focused at {}, {} sampler, seed {}, median of {} run(s) after a warm-up{}",
        report.scene.name,
        report.scene.triangles,
        s.width,
        s.height,
        s.spp,
        match s.noise_threshold {
            Some(threshold) => format!(" (its cap: adaptive, noise threshold {threshold})"),
            None => String::new(),
        },
        s.shading,
        s.aperture_radius,
        s.focus_distance,
        s.sampler.name(),
        s.seed,
        s.repeat,
        match report.sweep {
            Some(sweep) => format!(", sweep of {}", sweep.name()),
            None => String::new(),
        }
    );
    let _ = writeln!(
        out,
        "machine: {}, {} threads, {} ({})",
        report.machine.cpu, report.machine.threads, report.machine.os, report.machine.arch
    );
    for p in &report.paths {
        let _ = writeln!(out, "path {}: {}", p.path, p.device);
    }
    if let Some(load) = &report.scene.load {
        let time = |s: f64| Unit::for_seconds(s).show(s, true);
        let textures = match load.textures {
            0 => "no textures".to_string(),
            n => format!(
                "{n} texture(s), {} MiB in all levels",
                mib(load.texture_bytes)
            ),
        };
        let _ = writeln!(
            out,
            "load: {} (parse {}, texture decode {}, mips {}), {textures}; acceleration structures: the build column",
            time(load.seconds),
            time(load.parse_seconds),
            time(load.texture_decode_seconds),
            time(load.texture_mips_seconds),
        );
    }
}

/// Per point with a reference not shown yet: how the reference was obtained and its noise, and
/// how much of the shot is in focus.
fn references(out: &mut String, report: &BenchReport) {
    let mut seen_files = Vec::new();
    for point in &report.points {
        let r = &point.reference;
        if r.file.is_some() && seen_files.contains(&r.file) {
            continue;
        }
        seen_files.push(r.file.clone());
        let how = match (&r.file, r.cached, r.render_seconds) {
            (Some(file), true, _) => format!("cached ({})", file.display()),
            (Some(file), false, Some(s)) => format!(
                "rendered in {}, now cached ({})",
                Unit::for_seconds(s).show(s, true),
                file.display()
            ),
            (None, _, Some(s)) => format!(
                "rendered in {}, not cached",
                Unit::for_seconds(s).show(s, true)
            ),
            _ => "rendered".into(),
        };
        let _ = writeln!(
            out,
            "reference {}x{}: CPU at {} spp, seed {}, {how}; its own noise: RMSE ~{:.2e}",
            point.width, point.height, r.spp, r.seed, r.noise_rmse
        );
        let f = &point.focus;
        let _ = writeln!(
            out,
            "focus {}x{}: {:.1} % of the pixels in focus (CoC < 0.5 px), {:.1} % background; CoC of the surfaces: mean {:.1} px, largest {:.1} px",
            point.width,
            point.height,
            100.0 * f.in_focus_fraction,
            100.0 * f.background_fraction,
            f.mean_coc_pixels,
            f.largest_coc_pixels
        );
    }
}

/// The results table, one row per point and path, and its legend.
fn results(out: &mut String, report: &BenchReport) {
    let swept = match report.sweep {
        None | Some(SweepKind::Spp) => "spp",
        Some(SweepKind::Resolution) => "size",
        Some(SweepKind::Triangles) => "triangles",
        Some(SweepKind::Aperture) => "aperture",
        Some(SweepKind::Lens) => "lens",
        Some(SweepKind::Movements) => "shot",
    };
    let mut rows = vec![[
        swept,
        "path",
        "time (min-max)",
        "wall",
        "Mrays/s",
        "rays",
        "device MiB",
        "accel MiB",
        "build",
        "RMSE",
        "PSNR dB",
        "vs cpu",
    ]
    .map(String::from)];
    for point in &report.points {
        for m in &point.results {
            rows.push(result_row(report, point, m));
        }
    }
    write_rows(out, &rows, 2, "");
    let _ = writeln!(
        out,
        "time: tracing only, by GPU timestamps (gpu) or the CPU's clock; wall: the whole render call. vs cpu: the CPU path's time over the path's (higher is faster). PSNR: peak 1."
    );
    let startups: Vec<String> = report
        .paths
        .iter()
        .map(|p| {
            let s = p.startup;
            format!(
                "{} {:.2} s (device and pipelines {:.2} s, scene {:.3} s)",
                p.path,
                s.device_seconds + s.scene_seconds,
                s.device_seconds,
                s.scene_seconds
            )
        })
        .collect();
    let _ = writeln!(out, "start-up: {}.", startups.join("; "));
}

/// The results table's row of one path at one point.
fn result_row(report: &BenchReport, point: &PointReport, m: &Measurement) -> [String; 12] {
    let t = m.trace_seconds;
    let unit = Unit::for_seconds(t.median);
    let clock = match m.clock {
        Clock::GpuTimestamps => " gpu",
        Clock::WallClock => "",
    };
    [
        point.swept_label(report.sweep),
        m.path.to_string(),
        format!(
            "{}{clock} ({}-{})",
            unit.show(t.median, true),
            unit.show(t.min, false),
            unit.show(t.max, false)
        ),
        Unit::for_seconds(m.wall_seconds.median).show(m.wall_seconds.median, true),
        match m.aov_passes_per_second {
            Some(passes) => format!("{passes:.1} passes/s"),
            None => format!("{:.2}", m.rays_per_second / 1e6),
        },
        m.rays.to_string(),
        mib(m.peak_device_bytes),
        mib(m.accel_bytes),
        Unit::for_seconds(m.build_seconds).show(m.build_seconds, true),
        format!("{:.3e}", m.rmse),
        format!("{:.2}", m.psnr_db),
        m.speedup_vs_cpu
            .map_or_else(|| "-".into(), |x| format!("{x:.2}x")),
    ]
}

/// The aperture sweep: per path, each aperture's time over the round aperture's.
fn aperture_section(out: &mut String, report: &BenchReport) {
    let _ = writeln!(
        out,
        "aperture cost (median time over the round aperture's, same path, measured in turns):"
    );
    for p in &report.paths {
        let costs: Vec<String> = report
            .points
            .iter()
            .skip(1)
            .filter_map(|point| {
                let m = point.results.iter().find(|m| m.path == p.path)?;
                let cost = m.cost_vs_round?;
                Some(format!("{} {cost:.3}x", point.swept_label(report.sweep)))
            })
            .collect();
        let _ = writeln!(out, "  {}: {}", p.path, costs.join(", "));
    }
}

/// The lens sweep: each lens's pass shares, then per path its camera rays per second and its
/// costs against the thin model.
fn lens_section(out: &mut String, report: &BenchReport) {
    let _ = writeln!(
        out,
        "camera rays (counted on the CPU with the paths' samples; unlit: the paths' own rays): share of camera samples that reach the scene, over the image and at its centre ({}x{} lens grid per central pixel); CPU time to make them all (no scene traced, all threads), and per sample on one thread by piece (ns; camera ray: the whole, sampler excluded, one at a time; in packets: the same, 16 rays traced together as the CPU path does):",
        super::lens::CENTRE_GRID,
        super::lens::CENTRE_GRID
    );
    let mut rows = vec![[
        "lens",
        "f/",
        "samples",
        "camera rays",
        "pass (image)",
        "pass (centre)",
        "CPU ray making",
        "sampler ns",
        "pupil ns",
        "lens trace ns",
        "camera ray ns",
        "in packets ns",
    ]
    .map(String::from)];
    for point in &report.points {
        let Some(l) = &point.lens else { continue };
        rows.push([
            point.swept_label(report.sweep),
            format!("{:.2}", l.f_number),
            l.camera_samples.to_string(),
            l.camera_rays.to_string(),
            format!("{:.1} %", 100.0 * l.pass_share),
            format!("{:.1} %", 100.0 * l.centre_pass_share),
            Unit::for_seconds(l.camera_ray_seconds).show(l.camera_ray_seconds, true),
            format!("{:.1}", l.cpu_pieces.sampler_ns),
            format!("{:.1}", l.cpu_pieces.pupil_ns),
            format!("{:.1}", l.cpu_pieces.lens_trace_ns),
            format!("{:.1}", l.cpu_pieces.camera_ray_ns),
            format!("{:.1}", l.cpu_pieces.packet_ns),
        ]);
    }
    write_rows(out, &rows, 1, "  ");
    let _ = writeln!(
        out,
        "cost against the thin lens (same path, measured in turns; per camera ray that reaches the scene, target <= 2x):"
    );
    let mut rows = vec![[
        "lens",
        "path",
        "time",
        "Mcamera rays/s",
        "time vs thin",
        "per camera ray vs thin",
    ]
    .map(String::from)];
    for p in &report.paths {
        for point in &report.points {
            let Some(m) = point.results.iter().find(|m| m.path == p.path) else {
                continue;
            };
            let t = m.trace_seconds.median;
            let ratio = |x: Option<f64>| x.map_or_else(|| "-".into(), |x| format!("{x:.2}x"));
            rows.push([
                point.swept_label(report.sweep),
                m.path.to_string(),
                Unit::for_seconds(t).show(t, true),
                m.camera_rays_per_second
                    .map_or_else(|| "-".into(), |r| format!("{:.2}", r / 1e6)),
                ratio(m.cost_vs_thin),
                ratio(m.cost_per_camera_ray_vs_thin),
            ]);
        }
    }
    write_rows(out, &rows, 2, "  ");
}

/// The movements sweep: per path and moved shot, its time per sample against the plain shot's,
/// then the same ratio round by round (each round renders both, a few seconds apart): its
/// median and range show how much a busy machine moved it.
fn movements_section(out: &mut String, report: &BenchReport) {
    let _ = writeln!(
        out,
        "movements cost (median time per sample over the plain shot's, same path, measured in turns; target <= 1.05x):"
    );
    let Some(plain) = report.points.first() else {
        return;
    };
    let per_sample = |point: &PointReport, seconds: f64| {
        let samples = f64::from(point.width) * f64::from(point.height) * f64::from(point.spp);
        format!("{:.1}", seconds / samples.max(1.0) * 1e9)
    };
    let mut rows = vec![[
        "path",
        "shot",
        "plain: time",
        "ns/sample",
        "shot: time",
        "ns/sample",
        "vs plain",
        "rounds: median (min-max)",
        "target",
    ]
    .map(String::from)];
    for p in &report.paths {
        let Some(base) = plain.results.iter().find(|m| m.path == p.path) else {
            continue;
        };
        for point in report.points.iter().skip(1) {
            let Some(m) = point.results.iter().find(|m| m.path == p.path) else {
                continue;
            };
            let (t0, t) = (base.trace_seconds.median, m.trace_seconds.median);
            let ratio = m.time_per_sample_vs_plain.unwrap_or(f64::NAN);
            let rounds: Vec<f64> = m
                .runs
                .iter()
                .zip(&base.runs)
                .map(|(r, r0)| r.trace_seconds / r0.trace_seconds.max(1e-12))
                .collect();
            let (lo, hi) = lensray_core::stats::range(&rounds);
            let mid = lensray_core::stats::median(&rounds);
            rows.push([
                p.path.to_string(),
                point.swept_label(report.sweep),
                Unit::for_seconds(t0).show(t0, true),
                per_sample(plain, t0),
                Unit::for_seconds(t).show(t, true),
                per_sample(point, t),
                format!("{ratio:.3}x"),
                format!("{mid:.3} ({lo:.3}-{hi:.3})"),
                if ratio <= 1.05 { "met" } else { "missed" }.into(),
            ]);
        }
    }
    write_rows(out, &rows, 2, "  ");
}

/// Rows aligned in columns, each line after `indent`: the first `left` columns to the left, the
/// others to the right.
fn write_rows<const N: usize>(out: &mut String, rows: &[[String; N]], left: usize, indent: &str) {
    let widths: Vec<usize> = (0..N)
        .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
        .collect();
    for row in rows {
        let line: Vec<String> = row
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, w))| {
                if c < left {
                    format!("{cell:<w$}")
                } else {
                    format!("{cell:>w$}")
                }
            })
            .collect();
        let _ = writeln!(out, "{indent}{}", line.join("  ").trim_end());
    }
}

fn mib(bytes: u64) -> String {
    if bytes == 0 {
        "-".into()
    } else {
        format!("{:.1}", bytes as f64 / (1024.0 * 1024.0))
    }
}

/// Seconds shown in s, ms or µs, chosen once for a median and its spread.
#[derive(Clone, Copy)]
struct Unit {
    scale: f64,
    name: &'static str,
}

impl Unit {
    fn for_seconds(s: f64) -> Self {
        match s {
            s if s >= 1.0 => Unit {
                scale: 1.0,
                name: "s",
            },
            s if s >= 1e-3 => Unit {
                scale: 1e3,
                name: "ms",
            },
            _ => Unit {
                scale: 1e6,
                name: "µs",
            },
        }
    }

    fn show(self, seconds: f64, with_unit: bool) -> String {
        let v = seconds * self.scale;
        let digits = if v >= 100.0 {
            0
        } else if v >= 10.0 {
            1
        } else {
            2
        };
        if with_unit {
            format!("{v:.digits$} {}", self.name)
        } else {
            format!("{v:.digits$}")
        }
    }
}
