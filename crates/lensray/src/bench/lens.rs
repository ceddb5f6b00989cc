//! The lens sweep's own figures: how many camera samples a lens lets through (over the whole
//! shot, with the shot's own samples, and at the image centre over a grid of lens samples),
//! how long the CPU takes to make the shot's camera rays, and each path's cost per camera ray
//! that reaches the scene against the thin lens's.
//!
//! Camera rays are counted here, on the CPU, with `Camera::generate_ray` and the
//! samples the paths draw (same sampler, seed and pixels), so the count does not depend on the
//! shading: the paths' own counters add shadow rays under lit shading. Under unlit shading
//! (the bench's default) each camera ray that reaches the scene is exactly one ray of the
//! paths' counters, and the CPU path's count equals this one.

use std::hint::black_box;
use std::time::Instant;

use glam::{UVec2, Vec2, Vec3};
use rayon::prelude::*;
use serde::Serialize;

use super::runs::Measurement;
use super::sweep::BenchLens;
use crate::paths::PathKind;
use lensray_core::camera::{Camera, RealLens};
use lensray_core::optics::trace::narrow::LensRay;
use lensray_core::reference::PACKET_SIZE;
use lensray_core::sampler::{
    pixel_camera_sample, pixel_sampler, shared_pixel_sampler, CameraSample, PixelSampler,
};
use lensray_core::settings::Shot;
use lensray_core::stats::median;

/// Lens samples a side of the grid drawn at each central pixel.
pub const CENTRE_GRID: u32 = 64;
/// Timed passes over the shot's camera rays (their median is reported).
const CAMERA_RAY_PASSES: usize = 3;

/// What a lens-sweep point is, and how much light its lens lets through.
#[derive(Clone, Debug, Serialize)]
pub struct LensPoint {
    /// The built-in lens's name.
    pub lens: &'static str,
    /// Traced surface by surface, or its first-order thin lens.
    pub model: LensModel,
    /// The real lens's f-number (the thin model has the same: its radius is the entrance
    /// pupil's).
    pub f_number: f64,
    /// Radius of the entrance pupil (the thin model's aperture), world units.
    pub entrance_pupil_radius: f32,
    pub focus_distance: f32,
    /// Camera samples one render draws: width x height x spp.
    pub camera_samples: u64,
    /// Those whose camera ray reaches the scene (the lens blocks the others).
    pub camera_rays: u64,
    /// The share of the camera samples whose d line's ray reaches the scene.
    pub pass_share: f64,
    /// The same at the image centre: the central pixel(s) (1, 2 or 4), each at its centre
    /// with a `CENTRE_GRID` x `CENTRE_GRID` grid of lens samples.
    pub centre_pass_share: f64,
    pub centre_samples: u64,
    /// The CPU's time to make every camera ray of the shot (`generate_ray`, all
    /// threads, no scene traced; median of 3): the lens's part of the CPU path's time.
    pub camera_ray_seconds: f64,
    /// Where the CPU's time per camera sample goes, one thread.
    pub cpu_pieces: CpuPieces,
}

/// The CPU's nanoseconds per camera sample drawn, on one thread, over the samples of every
/// `PIECES_ROW_STRIDE`th row of the shot (medians of 3 passes): the pieces of a camera ray.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CpuPieces {
    /// Samples timed.
    pub samples: u64,
    /// Drawing the sample (film and lens dimensions).
    pub sampler_ns: f64,
    /// Film point and exit-pupil sample (0 for the thin lens).
    pub pupil_ns: f64,
    /// The trace through the lens's surfaces, blocked rays included (0 for the thin lens).
    pub lens_trace_ns: f64,
    /// `generate_ray` as a whole (pupil, trace, weight, to world space).
    pub camera_ray_ns: f64,
    /// What the CPU path runs instead: `RealLens::generate_rays` on packets of `PACKET_SIZE`
    /// samples traced together by lane (film point, pupil, trace and weight, in camera
    /// space). The thin lens's figure is `camera_ray_ns`: its packets are made elsewhere.
    pub packet_ns: f64,
}

/// Rows of the shot whose samples `CpuPieces` times: every this many.
const PIECES_ROW_STRIDE: u32 = 16;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LensModel {
    Real,
    /// The thin lens at the entrance pupil with the pupil's radius, focused as the real one.
    Thin,
}

impl LensPoint {
    /// The figures of `point` rendering `shot` (the real lens's camera is `real`: the thin
    /// model's point takes its f-number from it).
    pub fn measure(point: BenchLens, shot: &Shot, real: &Camera) -> Self {
        let (camera, settings) = (&shot.camera, &shot.render);
        let f_number = real.lens.real().map_or(0.0, |l| l.f_number);
        let mut seconds = Vec::with_capacity(CAMERA_RAY_PASSES);
        let (mut camera_rays, mut d_line_rays) = (0, 0);
        for _ in 0..CAMERA_RAY_PASSES {
            let start = Instant::now();
            (camera_rays, d_line_rays) = shot_camera_rays(shot);
            seconds.push(start.elapsed().as_secs_f64());
        }
        let camera_samples =
            u64::from(camera.width) * u64::from(camera.height) * u64::from(settings.spp);
        let (centre_passed, centre_samples) = centre_camera_rays(camera);
        let cpu_pieces = CpuPieces::measure(shot);
        LensPoint {
            lens: point.name(),
            model: if point.real {
                LensModel::Real
            } else {
                LensModel::Thin
            },
            f_number,
            entrance_pupil_radius: camera.lens.first_order().aperture_radius,
            focus_distance: camera.lens.first_order().focus_distance,
            camera_samples,
            camera_rays,
            pass_share: d_line_rays as f64 / camera_samples.max(1) as f64,
            centre_pass_share: centre_passed as f64 / centre_samples.max(1) as f64,
            centre_samples,
            camera_ray_seconds: median(&seconds),
            cpu_pieces,
        }
    }
}

impl CpuPieces {
    /// Times the pieces over the samples of every `PIECES_ROW_STRIDE`th row of `shot`.
    fn measure(shot: &Shot) -> Self {
        let (camera, settings) = (&shot.camera, &shot.render);
        let rows = (0..camera.height).step_by(PIECES_ROW_STRIDE as usize);
        let pixels: Vec<UVec2> = rows
            .flat_map(|y| (0..camera.width).map(move |x| UVec2::new(x, y)))
            .collect();
        let samples: Vec<(Vec2, Vec2)> = pixels
            .iter()
            .flat_map(|&p| {
                let sampler = sampler_of(shot, p);
                (0..settings.spp).map(move |i| {
                    let s = pixel_camera_sample(&sampler, i);
                    (s.film, s.lens)
                })
            })
            .collect();
        let n = samples.len().max(1) as f64;
        let sampler_ns = ns_per_sample(n, &|| {
            let mut sum = 0.0;
            for &p in &pixels {
                let sampler = sampler_of(shot, p);
                for i in 0..settings.spp {
                    let s = pixel_camera_sample(&sampler, black_box(i));
                    sum += s.film.x + s.lens.y;
                }
            }
            sum
        });
        let camera_ray_ns = ns_per_sample(n, &|| {
            let mut sum = 0.0;
            for &(film, lens) in &samples {
                if let Some((ray, weight)) =
                    camera.generate_ray(CameraSample::new(film, lens), None)
                {
                    sum += ray.direction.x + weight;
                }
            }
            sum
        });
        let (pupil_ns, lens_trace_ns, packet_ns) = match camera.lens.real() {
            Some(real) => real_lens_pieces(real, camera, &samples, n),
            None => (0.0, 0.0, camera_ray_ns),
        };
        CpuPieces {
            samples: samples.len() as u64,
            sampler_ns,
            pupil_ns,
            lens_trace_ns,
            camera_ray_ns,
            packet_ns,
        }
    }
}

/// The sampler of `pixel` of `shot` as the paths draw it (shared across pixels or per pixel).
fn sampler_of(shot: &Shot, pixel: UVec2) -> PixelSampler {
    let settings = &shot.render;
    if settings.shared_samples {
        shared_pixel_sampler(settings.sampler, settings.seed, pixel)
    } else {
        pixel_sampler(settings.sampler, settings.seed, pixel, shot.camera.width)
    }
}

/// Nanoseconds per sample of `work` over all `n` samples: the median of `CAMERA_RAY_PASSES`
/// passes.
fn ns_per_sample(n: f64, work: &dyn Fn() -> f32) -> f64 {
    let times: Vec<f64> = (0..CAMERA_RAY_PASSES)
        .map(|_| {
            let start = Instant::now();
            black_box(work());
            start.elapsed().as_secs_f64() * 1e9 / n
        })
        .collect();
    median(&times)
}

/// The real lens's pieces per sample over `samples` (`n` of them, at least 1): the film point
/// and pupil sample, the trace through the surfaces (the pupil's time taken off), and
/// `RealLens::generate_rays` on packets.
fn real_lens_pieces(
    real: &RealLens,
    camera: &Camera,
    samples: &[(Vec2, Vec2)],
    n: f64,
) -> (f64, f64, f64) {
    let (width, height) = (camera.width, camera.height);
    let pupil = || {
        let mut sum = 0.0;
        for &(film, lens) in samples {
            let film = real.film_point(film, width, height);
            let (rear, area) = real.pupil().sample(film, lens);
            sum += rear.x + area;
        }
        sum
    };
    let traced = || {
        let mut sum = 0.0;
        for &(film, lens) in samples {
            let film = real.film_point(film, width, height);
            let (rear, _) = real.pupil().sample(film, lens);
            let ray = LensRay {
                origin: film,
                direction: (rear - film).normalize(),
            };
            if let Some((out, t)) = real.trace_to_scene(ray) {
                sum += out.direction.x + t;
            }
        }
        sum
    };
    let packets = || {
        let mut sum = 0.0;
        for chunk in samples.chunks(PACKET_SIZE) {
            let mut lanes = [(Vec3::ZERO, Vec2::ZERO, 0.0); PACKET_SIZE];
            for (lane, &(film, lens)) in lanes.iter_mut().zip(chunk) {
                *lane = (real.film_point(film, width, height), lens, 0.0);
            }
            let mut out = [None; PACKET_SIZE];
            real.generate_rays(&lanes[..chunk.len()], &mut out);
            for (ray, weight) in out.into_iter().flatten() {
                sum += ray.direction.x + weight;
            }
        }
        sum
    };
    let pupil_ns = ns_per_sample(n, &pupil);
    let lens_trace_ns = (ns_per_sample(n, &traced) - pupil_ns).max(0.0);
    let packet_ns = ns_per_sample(n, &packets);
    (pupil_ns, lens_trace_ns, packet_ns)
}

/// The camera rays of a render of `shot` that the lens lets through: every pixel's samples
/// `0..spp`, drawn as the paths draw them (a dispersive lens's checking samples trace two),
/// and of those the d line's, one a sample at most.
pub fn shot_camera_rays(shot: &Shot) -> (u64, u64) {
    let (camera, settings) = (&shot.camera, &shot.render);
    (0..camera.height)
        .into_par_iter()
        .map(|y| {
            let (mut passed, mut d_line) = (0u64, 0u64);
            for x in 0..camera.width {
                let pixel = UVec2::new(x, y);
                let sampler = sampler_of(shot, pixel);
                for i in 0..settings.spp {
                    let sample = pixel_camera_sample(&sampler, i);
                    // As the render traces it: the d line, and through a dispersive lens the
                    // wavelength of a sample that checks it.
                    d_line += u64::from(camera.generate_ray(sample, None).is_some());
                    if let Some(lambda) = camera.checked_wavelength(&sampler, i) {
                        let ray = camera.generate_ray(sample, Some(lambda));
                        passed += u64::from(ray.is_some());
                    }
                }
            }
            (passed + d_line, d_line)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
}

/// At the centre of each central pixel (the pixel holding the image's centre, or the two or
/// four meeting there), a grid of lens samples: how many pass, of how many.
pub fn centre_camera_rays(camera: &Camera) -> (u64, u64) {
    let central = |side: u32| -> Vec<u32> {
        if side % 2 == 0 {
            vec![side / 2 - 1, side / 2]
        } else {
            vec![side / 2]
        }
    };
    let (mut passed, mut drawn) = (0u64, 0u64);
    for &y in &central(camera.height) {
        for &x in &central(camera.width) {
            let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            for j in 0..CENTRE_GRID {
                for i in 0..CENTRE_GRID {
                    let lens = (Vec2::new(i as f32, j as f32) + 0.5) / CENTRE_GRID as f32;
                    let sample = CameraSample::new(film, lens);
                    passed += u64::from(camera.generate_ray(sample, None).is_some());
                    drawn += 1;
                }
            }
        }
    }
    (passed, drawn)
}

/// Per path, the figures against the thin model of the same lens: camera rays per second, the
/// time over the thin model's, and the cost per camera ray that reaches the scene over the
/// thin model's (the target: at most 2x).
pub fn set_costs_vs_thin(
    values: &[BenchLens],
    lenses: &[LensPoint],
    results: &mut [Vec<Measurement>],
) {
    let thin_of = |point: BenchLens| values.iter().position(|&v| v == point.partner());
    let per_ray = |m: &Measurement, lens: &LensPoint| {
        m.trace_seconds.median / (lens.camera_rays as f64).max(1.0)
    };
    let thin_costs: Vec<Vec<(PathKind, f64, f64)>> = values
        .iter()
        .zip(lenses)
        .zip(results.iter())
        .map(|((&v, lens), ms)| {
            if v.real {
                return Vec::new();
            }
            ms.iter()
                .map(|m| (m.path, m.trace_seconds.median, per_ray(m, lens)))
                .collect()
        })
        .collect();
    for ((&v, lens), ms) in values.iter().zip(lenses).zip(results.iter_mut()) {
        let thin = if v.real {
            thin_of(v).map(|i| &thin_costs[i])
        } else {
            values.iter().position(|&w| w == v).map(|i| &thin_costs[i])
        };
        for m in ms.iter_mut() {
            m.camera_rays_per_second = Some(lens.camera_rays as f64 / m.trace_seconds.median);
            let Some(&(_, time, ray)) = thin.and_then(|t| t.iter().find(|(p, ..)| *p == m.path))
            else {
                continue;
            };
            m.cost_vs_thin = Some(m.trace_seconds.median / time.max(1e-12));
            m.cost_per_camera_ray_vs_thin = Some(per_ray(m, lens) / ray.max(1e-18));
        }
    }
}
