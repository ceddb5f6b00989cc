//! Timing the paths at one configuration: a warm-up render each (pipelines compiled, BVH paged
//! in, thread pool started), then N rounds of timed renders, one per path; each path's median
//! and spread, and the error of its image against the reference.

use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;

use crate::paths::{Clock, PathKind, Phases, RenderPath};
use lensray_core::camera::flare::Flare;
use lensray_core::film::compare::rmse;
use lensray_core::film::Image;
use lensray_core::scene::Light;
use lensray_core::settings::{RenderSettings, Shot};
use lensray_core::stats::{median, range};

/// One timed render.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Run {
    /// Trace time as the path measures it (GPU timestamps on GPU paths).
    pub trace_seconds: f64,
    /// Host wall clock around the whole render call (uploads and readback included).
    pub wall_seconds: f64,
    pub rays: u64,
    /// What the render asked of the device (0 on the CPU): queue submissions, host waits on
    /// the device, bytes read back.
    pub submits: u64,
    pub cpu_waits: u64,
    pub readback_bytes: u64,
    /// The render's phases: tracing, beyond tracing (and per sample pass), read-back.
    pub phases: Phases,
}

/// Median and extremes of repeated measurements.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    pub fn of(values: &[f64]) -> Self {
        let (min, max) = range(values);
        Self {
            median: median(values),
            min,
            max,
        }
    }
}

/// One path at one configuration.
#[derive(Clone, Debug, Serialize)]
pub struct Measurement {
    pub path: PathKind,
    pub device: String,
    /// How `trace_seconds` was measured.
    pub clock: Clock,
    pub runs: Vec<Run>,
    pub trace_seconds: Spread,
    pub wall_seconds: Spread,
    /// Rays of one render (camera and shadow rays).
    pub rays: u64,
    /// Of one render (the last): queue submissions, host waits on the device, bytes read back
    /// (0 on the CPU).
    pub submits: u64,
    pub cpu_waits: u64,
    pub readback_bytes: u64,
    /// `rays` over the median trace time.
    pub rays_per_second: f64,
    /// The median of each phase of the runs (`beyond_tracing_seconds` over `passes`: the
    /// host's time per sample pass beyond tracing).
    pub phases: Phases,
    /// AOV benches: images (GPU: G-buffer passes) per second at the median time.
    pub aov_passes_per_second: Option<f64>,
    /// Device memory held at the peak so far (0 for the CPU).
    pub peak_device_bytes: u64,
    /// The acceleration structure's size (device memory on GPU paths, host memory on the CPU).
    pub accel_bytes: u64,
    /// Time to build the scene's acceleration structure when the path loaded it.
    pub build_seconds: f64,
    /// Against the reference, over every pixel and channel.
    pub rmse: f64,
    /// 20 log10(1 / RMSE): the peak is 1, the brightest diffuse colour, in linear units.
    pub psnr_db: f64,
    /// How many times faster than the CPU path at the same point (median trace times), when
    /// the CPU path was measured there.
    pub speedup_vs_cpu: Option<f64>,
    /// The aperture sweep: this path's median time over its median time with the round
    /// aperture (the shape's cost; 1 for the round point).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cost_vs_round: Option<f64>,
    /// The lens sweep: camera rays that reach the scene (`LensPoint::camera_rays`) over the
    /// median trace time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camera_rays_per_second: Option<f64>,
    /// The lens sweep: this path's median time over its median time with the lens's
    /// first-order thin lens (1 for the thin point).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cost_vs_thin: Option<f64>,
    /// The lens sweep: time per camera ray that reaches the scene over the same with the
    /// thin lens, same path (the target: at most 2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cost_per_camera_ray_vs_thin: Option<f64>,
    /// The movements sweep: this path's median time per sample over the same at the plain
    /// point (the points share size and spp, so their time ratio; 1 for the plain point; the
    /// target: at most 1.05).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_per_sample_vs_plain: Option<f64>,
    /// `--flare`, `--starburst`: the median time the lens's own light took after each render
    /// (`phases.flare_seconds`) over the render's median wall time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flare_vs_render: Option<f64>,
}

/// What each timed render draws after it (`--flare`, `--starburst` on the bench): the flare,
/// the exposure's scale and the scene's lights.
pub struct BenchFlare<'a> {
    pub flare: &'a Flare,
    pub exposure: f32,
    pub lights: &'a [Light],
}

pub fn psnr_db(rmse: f64) -> f64 {
    -20.0 * rmse.log10()
}

/// Each path's warm-up render, then `repeat` rounds in which every path renders `shot` once,
/// timed (samples 0..spp into a fresh accumulation each time). Interleaved rather than
/// path after path: a slow phase of a shared machine (minutes long here) then slows every path
/// alike instead of one, and the ratios hold. The error is that of each path's last image
/// (every run gives the same).
pub fn measure_interleaved(
    paths: &mut [Box<dyn RenderPath>],
    shot: &Shot,
    repeat: usize,
    (reference, flare): (&Image, Option<&BenchFlare>),
) -> Result<Vec<Measurement>> {
    let mut points = measure_points_flared(paths, &[(shot, reference)], repeat, flare)?;
    Ok(points.remove(0))
}

/// `measure_interleaved` over several points (each a shot and its reference) whose ratios
/// matter (the aperture sweep: each shape against the round one): every round renders every
/// point with every path, so a slow phase of the machine slows them alike. Per point, each
/// path's measurement.
pub fn measure_points_interleaved(
    paths: &mut [Box<dyn RenderPath>],
    points: &[(&Shot, &Image)],
    repeat: usize,
) -> Result<Vec<Vec<Measurement>>> {
    measure_points_flared(paths, points, repeat, None)
}

/// [`measure_points_interleaved`], each timed render followed by `flare` (timed apart).
fn measure_points_flared(
    paths: &mut [Box<dyn RenderPath>],
    points: &[(&Shot, &Image)],
    repeat: usize,
    flare: Option<&BenchFlare>,
) -> Result<Vec<Vec<Measurement>>> {
    for &(shot, _) in points {
        for path in paths.iter_mut() {
            path.render(shot, &mut |_, _| {})
                .with_context(|| format!("--paths {}", path.kind()))?;
        }
    }
    let mut runs = vec![vec![Vec::with_capacity(repeat); paths.len()]; points.len()];
    let mut images = vec![vec![None; paths.len()]; points.len()];
    for _ in 0..repeat {
        for (&(shot, _), (runs, images)) in points.iter().zip(runs.iter_mut().zip(&mut images)) {
            for ((path, runs), image) in paths.iter_mut().zip(runs).zip(images) {
                let (run, rendered) = timed_render(path.as_mut(), shot, flare)
                    .with_context(|| format!("--paths {}", path.kind()))?;
                runs.push(run);
                *image = Some(rendered);
            }
        }
    }
    points
        .iter()
        .zip(runs.into_iter().zip(images))
        .map(|(&(shot, reference), (runs, images))| {
            paths
                .iter()
                .zip(runs)
                .zip(images)
                .map(|((path, runs), image)| {
                    let image = image.expect("at least one run");
                    Ok(measurement(
                        path.as_ref(),
                        &shot.render,
                        runs,
                        &image,
                        reference,
                    ))
                })
                .collect()
        })
        .collect()
}

/// `path`'s render of `shot`, timed, then `flare` drawn on it, timed apart.
pub fn timed_render(
    path: &mut dyn RenderPath,
    shot: &Shot,
    flare: Option<&BenchFlare>,
) -> Result<(Run, Image)> {
    let before = path.report();
    let start = Instant::now();
    let mut image = path.render(shot, &mut |_, _| {})?;
    let wall_seconds = start.elapsed().as_secs_f64();
    let mut flare_seconds = 0.0;
    if let Some(f) = flare {
        let flare_start = Instant::now();
        f.flare.forget_patterns();
        crate::lens_flare::add(f.flare, (&mut image, f.exposure), shot, f.lights, path)?;
        flare_seconds = flare_start.elapsed().as_secs_f64();
    }
    let done = path.report().since(&before);
    // An AOV is one pass (GPU: the raster G-buffer), timed as such; no rays on the GPU.
    let aov = shot.render.shading.is_aov();
    let passes = if aov { 1 } else { shot.render.spp };
    let phases = Phases {
        flare_seconds,
        ..Phases::of_render(wall_seconds, &done, passes, aov)
    };
    let run = Run {
        trace_seconds: phases.tracing_seconds,
        wall_seconds,
        rays: done.rays,
        submits: done.submits,
        cpu_waits: done.cpu_waits,
        readback_bytes: done.readback_bytes,
        phases,
    };
    Ok((run, image))
}

fn measurement(
    path: &dyn RenderPath,
    settings: &RenderSettings,
    runs: Vec<Run>,
    image: &Image,
    reference: &Image,
) -> Measurement {
    let report = path.report();
    let trace: Vec<f64> = runs.iter().map(|r| r.trace_seconds).collect();
    let wall: Vec<f64> = runs.iter().map(|r| r.wall_seconds).collect();
    let trace_seconds = Spread::of(&trace);
    let rays = runs.last().map_or(0, |r| r.rays);
    let last = runs.last().copied();
    let error = rmse(image, reference);
    Measurement {
        path: path.kind(),
        device: path.device_name(),
        clock: report.clock,
        trace_seconds,
        wall_seconds: Spread::of(&wall),
        rays,
        submits: last.map_or(0, |r| r.submits),
        cpu_waits: last.map_or(0, |r| r.cpu_waits),
        readback_bytes: last.map_or(0, |r| r.readback_bytes),
        rays_per_second: rays as f64 / trace_seconds.median.max(1e-12),
        phases: median_phases(&runs),
        aov_passes_per_second: settings
            .shading
            .is_aov()
            .then(|| 1.0 / trace_seconds.median.max(1e-12)),
        peak_device_bytes: report.peak_device_bytes,
        accel_bytes: report.accel_bytes,
        build_seconds: report.build_seconds,
        rmse: error,
        psnr_db: psnr_db(error),
        speedup_vs_cpu: None,
        cost_vs_round: None,
        camera_rays_per_second: None,
        cost_vs_thin: None,
        cost_per_camera_ray_vs_thin: None,
        time_per_sample_vs_plain: None,
        flare_vs_render: flare_vs_render(&runs),
        runs,
    }
}

/// The median flare time over the median render time, where the runs drew a flare.
fn flare_vs_render(runs: &[Run]) -> Option<f64> {
    let flare = median(
        &runs
            .iter()
            .map(|r| r.phases.flare_seconds)
            .collect::<Vec<_>>(),
    );
    let wall = median(&runs.iter().map(|r| r.wall_seconds).collect::<Vec<_>>());
    (flare > 0.0 && wall > 0.0).then(|| flare / wall)
}

/// Each render phase's median over `runs`.
fn median_phases(runs: &[Run]) -> Phases {
    let of = |phase: fn(&Phases) -> f64| {
        median(&runs.iter().map(|r| phase(&r.phases)).collect::<Vec<_>>())
    };
    Phases {
        device_seconds: of(|p| p.device_seconds),
        instance_seconds: of(|p| p.instance_seconds),
        tracing_seconds: of(|p| p.tracing_seconds),
        beyond_tracing_seconds: of(|p| p.beyond_tracing_seconds),
        passes: runs.first().map_or(0, |r| r.phases.passes),
        submits: runs.last().map_or(0, |r| r.phases.submits),
        readback_seconds: of(|p| p.readback_seconds),
        flare_seconds: of(|p| p.flare_seconds),
        ..Phases::default()
    }
}

/// Gives each measurement, through `set`, its path's median time over the same path's at the
/// first point (the point the others are weighed against: the round aperture, the plain shot).
/// A path the first point lacks gets nothing.
pub fn set_costs_vs_first(points: &mut [Vec<Measurement>], set: fn(&mut Measurement, f64)) {
    let first: Vec<(PathKind, f64)> = points.first().map_or(Vec::new(), |ms| {
        ms.iter()
            .map(|m| (m.path, m.trace_seconds.median))
            .collect()
    });
    for point in points {
        for m in point {
            if let Some(&(_, t)) = first.iter().find(|(p, _)| *p == m.path) {
                set(m, m.trace_seconds.median / t.max(1e-12));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A measurement of `path` whose runs took `seconds`.
    fn measured(path: PathKind, seconds: &[f64]) -> Measurement {
        let runs: Vec<Run> = seconds
            .iter()
            .map(|&s| Run {
                trace_seconds: s,
                wall_seconds: s,
                rays: 1,
                submits: 0,
                cpu_waits: 0,
                readback_bytes: 0,
                phases: Phases::default(),
            })
            .collect();
        Measurement {
            path,
            device: String::new(),
            clock: Clock::WallClock,
            phases: median_phases(&runs),
            trace_seconds: Spread::of(seconds),
            wall_seconds: Spread::of(seconds),
            runs,
            rays: 1,
            submits: 0,
            cpu_waits: 0,
            readback_bytes: 0,
            rays_per_second: 1.0,
            aov_passes_per_second: None,
            peak_device_bytes: 0,
            accel_bytes: 0,
            build_seconds: 0.0,
            rmse: 0.1,
            psnr_db: 20.0,
            speedup_vs_cpu: None,
            cost_vs_round: None,
            camera_rays_per_second: None,
            cost_vs_thin: None,
            cost_per_camera_ray_vs_thin: None,
            time_per_sample_vs_plain: None,
            flare_vs_render: None,
        }
    }

    #[test]
    fn costs_are_medians_over_the_first_points_same_path() {
        let plain = vec![
            measured(PathKind::Cpu, &[2.0, 9.0, 1.0]),
            measured(PathKind::Raster, &[4.0]),
        ];
        // The raster path is listed first here: each is matched by path, not by place.
        let moved = vec![
            measured(PathKind::Raster, &[5.0]),
            measured(PathKind::Cpu, &[2.1, 2.2, 0.5]),
            measured(PathKind::Hybrid, &[1.0]),
        ];
        let mut points = vec![plain, moved];
        set_costs_vs_first(&mut points, |m, c| m.time_per_sample_vs_plain = Some(c));
        let costs: Vec<Vec<Option<f64>>> = points
            .iter()
            .map(|ms| ms.iter().map(|m| m.time_per_sample_vs_plain).collect())
            .collect();
        assert_eq!(costs[0], [Some(1.0), Some(1.0)]);
        // Medians: cpu 2.1 over 2.0, raster 5 over 4; the hybrid has no plain point.
        let cpu = costs[1][1].unwrap();
        assert!((cpu - 1.05).abs() < 1e-12, "{cpu}");
        assert_eq!(costs[1][0], Some(1.25));
        assert_eq!(costs[1][2], None);
    }
}
