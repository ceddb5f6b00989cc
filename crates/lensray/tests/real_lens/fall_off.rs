//! Fall-off: the image's brightness across the film against the irradiance.

use glam::{Vec2, Vec3};
use lensray_core::camera::RealLens;
use lensray_core::optics::trace::narrow;
use lensray_core::reference::Renderer;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;
use rayon::prelude::*;

use crate::{below, builtin_lens, camera, material, quad, real, real_lens, settings, write_png};

/// Grid cells a side of the integration over the rear vertex's plane.
const IRRADIANCE_GRID: u32 = 400;

/// The irradiance at `film` (lens space) up to a constant: the integral of
/// T cos(theta_film) cos(theta_rear) / d^2 over a square of the rear vertex's plane 1.5 times
/// the rear clear aperture's radius on each side of the axis (every point a passing ray can
/// cross), by the midpoint rule on a `IRRADIANCE_GRID` square grid, T and passing from
/// `RealLens::trace_to_scene`; theta_film from the film's normal (the axis, but for a tilted
/// lens), theta_rear from the axis, d the distance. For a film square to the axis this is
/// T cos^4(theta) / h^2. Independent of the lens's exit-pupil regions and of
/// `RealLens::generate_ray`'s weights.
fn irradiance(lens: &RealLens, film: Vec3) -> f64 {
    irradiance_on_grid(lens, film, IRRADIANCE_GRID)
}

/// [`irradiance`] on an `n` x `n` grid.
pub(crate) fn irradiance_on_grid(lens: &RealLens, film: Vec3, n: u32) -> f64 {
    let rear = lens.elements().interfaces.last().expect("surfaces");
    let half = 1.5 * rear.aperture_radius;
    let cell = 2.0 * half / n as f32;
    let normal = lens.film().normal.as_dvec3();
    let sum: f64 = (0..n)
        .into_par_iter()
        .map(|j| {
            let mut row = 0.0;
            for i in 0..n {
                let q = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) * cell - Vec2::splat(half);
                let to_rear = q.extend(rear.z) - film;
                let direction = to_rear.normalize();
                let ray = narrow::LensRay {
                    origin: film,
                    direction,
                };
                if let Some((_, transmission)) = lens.trace_to_scene(ray) {
                    let d = direction.as_dvec3();
                    let cosines = d.z.abs() * d.dot(normal).abs();
                    row += f64::from(transmission) * cosines / to_rear.as_dvec3().length_squared();
                }
            }
            row
        })
        .sum();
    sum * f64::from(cell * cell)
}

/// The mean weight of `RealLens::generate_ray` at `film` over a 256 x 256 midpoint grid of lens
/// samples (blocked rays count 0): what the image averages there.
pub(crate) fn mean_weight(lens: &RealLens, film: Vec3) -> f64 {
    const M: u32 = 256;
    let sum: f64 = (0..M)
        .into_par_iter()
        .map(|j| {
            (0..M)
                .filter_map(|i| {
                    let u = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) / M as f32;
                    lens.generate_ray(film, u, 0.0).map(|(_, w)| f64::from(w))
                })
                .sum::<f64>()
        })
        .sum();
    sum / f64::from(M * M)
}

/// The relative illumination E(r) / E(0) of the integration over the rear plane against the
/// mean camera-ray weight (normalised by the centre's) at film points 0.25, 0.5, 0.75 and 1
/// of the film's half diagonal, along +x, the diagonal and a direction at 110 degrees, for
/// double-gauss-50 wide open (f/2.03: strong optical vignetting) and at f/8, and wide-22 wide
/// open (f/2.68). 36 x 24 mm film, focus 3 m.
///
/// Measured: at most 0.45 % apart (double-gauss-50 at f/8, where the pupil's footprint on the
/// rear plane is only 60 cells across: there the 400-cell integral itself moves by up to
/// 0.4 % on an 800-cell grid; elsewhere 0.3 %). Bound 1 %. What it catches, tried on a copy
/// of src: weights without cos^4 (+26 % at the corner), regions not turned to the film
/// point's angle (-42 % on the diagonal), regions 6 % too small, cutting the pupil's rim
/// (+1.7 %; 3 % stays inside the search's one-step margin and changes nothing). Optical
/// vignetting is in it: double-gauss-50's corner gets 0.17 of the centre's light wide open,
/// 0.78 at f/8 (bound: under half of the f/8 figure).
#[test]
fn fall_off_matches_the_irradiance_over_the_rear_plane() {
    let cases = [
        ("double-gauss-50", None),
        ("double-gauss-50", Some(8.0)),
        ("wide-22", None),
    ];
    let directions = [
        Vec2::X,
        Vec2::ONE.normalize(),
        Vec2::from_angle(110f32.to_radians()),
    ];
    let mut failures = Vec::new();
    let mut corners = Vec::new();
    for (name, f_number) in cases {
        let cam = camera(96, 64, real(&builtin_lens(name), f_number, 3.0, 24.0));
        let lens = real_lens(&cam);
        let at = |p: Vec2| p.extend(lens.film_z());
        let (e0, w0) = (
            irradiance(lens, at(Vec2::ZERO)),
            mean_weight(lens, at(Vec2::ZERO)),
        );
        println!(
            "{name} at f/{:.2}: centre mean weight {w0:.5}",
            lens.f_number
        );
        for direction in directions {
            for fraction in [0.25f32, 0.5, 0.75, 1.0] {
                let p = direction * fraction * lens.pupil().film_radius;
                let expected = irradiance(lens, at(p)) / e0;
                let got = mean_weight(lens, at(p)) / w0;
                let error = got / expected - 1.0;
                println!(
                    "  {fraction} of the half diagonal toward {direction}: E / E0 {expected:.5}, \
                     mean weight {got:.5} ({:+.3} %)",
                    100.0 * error
                );
                if !below(error.abs(), 0.01) {
                    failures.push(format!(
                        "{name} f/{:.2} at film {p}: E / E0 {expected:.5}, camera rays' mean \
                         weight {got:.5}: {:+.2} %",
                        lens.f_number,
                        100.0 * error
                    ));
                }
                if fraction == 1.0 && direction == Vec2::X && name == "double-gauss-50" {
                    corners.push(expected);
                }
            }
        }
    }
    println!(
        "double-gauss-50 corner E / E0: wide open {:.4}, f/8 {:.4}",
        corners[0], corners[1]
    );
    if !below(corners[0], 0.5 * corners[1]) {
        failures.push(format!(
            "double-gauss-50: no optical vignetting? corner E / E0 {:.4} wide open, {:.4} at f/8",
            corners[0], corners[1]
        ));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The whole render path: a uniform white background (radiance 1 everywhere the camera looks)
/// through double-gauss-50 wide open, 96 x 64 px on a 36 x 24 mm film, 1024 spp. The mean of
/// 2 x 2 pixel blocks at the centre, at 1/2 and 3/4 of the way to the corners, in a corner, at
/// the middle of the top and left edges, against the mean of E / E0 (see
/// [`fall_off_matches_the_irradiance_over_the_rear_plane`]) at the blocks' pixel centres.
///
/// Measured over 3 seeds: within 0.56 % (sample noise: 0.2 % at 4096 spp), the corner at 0.19
/// of the centre. Bound 1.5 %. Unlike the ratios above this sees the centre's normalisation
/// (1 / I0): regions 6 % too small render the centre 2.0 % dark.
#[test]
fn a_uniform_background_renders_the_relative_illumination() {
    let (width, height) = (96u32, 64u32);
    let shot = Shot {
        camera: camera(
            width,
            height,
            real(&builtin_lens("double-gauss-50"), None, 3.0, 24.0),
        ),
        render: settings(1024, 1, Vec3::ONE),
    };
    let lens = real_lens(&shot.camera);
    // Something for the BVH to hold, behind the camera: every ray sees the background.
    let scene = Scene {
        meshes: vec![quad(-1.0, 1.0, -1.0, 1.0, 10.0, 0)],
        materials: vec![material("unseen", Vec3::ZERO)],
        ..Default::default()
    };
    let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    let e0 = irradiance(lens, Vec3::new(0.0, 0.0, lens.film_z()));
    // Each block's top-left pixel is (x - 1, y - 1).
    let blocks = [
        (48u32, 32u32),
        (24, 16),
        (72, 48),
        (12, 8),
        (1, 1),
        (95, 63),
        (48, 1),
        (1, 32),
    ];
    let mut failures = Vec::new();
    for (bx, by) in blocks {
        let (mut rendered, mut expected) = (0.0, 0.0);
        for (x, y) in [(bx - 1, by - 1), (bx, by - 1), (bx - 1, by), (bx, by)] {
            rendered += f64::from(image.get(x, y).x) / 4.0;
            let film = lens.film_point(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), width, height);
            expected += irradiance(lens, film) / e0 / 4.0;
        }
        let error = rendered / expected - 1.0;
        println!(
            "block at ({bx}, {by}): rendered {rendered:.5}, E / E0 {expected:.5} ({:+.3} %)",
            100.0 * error
        );
        if !below(error.abs(), 0.015) {
            failures.push(format!(
                "block at ({bx}, {by}): rendered {rendered:.5}, E / E0 {expected:.5}: {:+.2} %",
                100.0 * error
            ));
        }
    }
    if !failures.is_empty() {
        let png = write_png(&image, "real_lens_fall_off.png", 1.0);
        failures.push(format!("image: {}", png.display()));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
