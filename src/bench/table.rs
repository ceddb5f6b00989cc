//! The bench's report as text: a few lines on what was measured, then one row per path and
//! point.

use std::fmt::Write;

use super::options::SweepKind;
use super::report::BenchReport;
use crate::paths::Clock;

pub fn render(report: &BenchReport) -> String {
    let mut out = String::new();
    let s = &report.settings;
    let _ = writeln!(
        out,
        "bench: {} ({} triangles), {}x{} px, {} spp, {:?} shading, aperture radius {} focused at {}, {} sampler, seed {}, median of {} run(s) after a warm-up{}",
        report.scene.name,
        report.scene.triangles,
        s.width,
        s.height,
        s.spp,
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

    let swept = match report.sweep {
        None | Some(SweepKind::Spp) => "spp",
        Some(SweepKind::Resolution) => "size",
        Some(SweepKind::Triangles) => "triangles",
        Some(SweepKind::Aperture) => "aperture",
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
            let t = m.trace_seconds;
            let unit = Unit::for_seconds(t.median);
            let clock = match m.clock {
                Clock::GpuTimestamps => " gpu",
                Clock::WallClock => "",
            };
            rows.push([
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
            ]);
        }
    }
    let widths: Vec<usize> = (0..rows[0].len())
        .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
        .collect();
    for row in &rows {
        let line: Vec<String> = row
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, w))| {
                if c < 2 {
                    format!("{cell:<w$}")
                } else {
                    format!("{cell:>w$}")
                }
            })
            .collect();
        let _ = writeln!(out, "{}", line.join("  ").trim_end());
    }
    let _ = writeln!(
        out,
        "time: tracing only, by GPU timestamps (gpu) or the CPU's clock; wall: the whole render call. vs cpu: the CPU path's time over the path's (higher is faster). PSNR: peak 1."
    );
    if report.sweep == Some(SweepKind::Aperture) {
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
    out
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
