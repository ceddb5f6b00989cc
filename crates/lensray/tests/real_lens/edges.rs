//! Edges: the blur of a thin singlet, and the sharpness at the focus distance.

use std::sync::Arc;

use glam::Vec3;
use lensray_core::camera::physical::PhysicalLens;
use lensray_core::camera::{Camera, LensParams};
use lensray_core::film::Image;
use lensray_core::optics::{builtin, Prescription};
use lensray_core::reference::Renderer;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;

use crate::{
    above, builtin_lens, camera, edge_fit, material, quad, real, real_lens, settings, write_png,
};

/// A vertical black/white edge on the plane at view depth `z`, 0.37 px right of the image's
/// middle pixel boundary in `camera`'s first-order projection, rendered at `spp`: the rows'
/// mean profile, the image, and the raster x where the edge projects.
fn render_edge(camera: &Camera, z: f32, spp: u32) -> (Vec<f64>, Image, f32) {
    let edge_x = 0.37 * z / camera.pixels_per_screen_unit();
    let scene = Scene {
        meshes: vec![
            quad(-100.0, edge_x, -100.0, 100.0, -z, 0),
            quad(edge_x, 100.0, -100.0, 100.0, -z, 1),
        ],
        materials: vec![material("black", Vec3::ZERO), material("white", Vec3::ONE)],
        ..Default::default()
    };
    let shot = Shot {
        camera: camera.clone(),
        render: settings(spp, 1, Vec3::ZERO),
    };
    let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    let profile = (0..camera.width)
        .map(|c| {
            let column: f64 = (0..camera.height)
                .map(|r| f64::from(image.get(c, r).x))
                .sum();
            column / f64::from(camera.height)
        })
        .collect();
    let projected = camera.project(Vec3::new(edge_x, 0.0, -z)).x;
    (profile, image, projected)
}

/// A thin equiconvex singlet, index 1.5, R = +-50 mm, 0.1 mm thick at the centre (the two
/// spheres meet at 2.24 mm from the axis, so the clear aperture is 4.4 mm), its 4 mm stop
/// 0.05 mm in front: efl 50.02 mm, f/12.5, the entrance pupil at the stop.
const THIN_SINGLET: &str = "# a thin singlet\n\
    0 0.05 1 4\n\
    50 0.1 1.5 4.4\n\
    -50 0 1 4.4\n";

/// A thin singlet renders what the thin lens renders: an edge off the focus distance, seen
/// through the singlet traced surface by surface and through `LensParams::Physical` with the
/// singlet's efl, f-number and focus distance, is blurred by the thin lens's circle of
/// confusion.
///
/// Set-up: a 64 x 32 image of a 1 mm high film (0.031 mm pixels): the field is 1.1 degrees
/// wide at the image's sides, where cos^4 darkens by 0.16 %, so vignetting cannot bend the
/// edge profile; the thin lens's CoC is 10.7 px at z = 0.2 and 6.4 px at z = 5 (focus 0.5 m).
/// The singlet's spherical aberration (Seidel LSA -0.13 mm at the rim) is 2 % of the film's
/// defocus at these depths. Measured at 1024 spp: the fitted radius is 0.9991 and 0.9968 of
/// the thin CoC (the thin-lens render itself: 1.0008 and 0.9999), the edge within 0.002 px of
/// its projection, rms residual 0.0008 and 0.0018. Bounds as in lensray-core's tests/reference.rs: 2 % (5 %
/// off in the entrance pupil, or a focus measured from the lens's rear instead of its
/// entrance pupil, moves the CoC by more), the edge within 0.1 px, residual below 0.008
/// (a blur of another shape).
#[test]
fn a_thin_singlet_blurs_as_the_thin_lens_does() {
    let singlet = Arc::new(Prescription::parse("thin-singlet", THIN_SINGLET).expect("parses"));
    let (width, height, sensor_mm, focus) = (64, 32, 1.0, 0.5);
    let real_camera = camera(width, height, real(&singlet, None, focus, sensor_mm));
    let lens = real_lens(&real_camera);
    let thin_camera = camera(
        width,
        height,
        LensParams::Physical {
            lens: PhysicalLens {
                focal_length_mm: lens.first_order.efl,
                f_number: lens.f_number,
                sensor_height_mm: sensor_mm,
            },
            focus_distance: focus,
        },
    );
    println!(
        "singlet: efl {:.4} mm, f/{:.4}, entrance pupil {:?}",
        lens.first_order.efl, lens.f_number, lens.first_order.entrance_pupil
    );
    let mut failures = Vec::new();
    for z in [0.2f32, 5.0] {
        let coc = thin_camera.coc_radius_pixels(glam::Vec2::ZERO, z);
        assert!(coc > 5.0, "test set-up: CoC {coc} px at z = {z}");
        let (profile, image, projected) = render_edge(&real_camera, z, 1024);
        let (thin_profile, thin_image, _) = render_edge(&thin_camera, z, 1024);
        let fit = edge_fit::fit(&profile);
        let thin_fit = edge_fit::fit(&thin_profile);
        let ratio = fit.radius / f64::from(coc);
        println!(
            "z = {z}: singlet {fit:?} (radius / thin CoC {ratio:.5}), edge projected at \
             {projected:.4}; thin lens {thin_fit:?}, CoC {coc:.4} px"
        );
        // Written as "not within" so that a NaN fails.
        if !((ratio - 1.0).abs() < 0.02
            && (fit.edge - f64::from(projected)).abs() < 0.1
            && fit.rms_residual < 0.008)
        {
            let a = write_png(&image, &format!("real_lens_singlet_z{z}.png"), 1.0);
            let b = write_png(&thin_image, &format!("real_lens_thin_z{z}.png"), 1.0);
            failures.push(format!(
                "z = {z}: singlet {fit:?}, expected radius {coc} px (thin lens) at x = \
                 {projected}: off by {:+.2} %; images {} {}",
                100.0 * (ratio - 1.0),
                a.display(),
                b.display()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// An edge at the focus distance is sharp through each built-in lens at f/8: fitted blur
/// radius under half a pixel, the edge where the first-order projection puts it (0.1 px).
///
/// Set-up: focus and edge 0.3 m from the entrance pupil, a 64 x 32 image of 0.02 mm pixels
/// near the axis. The pitch is the finest at which every lens's own blur stays under 0.5 px:
/// biconvex-50's spherical aberration measures 0.88 px at 0.005 mm pixels and 0.48 px at
/// 0.01 mm (a 0.0045 mm radius); at 0.02 mm all four fit below the fit's resolution (0.125).
/// At f/8 a film 0.16 mm off the focus blurs by 0.5 px here: focusing at 0.3 m from the first
/// vertex instead of the entrance pupil (tried on a copy of src) fits as 1.96 px through
/// double-gauss-50 and 1.25 px through cooke-triplet-50 (their pupils lie 20 and 12.6 mm
/// inside; biconvex-50's is at its vertex, wide-22's 0.23 px is too little to see). That the
/// pitch resolves a blur is checked too: an edge 1.5 px of first-order CoC behind the focus
/// fits as 1.45 to 1.49 px through the four lenses (bound: above 1 px).
#[test]
fn an_edge_at_the_focus_distance_is_sharp() {
    let (width, height, pitch_mm, focus) = (64u32, 32u32, 0.02, 0.3f32);
    let mut failures = Vec::new();
    for name in builtin::names() {
        let lens = builtin_lens(name);
        let sensor = pitch_mm * f64::from(height);
        let cam = camera(
            width,
            height,
            real(&lens, Some(8.0), f64::from(focus), sensor),
        );
        let (profile, image, projected) = render_edge(&cam, focus, 256);
        let fit = edge_fit::fit(&profile);
        // 1 / z = 1 / F - 1.5 px / (A * pixels per screen unit): the first-order CoC is 1.5 px.
        let reach = cam.lens.first_order().aperture_radius * cam.pixels_per_screen_unit();
        let behind = 1.0 / (1.0 / focus - 1.5 / reach);
        let (defocused, _, _) = render_edge(&cam, behind, 256);
        let defocused_fit = edge_fit::fit(&defocused);
        println!(
            "{name} at f/8: in focus {fit:?} (projected {projected:.4}); 1.5 px CoC behind \
             (z = {behind:.4}): radius {:.3}",
            defocused_fit.radius
        );
        if !(fit.radius < 0.5 && (fit.edge - f64::from(projected)).abs() < 0.1) {
            let png = write_png(&image, &format!("real_lens_sharp_{name}.png"), 1.0);
            failures.push(format!(
                "{name}: {fit:?}, expected a radius under 0.5 px at x = {projected}; image {}",
                png.display()
            ));
        }
        if !above(defocused_fit.radius, 1.0) {
            failures.push(format!(
                "{name}: an edge 1.5 px of first-order CoC behind the focus fits as {:.3} px: \
                 the pitch does not resolve a defocus, or the lens focuses elsewhere",
                defocused_fit.radius
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
