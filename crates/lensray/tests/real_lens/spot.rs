//! Measuring a bokeh spot: rays traced forward from its emitter, the window of pixels around
//! it, its light-weighted moments, the renderer's estimate over the window, and a spot
//! against its forward trace.

use glam::{DVec3, UVec2, Vec2, Vec3};
use lensray_core::camera::Camera;
use lensray_core::optics::trace::wide;
use lensray_core::optics::trace::Toward;
use lensray_core::sampler::{camera_sample, SamplerKind};
use rayon::prelude::*;

use crate::real_lens;

/// Where rays from an emitter square (centre `centre` in camera space, half side `half`,
/// facing the camera) land on the film, in raster coordinates: traced forward in f64 from a
/// 4 x 4 grid of points on the emitter toward a 400 x 400 grid over twice the entrance pupil's
/// diameter (every ray that can pass), through `RealLens::stopped` (the lens as focused and
/// stopped down) to the film plane. Independent of the camera's rays, its exit-pupil regions
/// and its weights; each ray carries the same flux (the cone is at most 7 degrees wide).
pub fn forward_spot(camera: &Camera, centre: Vec3, half: f32) -> Vec<(f64, f64)> {
    let lens = real_lens(camera);
    let elements = wide::Elements::new(&lens.stopped);
    let pupil = lens.first_order.entrance_pupil;
    let radius = 0.5 * pupil.diameter_mm;
    let film_z = f64::from(lens.film_z());
    let mm_per_pixel = 2.0 * f64::from(lens.film_half_height()) / f64::from(camera.height);
    let (width, height) = (f64::from(camera.width), f64::from(camera.height));
    const EMITTER: u32 = 4;
    const GRID: u32 = 400;
    (0..EMITTER * EMITTER)
        .into_par_iter()
        .flat_map_iter(|k| {
            let e =
                |i: u32| f64::from(half) * (2.0 * (f64::from(i) + 0.5) / f64::from(EMITTER) - 1.0);
            // Camera space (metres, +z forward) to lens space (mm, +z toward the film).
            let point = DVec3::new(
                (f64::from(centre.x) + e(k % EMITTER)) * 1000.0,
                (f64::from(centre.y) + e(k / EMITTER)) * 1000.0,
                pupil.position_mm - f64::from(centre.z) * 1000.0,
            );
            let elements = &elements;
            (0..GRID * GRID).filter_map(move |g| {
                let a = |i: u32| radius * (4.0 * (f64::from(i) + 0.5) / f64::from(GRID) - 2.0);
                let aim = DVec3::new(a(g % GRID), a(g / GRID), pupil.position_mm);
                let ray = wide::LensRay {
                    origin: point,
                    direction: (aim - point).normalize(),
                };
                let out = elements.trace(ray, Toward::Film)?;
                let on_film =
                    out.origin + (film_z - out.origin.z) / out.direction.z * out.direction;
                // The image is inverted: film (x, y) is raster (centre - x, centre + y) / pitch.
                Some((
                    0.5 * width - on_film.x / mm_per_pixel,
                    0.5 * height + on_film.y / mm_per_pixel,
                ))
            })
        })
        .collect()
}

/// A window of pixels [x0, x1) x [y0, y1).
#[derive(Clone, Copy, Debug)]
pub struct Window {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

/// The window holding `points` with a 3 px margin; `None` if it leaves a `width` x `height`
/// image (the spot would be cut by the image's edge).
pub fn window_around(points: &[(f64, f64)], width: u32, height: u32) -> Option<Window> {
    let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
    for &(x, y) in points {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    let (x0, y0) = (lo.0.floor() - 3.0, lo.1.floor() - 3.0);
    let (x1, y1) = (hi.0.ceil() + 3.0, hi.1.ceil() + 3.0);
    (x0 >= 0.0 && y0 >= 0.0 && x1 <= f64::from(width) && y1 <= f64::from(height)).then_some(
        Window {
            x0: x0 as u32,
            x1: x1 as u32,
            y0: y0 as u32,
            y1: y1 as u32,
        },
    )
}

/// A spot's light-weighted centroid (raster px) and covariance [xx, yy, xy] (px^2), from
/// pixel values (each at its pixel's centre).
#[derive(Clone, Copy, Debug)]
pub struct Spot {
    pub centroid: Vec2,
    covariance: [f64; 3],
}

impl Spot {
    pub fn of(window: Window, value: impl Fn(u32, u32) -> f64) -> Spot {
        let pixels = || {
            (window.y0..window.y1)
                .flat_map(move |y| (window.x0..window.x1).map(move |x| (x, y)))
                .map(|(x, y)| (f64::from(x) + 0.5, f64::from(y) + 0.5, value(x, y)))
        };
        let (mut sum, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for (x, y, v) in pixels() {
            sum += v;
            sx += v * x;
            sy += v * y;
        }
        let (cx, cy) = (sx / sum, sy / sum);
        let mut c = [0.0; 3];
        for (x, y, v) in pixels() {
            c[0] += v * (x - cx) * (x - cx);
            c[1] += v * (y - cy) * (y - cy);
            c[2] += v * (x - cx) * (y - cy);
        }
        Spot {
            centroid: Vec2::new(cx as f32, cy as f32),
            covariance: c.map(|m| m / sum),
        }
    }

    /// Forward-traced landing points binned into the pixels, as a render shows them.
    pub fn of_points(window: Window, points: &[(f64, f64)]) -> Spot {
        let columns = window.x1 - window.x0;
        let mut bins = vec![0.0; (columns * (window.y1 - window.y0)) as usize];
        for &(x, y) in points {
            let (i, j) = (x as u32 - window.x0, y as u32 - window.y0);
            bins[(j * columns + i) as usize] += 1.0;
        }
        Spot::of(window, |x, y| {
            bins[((y - window.y0) * columns + x - window.x0) as usize]
        })
    }

    /// The standard deviations along unit `u` and across it, px.
    fn sigmas(&self, u: Vec2) -> (f64, f64) {
        let [xx, yy, xy] = self.covariance;
        let (ux, uy) = (f64::from(u.x), f64::from(u.y));
        let along = xx * ux * ux + yy * uy * uy + 2.0 * xy * ux * uy;
        let across = xx * uy * uy + yy * ux * ux - 2.0 * xy * ux * uy;
        (along.sqrt(), across.sqrt())
    }

    /// The minor principal axis over the major one, and the minor axis's direction (radians).
    fn principal(&self) -> (f64, f64) {
        let [xx, yy, xy] = self.covariance;
        let mean = 0.5 * (xx + yy);
        let spread = (0.25 * (xx - yy) * (xx - yy) + xy * xy).sqrt();
        let major_angle = 0.5 * (2.0 * xy).atan2(xx - yy);
        (
            ((mean - spread) / (mean + spread)).sqrt(),
            major_angle + std::f64::consts::FRAC_PI_2,
        )
    }
}

/// The angle between two axes (undirected lines), radians in [0, pi/2].
pub fn axis_angle(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::PI);
    d.min(std::f64::consts::PI - d)
}

/// The renderer's estimate restricted to a window: each pixel is the mean, over its `spp`
/// samples from the renderer's own sampler (Sobol, seed 1), of the camera ray's weight where
/// the ray hits the emitter square (value 1) and 0 elsewhere or where the lens blocks it:
/// what `Renderer::render` adds for an `Unlit` white emitter on black (checked against a
/// render below), without tracing the pixels where nothing is.
pub fn render_window(
    camera: &Camera,
    centre: Vec3,
    half: f32,
    window: Window,
    spp: u32,
) -> Vec<f64> {
    let columns = (window.x1 - window.x0) as usize;
    let mut values = vec![0.0; columns * (window.y1 - window.y0) as usize];
    values
        .par_chunks_mut(columns)
        .enumerate()
        .for_each(|(j, row)| {
            let y = window.y0 + j as u32;
            for (i, value) in row.iter_mut().enumerate() {
                let pixel = UVec2::new(window.x0 + i as u32, y);
                let mut sum = 0.0;
                for k in 0..spp {
                    let sample = camera_sample(SamplerKind::Sobol, 1, pixel, camera.width, k);
                    let Some((ray, weight)) = camera.generate_ray(sample, None) else {
                        continue;
                    };
                    // The emitter's plane is world z = -centre.z.
                    let t = (-centre.z - ray.origin.z) / ray.direction.z;
                    let p = ray.origin + t * ray.direction;
                    if t > 0.0 && (p.x - centre.x).abs() <= half && (p.y - centre.y).abs() <= half {
                        sum += f64::from(weight);
                    }
                }
                *value = sum / f64::from(spp);
            }
        });
    values
}

/// A spot against its forward trace: sigma radial and tangential, the principal axes' ratio
/// and the minor axis's direction; a failure when the centroids are 0.5 px or more apart or
/// either sigma is 3 % or more off.
pub fn compare(
    label: &str,
    spot: &Spot,
    traced: &Spot,
    radial: Vec2,
) -> (f64, f64, f64, f64, Option<String>) {
    let (r, t) = spot.sigmas(radial);
    let (tr, tt) = traced.sigmas(radial);
    let (ratio, minor_angle) = spot.principal();
    let off = (spot.centroid - traced.centroid).length();
    println!(
        "{label}: centroid {} (traced {}), sigma radial {r:.3} tangential {t:.3} px \
         (traced {tr:.3} {tt:.3}), radial / tangential {:.3} (traced {:.3}), principal \
         ratio {ratio:.3}, minor axis {:.1} degrees from the radius",
        spot.centroid,
        traced.centroid,
        r / t,
        tr / tt,
        axis_angle(minor_angle, f64::from(radial.y.atan2(radial.x))).to_degrees()
    );
    // Written as "not within" so that a NaN (an empty spot) fails.
    let within = off < 0.5 && (r / tr - 1.0).abs() < 0.03 && (t / tt - 1.0).abs() < 0.03;
    let failure = (!within).then(|| {
        format!(
            "{label}: centroid {} vs traced {} ({off:.3} px), sigmas ({r:.3}, {t:.3}) vs \
                 traced ({tr:.3}, {tt:.3}): {:+.2} % and {:+.2} %",
            spot.centroid,
            traced.centroid,
            100.0 * (r / tr - 1.0),
            100.0 * (t / tt - 1.0)
        )
    });
    (r, t, ratio, minor_angle, failure)
}
