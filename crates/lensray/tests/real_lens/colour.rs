//! Colour from the glass: a white point imaged through dispersive lenses, on the CPU reference,
//! against spots traced forward from the point in f64 at each wavelength (independent of the
//! camera's rays, exit-pupil regions and weights), mixed into red, green and blue as
//! `film::spectral` weighs a wavelength.
//!
//! - Lateral colour: off the axis, the red and blue images of the point sit apart by what the
//!   traced chief rays of each wavelength predict; with `--dispersion off` they coincide.
//! - Axial colour: on the axis, focused for the d line, the green and blue spots have the
//!   sizes the traced focal shift gives each wavelength.
//! - An achromat shows far less colour than a singlet of the same focal length.
//! - Through glass whose dispersion is negligible, the spectral estimate converges to the RGB
//!   render, and a white surface stays white.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use lensray_core::camera::Camera;
use lensray_core::film::spectral::{rgb_weights, sample_wavelength};
use lensray_core::film::Image;
use lensray_core::optics::analysis::LensData;
use lensray_core::optics::glass::dispersion_offset;
use lensray_core::optics::trace::{wide, Toward};
use lensray_core::optics::{builtin, Prescription};
use lensray_core::reference::Renderer;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;
use rayon::prelude::*;

use crate::{camera, material, quad, real, real_lens, settings, write_png};

/// A plano-convex SF57 singlet (n_d 1.84666, V_d 23.83) 25 mm behind its stop: strong axial
/// colour (-2.09 mm) and, the stop being far from the lens, strong lateral colour.
const FLINT_SINGLET: &str = "# SF57 plano-convex singlet behind a distant stop (a test lens)\n\
    0 25 1 16\n40 6 1.84666 24 23.83\n400 0 1 24\n";

/// The point's distance (m) and the image's size; the film pitch is 0.04 mm.
const DISTANCE: f32 = 100.0;
const WIDTH: u32 = 240;
const HEIGHT: u32 = 160;
const SENSOR_MM: f64 = 6.4;
/// Wavelengths the forward traces mix (stratified as a render draws them).
const WAVELENGTHS: u32 = 48;

/// A point's moments in one channel: light-weighted centroid and mean squared radius (px).
#[derive(Clone, Copy, Debug)]
struct Moments {
    x: f64,
    y: f64,
    r2: f64,
}

fn moments(samples: impl Iterator<Item = (f64, f64, f64)> + Clone) -> Moments {
    let total: f64 = samples.clone().map(|(_, _, w)| w).sum();
    let x = samples.clone().map(|(x, _, w)| w * x).sum::<f64>() / total;
    let y = samples.clone().map(|(_, y, w)| w * y).sum::<f64>() / total;
    let r2 = samples
        .map(|(px, py, w)| w * ((px - x).powi(2) + (py - y).powi(2)))
        .sum::<f64>()
        / total;
    Moments { x, y, r2 }
}

/// The point at `field` degrees (along +x) through `lens` at `f_number`, focused on it.
fn shot(lens: &Arc<Prescription>, f_number: f64, dispersion: bool) -> Camera {
    let mut params = real(lens, Some(f_number), f64::from(DISTANCE), SENSOR_MM);
    if let lensray_core::camera::LensParams::Real(p) = &mut params {
        p.dispersion = dispersion;
    }
    camera(WIDTH, HEIGHT, params)
}

fn point(field_deg: f32) -> Vec3 {
    Vec3::new(DISTANCE * field_deg.to_radians().tan(), 0.0, -DISTANCE)
}

/// Half the side of the point's square, m: 1.07 px on the film (a pixel sees 7.7 cm there),
/// so that most of the samples of the pixels it covers see it.
const HALF: f32 = 0.04;
/// Samples per pixel: one wavelength's weight has a standard deviation of 1.4-2.2 per channel
/// for white, so a colour's moments need many.
const SPP: u32 = 4096;

/// The point (a white square 8 cm across) rendered on black.
fn render_point(camera: &Camera, p: Vec3) -> Image {
    let half = HALF;
    let scene = Scene {
        meshes: vec![quad(p.x - half, p.x + half, -half, half, p.z, 0)],
        materials: vec![material("white", Vec3::ONE)],
        ..Default::default()
    };
    let shot = Shot {
        camera: camera.clone(),
        render: settings(SPP, 1, Vec3::ZERO),
    };
    Renderer::new(&scene).render(&shot, &mut |_, _| {}).0
}

/// Each channel's moments over the window of `radius` px around raster (cx, cy).
fn measured(image: &Image, (cx, cy): (f64, f64), radius: f64) -> [Moments; 3] {
    let pixels: Vec<(f64, f64, Vec3)> = image
        .pixels
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let (x, y) = (
                (i as u32 % image.width) as f64,
                (i as u32 / image.width) as f64,
            );
            (x + 0.5, y + 0.5, *v)
        })
        .filter(|(x, y, _)| (x - cx).abs() <= radius && (y - cy).abs() <= radius)
        .collect();
    let light: f32 = pixels.iter().map(|(_, _, v)| v.element_sum()).sum();
    assert!(
        light > 0.0,
        "no light within {radius} px of ({cx:.1}, {cy:.1})"
    );
    std::array::from_fn(|c| moments(pixels.iter().map(move |&(x, y, v)| (x, y, f64::from(v[c])))))
}

/// Where rays from the point land on the film (raster px), traced forward in f64 through the
/// lens as focused and stopped down, at dispersion offset `k`: a 160 x 160 grid over twice
/// the entrance pupil.
fn forward(camera: &Camera, p: Vec3, k: f64) -> Vec<(f64, f64)> {
    let lens = real_lens(camera);
    let elements = wide::Elements::new(&lens.stopped);
    let pupil = lens.first_order.entrance_pupil;
    let radius = 0.5 * pupil.diameter_mm;
    let film_z = f64::from(lens.film_z());
    let pitch = SENSOR_MM / f64::from(HEIGHT);
    let origin = DVec3::new(
        f64::from(p.x) * 1000.0,
        f64::from(p.y) * 1000.0,
        pupil.position_mm + f64::from(p.z) * 1000.0,
    );
    const GRID: u32 = 160;
    (0..GRID * GRID)
        .into_par_iter()
        .filter_map(|g| {
            let a = |i: u32| radius * (4.0 * (f64::from(i) + 0.5) / f64::from(GRID) - 2.0);
            let aim = DVec3::new(a(g % GRID), a(g / GRID), pupil.position_mm);
            let ray = wide::LensRay {
                origin,
                direction: (aim - origin).normalize(),
            };
            let out = elements.trace_at(ray, Toward::Film, k)?;
            let on_film = out.origin + (film_z - out.origin.z) / out.direction.z * out.direction;
            Some((
                0.5 * f64::from(WIDTH) - on_film.x / pitch,
                0.5 * f64::from(HEIGHT) + on_film.y / pitch,
            ))
        })
        .collect()
}

/// Each channel's moments of the point's image as the forward traces predict it: every
/// wavelength's spot, weighted by what `film::spectral` makes of white at that wavelength,
/// each landing ray spread over the square's image (it is no point) and binned into pixels as
/// a render averages the film over each pixel; the moments are then taken over the window of
/// `radius` px around the green centroid, as [`measured`] takes them.
fn predicted(camera: &Camera, p: Vec3, radius: f64) -> [Moments; 3] {
    let efl = real_lens(camera).first_order.efl;
    let side = f64::from(2.0 * HALF / DISTANCE) * efl / (SENSOR_MM / f64::from(HEIGHT));
    let mut image = vec![Vec3::ZERO; (WIDTH * HEIGHT) as usize];
    for i in 0..WAVELENGTHS {
        let lambda = sample_wavelength((i as f32 + 0.5) / WAVELENGTHS as f32);
        let white = rgb_weights(lambda) * Vec3::ONE;
        for (x, y) in forward(camera, p, dispersion_offset(f64::from(lambda))) {
            // The square's image [x - side / 2, x + side / 2]^2 over the pixels it overlaps.
            let (x0, x1, y0, y1) = (
                x - 0.5 * side,
                x + 0.5 * side,
                y - 0.5 * side,
                y + 0.5 * side,
            );
            for py in y0.floor() as i64..=y1.floor() as i64 {
                for px in x0.floor() as i64..=x1.floor() as i64 {
                    let (px_f, py_f) = (px as f64, py as f64);
                    let overlap = (x1.min(px_f + 1.0) - x0.max(px_f)).max(0.0)
                        * (y1.min(py_f + 1.0) - y0.max(py_f)).max(0.0);
                    if (0..i64::from(WIDTH)).contains(&px) && (0..i64::from(HEIGHT)).contains(&py) {
                        image[(py * i64::from(WIDTH) + px) as usize] +=
                            white * (overlap / (side * side)) as f32;
                    }
                }
            }
        }
    }
    let image = Image {
        width: WIDTH,
        height: HEIGHT,
        pixels: image,
    };
    let green = moments(image.pixels.iter().enumerate().map(|(i, v)| {
        let (x, y) = (
            (i as u32 % WIDTH) as f64 + 0.5,
            (i as u32 / WIDTH) as f64 + 0.5,
        );
        (x, y, f64::from(v.y))
    }));
    measured(&image, (green.x, green.y), radius)
}

/// Lateral colour: 4.5 degrees off the axis at f/16, the blue image lies further out than the
/// red by what the chief rays of each wavelength predict (within 5 % and 0.03 px); with
/// dispersion off the channels coincide.
#[test]
fn lateral_colour_separates_red_and_blue_as_traced() {
    let lens = Arc::new(Prescription::parse("flint", FLINT_SINGLET).unwrap());
    let p = point(4.5);
    let on = shot(&lens, 16.0, true);
    let want = predicted(&on, p, 8.0);
    let centre = (want[1].x, want[1].y);
    let image = render_point(&on, p);
    let got = measured(&image, centre, 8.0);
    let off = measured(&render_point(&shot(&lens, 16.0, false), p), centre, 8.0);
    let (got_shift, want_shift, off_shift) = (
        got[2].x - got[0].x,
        want[2].x - want[0].x,
        off[2].x - off[0].x,
    );
    let lateral = LensData::of(&lens).lateral_color;
    println!(
        "blue minus red centroid: rendered {got_shift:.3} px, traced {want_shift:.3} px, without dispersion {off_shift:.4} px (F - C at 5 deg: {:.4} mm)",
        lateral[0].lateral_color_mm
    );
    let ok = (got_shift - want_shift).abs() <= 0.05 * want_shift.abs() + 0.03
        && want_shift.abs() > 1.0
        && off_shift.abs() < 0.03;
    if !ok {
        let path = write_png(&image, "lateral-colour.png", 1.0);
        panic!(
            "rendered {got_shift} px vs traced {want_shift} px (off: {off_shift}); {}",
            path.display()
        );
    }
}

/// The rms radius (px) of each channel's image of the point on the axis through `lens`,
/// rendered and traced: red and green within 3 px of the centre, blue within 12 px. Red and
/// green weigh the far-spread blue wavelengths negatively (the matching functions' negative
/// lobes in sRGB), and those samples make a wide window's moments noisy; the prediction takes
/// the same windows, so the comparison stays fair.
fn axial_spots(lens: &Arc<Prescription>, f_number: f64) -> ([f64; 3], [f64; 3]) {
    let camera = shot(lens, f_number, true);
    let p = point(0.0);
    let image = render_point(&camera, p);
    let windowed = |moments: [Moments; 3], wide: [Moments; 3]| {
        [moments[0].r2, moments[1].r2, wide[2].r2].map(f64::sqrt)
    };
    let (near, far) = (predicted(&camera, p, 3.0), predicted(&camera, p, 12.0));
    let centre = (far[1].x, far[1].y);
    let got = windowed(
        measured(&image, centre, 3.0),
        measured(&image, centre, 12.0),
    );
    (got, windowed(near, far))
}

/// Axial colour: on the axis at f/6, focused for the d line, the green and blue spots have the
/// sizes the traced focal shift of their wavelengths gives (within 5 %; 1024 spp leave about
/// 4 % of noise), and blue blurs far more than green. Red has no rms radius to compare: sRGB's
/// red takes the blue wavelengths, whose spots spread widest, with a negative weight, and its
/// second moment comes out negative, in the traces as in the render.
#[test]
fn axial_colour_blurs_green_and_blue_as_traced() {
    let lens = Arc::new(Prescription::parse("flint", FLINT_SINGLET).unwrap());
    let (got, want) = axial_spots(&lens, 6.0);
    println!("rms radius R, G, B: rendered {got:.3?} px, traced {want:.3?} px");
    for c in 1..3 {
        assert!(
            (got[c] - want[c]).abs() <= 0.05 * want[c],
            "channel {c}: rendered {} px, traced {} px",
            got[c],
            want[c]
        );
    }
    assert!(
        want[2] > 2.0 * want[1],
        "blue should blur far more than green: {want:?}"
    );
}

/// An achromat against a singlet of about the same focal length, both at f/8: the spread of
/// its channels' spot sizes and its axial colour are a small fraction of the singlet's.
#[test]
fn an_achromat_shows_far_less_colour_than_a_singlet() {
    let spread = |name: &str| {
        let lens = Arc::new(builtin::lens(name).unwrap());
        let axial = LensData::of(&lens).axial_color_mm;
        let (got, _) = axial_spots(&lens, 8.0);
        println!("{name}: rms radius R, G, B {got:.3?} px, axial colour {axial:.4} mm");
        ((got[2] - got[0]).abs(), axial.abs())
    };
    let (achromat, achromat_axial) = spread("achromat-50");
    let (singlet, singlet_axial) = spread("biconvex-50");
    println!(
        "blue minus red spot radius: achromat {achromat:.3} px, singlet {singlet:.3} px; axial colour ratio {:.3}",
        achromat_axial / singlet_axial
    );
    assert!(achromat_axial < 0.1 * singlet_axial);
    assert!(
        achromat < 0.25 * singlet,
        "achromat {achromat} px vs singlet {singlet} px"
    );
}

/// A BK7 singlet whose glass disperses negligibly (V_d = 1e7).
fn negligible_dispersion_singlet() -> Arc<Prescription> {
    let text =
        "# BK7 singlet with negligible dispersion\n0 2 1 20\n51.5 5 1.5168 25 1e7\n-51.5 0 1 25\n";
    Arc::new(Prescription::parse("flat", text).unwrap())
}

/// Four quadrants, red, green, blue and white, rendered through `lens` at f/4, `spp` samples,
/// with dispersion on and off: (spectral, RGB).
fn quadrants(lens: &Arc<Prescription>, spp: u32) -> (Image, Image) {
    let colours = [
        Vec3::new(0.8, 0.1, 0.1),
        Vec3::new(0.1, 0.7, 0.2),
        Vec3::new(0.1, 0.2, 0.9),
        Vec3::ONE,
    ];
    let scene = Scene {
        meshes: vec![
            quad(-2.0, 0.0, 0.0, 2.0, -3.0, 0),
            quad(0.0, 2.0, 0.0, 2.0, -3.0, 1),
            quad(-2.0, 0.0, -2.0, 0.0, -3.0, 2),
            quad(0.0, 2.0, -2.0, 0.0, -3.0, 3),
        ],
        materials: colours.iter().map(|&c| material("patch", c)).collect(),
        ..Default::default()
    };
    let render = |dispersion: bool| {
        let mut params = real(lens, Some(4.0), 3.0, 24.0);
        if let lensray_core::camera::LensParams::Real(p) = &mut params {
            p.dispersion = dispersion;
        }
        let camera = camera(32, 24, params);
        assert_eq!(real_lens(&camera).dispersive(), dispersion);
        let shot = Shot {
            camera,
            render: settings(spp, 1, Vec3::ZERO),
        };
        Renderer::new(&scene).render(&shot, &mut |_, _| {}).0
    };
    (render(true), render(false))
}

/// Through glass of negligible dispersion, the spectral estimate converges to the RGB render,
/// and white stays white: the quadrants at 4096 spp, each quadrant's inner pixels averaged.
#[test]
fn negligible_dispersion_converges_to_the_rgb_render() {
    let (spectral, rgb) = quadrants(&negligible_dispersion_singlet(), 4096);
    // Each quadrant's pixels at least 3 px from its edges (the image is 32 x 24).
    let quadrant_mean = |image: &Image, q: usize| {
        let (x0, y0) = (if q % 2 == 0 { 3 } else { 19 }, if q < 2 { 3 } else { 15 });
        let mut sum = Vec3::ZERO;
        for y in y0..y0 + 6 {
            for x in x0..x0 + 10 {
                sum += image.pixels[y * 32 + x];
            }
        }
        sum / 60.0
    };
    let mut failures = Vec::new();
    for q in 0..4 {
        let (a, b) = (quadrant_mean(&spectral, q), quadrant_mean(&rgb, q));
        let difference = ((a - b) / b.max(Vec3::splat(0.05))).abs().max_element();
        println!("quadrant {q}: spectral {a:.4}, RGB {b:.4} ({difference:.4})");
        if difference > 0.01 {
            failures.push(format!("quadrant {q}: spectral {a} vs RGB {b}"));
        }
    }
    let white = quadrant_mean(&spectral, 3);
    if (white / white.y - Vec3::ONE).abs().max_element() > 0.005 {
        failures.push(format!("white is {white}"));
    }
    if !failures.is_empty() {
        write_png(&spectral, "negligible-dispersion-spectral.png", 1.0);
        write_png(&rgb, "negligible-dispersion-rgb.png", 1.0);
        panic!("{}", failures.join("; "));
    }
}

/// Where a wavelength's ray sees what the d line's sees, the spectral estimate adds no colour
/// noise (film::spectral, "Dispersion at little cost"): through negligible dispersion at 16
/// spp, every pixel is the RGB render's within 2e-3. One wavelength a sample, weighted back to
/// RGB, leaves single pixels tens of times further off at this count (the weight of white has
/// a standard deviation of 1.4-2.2 per channel).
#[test]
fn negligible_dispersion_adds_no_colour_noise() {
    let (spectral, rgb) = quadrants(&negligible_dispersion_singlet(), 16);
    let worst = spectral
        .pixels
        .iter()
        .zip(&rgb.pixels)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0f32, f32::max);
    println!("largest |spectral - RGB| over the pixels at 16 spp: {worst:.2e}");
    if worst > 2e-3 {
        write_png(&spectral, "negligible-dispersion-16-spectral.png", 1.0);
        write_png(&rgb, "negligible-dispersion-16-rgb.png", 1.0);
        panic!("a pixel is {worst} from the RGB render");
    }
}
