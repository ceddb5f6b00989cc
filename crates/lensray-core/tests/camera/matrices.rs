//! 1. Each matrix against the course's formulas.

use glam::{DVec3, Vec3, Vec4};
use lensray_core::camera::projection::{
    orthographic, orthographic_inverse, perspective, perspective_inverse,
};
use lensray_core::camera::raster::{self, ScreenWindow};
use lensray_core::camera::{Camera, Projection};

use crate::common::*;

/// (near, far) samples: ordinary, narrow, very wide range, non-round numbers.
const NEAR_FAR: [(f64, f64); 6] = [
    (0.1, 100.0),
    (1.0, 2.0),
    (0.01, 1000.0),
    (2.5, 7.25),
    (0.5, 20.0),
    (3.0, 3.5),
];

/// Slide "Orthographic".
fn slide_orthographic(n: f64, f: f64) -> Rows {
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0 / (f - n), -n / (f - n)],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// Slide "Perspective".
fn slide_perspective(n: f64, f: f64) -> Rows {
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, f / (f - n), -f * n / (f - n)],
        [0.0, 0.0, 1.0, 0.0],
    ]
}

/// Hand-inverted slide "Orthographic": z = near + z_screen (far - near).
fn slide_orthographic_inverse(n: f64, f: f64) -> Rows {
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, f - n, n],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// Hand-inverted slide "Perspective": the lower-right block [[f/(f-n), -fn/(f-n)], [1, 0]] has
/// determinant fn/(f-n) and inverse [[0, 1], [-(f-n)/(fn), 1/n]].
fn slide_perspective_inverse(n: f64, f: f64) -> Rows {
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [0.0, 0.0, -(f - n) / (f * n), 1.0 / n],
    ]
}

#[test]
fn orthographic_matrix_matches_slide() {
    for (n, f) in NEAR_FAR {
        let m = orthographic(n as f32, f as f32);
        assert_matrix(
            &format!("orthographic(near {n}, far {f})"),
            &m,
            &slide_orthographic(n, f),
            1e-6,
        );
        let via_enum =
            Projection::Orthographic { height: 2.0 }.screen_from_camera(n as f32, f as f32);
        assert_eq!(
            via_enum, m,
            "Projection::Orthographic dispatches to orthographic()"
        );
    }
}

#[test]
fn perspective_matrix_matches_slide() {
    for (n, f) in NEAR_FAR {
        let m = perspective(n as f32, f as f32);
        assert_matrix(
            &format!("perspective(near {n}, far {f})"),
            &m,
            &slide_perspective(n, f),
            1e-6,
        );
        let via_enum = Projection::Perspective { vfov: 1.0 }.screen_from_camera(n as f32, f as f32);
        assert_eq!(
            via_enum, m,
            "Projection::Perspective dispatches to perspective()"
        );
    }
}

#[test]
fn projection_inverses_match_hand_inverse_and_multiply_to_identity() {
    for (n, f) in NEAR_FAR {
        let (nf, ff) = (n as f32, f as f32);
        let cases = [
            (
                "orthographic",
                orthographic(nf, ff),
                orthographic_inverse(nf, ff),
                Projection::Orthographic { height: 2.0 },
                slide_orthographic_inverse(n, f),
            ),
            (
                "perspective",
                perspective(nf, ff),
                perspective_inverse(nf, ff),
                Projection::Perspective { vfov: 1.0 },
                slide_perspective_inverse(n, f),
            ),
        ];
        for (name, m, inv, projection, hand) in cases {
            let what = format!("{name} inverse (near {n}, far {f})");
            assert_matrix(&what, &inv, &hand, 1e-6);
            assert_eq!(
                projection.camera_from_screen(nf, ff),
                inv,
                "{name}: Projection::camera_from_screen dispatches to the inverse"
            );
            assert_identity(&format!("{what}: P * P^-1"), &(m * inv), 2e-6);
            assert_identity(&format!("{what}: P^-1 * P"), &(inv * m), 2e-6);
            // And against glam's general inverse (only where it is well conditioned).
            let general = m.inverse();
            for c in 0..4 {
                for r in 0..4 {
                    let (a, g) = (inv.col(c)[r] as f64, general.col(c)[r] as f64);
                    assert_close(
                        &format!("{what}: entry ({r}, {c}) vs Mat4::inverse"),
                        a,
                        g,
                        1e-5 * g.abs().max(1.0),
                    );
                }
            }
        }
    }
}

/// The matrices applied to points: x, y unchanged (ortho) or divided by z (perspective), depth
/// far (z - near) / (z (far - near)) or (z - near) / (far - near), 0 at near and 1 at far.
#[test]
fn projections_map_points_and_depth_by_course_formulas() {
    let mut rng = Rng::new(1);
    for (n, f) in NEAR_FAR {
        let (nf, ff) = (n as f32, f as f32);
        for i in 0..200 {
            // Include the near and far planes themselves.
            let z = match i {
                0 => n,
                1 => f,
                _ => n * (f / n).powf(rng.f64()),
            };
            let (x, y) = (rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            let p = Vec3::new(x as f32, y as f32, z as f32);
            let (x, y, z) = (p.x as f64, p.y as f64, p.z as f64);

            let (o, w) = transform_h(&orthographic(nf, ff), p);
            assert_close(&format!("orthographic w of {p:?}"), w as f64, 1.0, 0.0);
            let expected = DVec3::new(x, y, (z - n) / (f - n));
            assert_vec_close(
                &format!("orthographic(near {n}, far {f}) applied to {p:?}"),
                o.as_dvec3(),
                expected,
                2e-6 * expected.abs().max_element().max(1.0),
            );

            let (s, w) = transform_h(&perspective(nf, ff), p);
            assert_close(&format!("perspective w (= z) of {p:?}"), w as f64, z, 0.0);
            let expected = DVec3::new(x / z, y / z, f * (z - n) / (z * (f - n)));
            assert_vec_close(
                &format!("perspective(near {n}, far {f}) applied to {p:?}"),
                s.as_dvec3(),
                expected,
                2e-6 * expected.abs().max_element().max(1.0),
            );
            if i == 0 {
                assert_close("ortho depth at near", o.z as f64, 0.0, 1e-7);
                assert_close("perspective depth at near", s.z as f64, 0.0, 1e-6);
            }
            if i == 1 {
                assert_close("ortho depth at far", o.z as f64, 1.0, 1e-6);
                assert_close("perspective depth at far", s.z as f64, 1.0, 1e-6);
            }
        }
    }
}

/// The camera's screen window (half width `hw`, half height `hh`), its bounds, and the
/// NDC <-> raster matrices it uses.
fn check_screen_window(name: &str, cam: &Camera, hw: f64, hh: f64) {
    assert_rel(
        &format!("{name}: screen window half height"),
        cam.screen_window.half_height as f64,
        hh,
        1e-6,
    );
    assert_rel(
        &format!("{name}: screen window half width"),
        cam.screen_window.half_width as f64,
        hw,
        1e-6,
    );
    assert_rel(
        &format!("{name}: Projection::screen_half_height"),
        cam.projection.screen_half_height() as f64,
        hh,
        1e-6,
    );
    let window = ScreenWindow::new(
        cam.projection.screen_half_height(),
        cam.width,
        cam.height,
        cam.screen_window.centre,
    );
    assert_eq!(window, cam.screen_window, "{name}: ScreenWindow::new");
    assert_eq!(
        (
            window.x_start(),
            window.x_stop(),
            window.y_start(),
            window.y_stop()
        ),
        (
            -window.half_width,
            window.half_width,
            -window.half_height,
            window.half_height
        ),
        "{name}: xStart, xStop, yStart, yStop"
    );
    assert_eq!(
        cam.raster_from_ndc,
        raster::raster_from_ndc(cam.width, cam.height),
        "{name}: camera uses raster::raster_from_ndc"
    );
    assert_eq!(
        cam.ndc_from_raster,
        raster::ndc_from_raster(cam.width, cam.height),
        "{name}: camera uses raster::ndc_from_raster"
    );
}

/// A screen point's images under the forward film maps.
struct FilmImages {
    /// ndc_from_screen of the point.
    ndc: DVec3,
    /// The expected NDC point, in f32: what raster_from_ndc is given.
    nf: Vec3,
    /// raster_from_ndc of `nf`.
    raster: DVec3,
    /// raster_from_screen of the point.
    composed: DVec3,
}

/// Screen point `p` (number `i`: 0 is the window's top-left corner, 1 its bottom-right one)
/// through ndc_from_screen, raster_from_ndc and raster_from_screen against the window's
/// formulas, the window's half sizes being `hw` and `hh`.
fn check_forward_maps(
    name: &str,
    cam: &Camera,
    r: &RefCam,
    (hw, hh): (f64, f64),
    i: u32,
    p: Vec3,
) -> FilmImages {
    let (x, y, d) = (p.x as f64, p.y as f64, p.z as f64);

    let ndc = cam.ndc_from_screen.transform_point3(p).as_dvec3();
    let expected_ndc = DVec3::new((x + hw) / (2.0 * hw), (hh - y) / (2.0 * hh), d);
    assert_vec_close(
        &format!("{name}: ndc_from_screen of {p:?}"),
        ndc,
        expected_ndc,
        2e-6,
    );
    let nf = expected_ndc.as_vec3();
    let raster = cam.raster_from_ndc.transform_point3(nf).as_dvec3();
    let expected_raster = DVec3::new(r.width * nf.x as f64, r.height * nf.y as f64, d);
    assert_vec_close(
        &format!("{name}: raster_from_ndc of {nf:?}"),
        raster,
        expected_raster,
        1e-6 * r.width.max(r.height),
    );
    let composed = cam.raster_from_screen.transform_point3(p).as_dvec3();
    let expected = DVec3::new(
        (1.0 + x / hw) * r.width / 2.0,
        (1.0 - y / hh) * r.height / 2.0,
        d,
    );
    assert_vec_close(
        &format!("{name}: raster_from_screen of {p:?}"),
        composed,
        expected,
        2e-6 * r.width.max(r.height),
    );
    if i == 0 {
        assert_vec_close(
            &format!("{name}: top-left of the window is raster (0, 0)"),
            composed,
            DVec3::new(0.0, 0.0, d),
            1e-4,
        );
    }
    if i == 1 {
        assert_vec_close(
            &format!("{name}: bottom-right of the window is raster (W, H)"),
            composed,
            DVec3::new(r.width, r.height, d),
            1e-4,
        );
    }
    FilmImages {
        ndc,
        nf,
        raster,
        composed,
    }
}

/// The reverse film maps take screen point `p`'s images back (window half sizes `hw`, `hh`).
fn check_reverse_maps(name: &str, cam: &Camera, (hw, hh): (f64, f64), p: Vec3, at: &FilmImages) {
    let (x, y, d) = (p.x as f64, p.y as f64, p.z as f64);
    let FilmImages {
        ndc,
        nf,
        raster,
        composed,
    } = *at;
    let back = cam
        .screen_from_raster
        .transform_point3(composed.as_vec3())
        .as_dvec3();
    assert_vec_close(
        &format!("{name}: screen_from_raster(raster_from_screen({p:?}))"),
        back,
        DVec3::new(x, y, d),
        4e-6 * hw.max(hh).max(1.0),
    );
    let back_ndc = cam
        .screen_from_ndc
        .transform_point3(ndc.as_vec3())
        .as_dvec3();
    assert_vec_close(
        &format!("{name}: screen_from_ndc(ndc_from_screen({p:?}))"),
        back_ndc,
        DVec3::new(x, y, d),
        4e-6 * hw.max(hh).max(1.0),
    );
    let back_raster = cam
        .ndc_from_raster
        .transform_point3(raster.as_vec3())
        .as_dvec3();
    assert_vec_close(
        &format!("{name}: ndc_from_raster(raster_from_ndc({nf:?}))"),
        back_raster,
        nf.as_dvec3(),
        2e-6,
    );
}

/// Screen -> NDC -> raster for each sample camera (non-square images included): the screen
/// window is [-s a, s a] x [-s, s], NDC = ((x + s a) / (2 s a), (s - y) / (2 s)), raster =
/// (W u, H v); depth passes through unchanged; the reverse maps are the inverses.
#[test]
fn film_matrices_match_screen_window_formulas() {
    let mut rng = Rng::new(2);
    for setup in setups() {
        let cam = setup.camera();
        let r = setup.reference();
        let name = setup.name;
        let (hw, hh) = (r.s * r.aspect(), r.s);
        check_screen_window(name, &cam, hw, hh);

        for i in 0..300 {
            // The window's corners first, then random points (some outside the window).
            let (x, y) = match i {
                0 => (-hw, hh),
                1 => (hw, -hh),
                2 => (0.0, 0.0),
                _ => (rng.range(-1.3, 1.3) * hw, rng.range(-1.3, 1.3) * hh),
            };
            let d = rng.f64();
            let p = Vec3::new(x as f32, y as f32, d as f32);
            let images = check_forward_maps(name, &cam, &r, (hw, hh), i, p);
            check_reverse_maps(name, &cam, (hw, hh), p, &images);
        }
        assert_identity(
            &format!("{name}: raster_from_screen * screen_from_raster"),
            &(cam.raster_from_screen * cam.screen_from_raster),
            // The translation column is in pixels: a few ulps of the image size.
            4.0 * f32::EPSILON as f64 * r.width.max(r.height),
        );
    }
}

/// The composed world -> raster matrix (and `Camera::project`) against the explicit
/// formula, for many random world points, both models, non-square images.
#[test]
fn raster_from_world_matches_explicit_projection_formula() {
    let mut rng = Rng::new(3);
    for setup in setups() {
        let cam = setup.camera();
        let r = setup.reference();
        let name = setup.name;
        let m = cam.raster_from_world();
        for _ in 0..2000 {
            let p = r.random_point(&mut rng, 1.2).as_vec3();
            let pd = p.as_dvec3();
            let (px_tol, depth_tol) = r.raster_tolerance(pd);
            let expected = r.raster(pd);
            let c = r.camera_coords(pd);

            let cam_space = cam.camera_from_world.transform_point3(p).as_dvec3();
            assert_vec_close(
                &format!("{name}: camera_from_world of {p:?}"),
                cam_space,
                c,
                2e-6 * (pd - r.eye).length().max(1.0),
            );
            assert_rel(
                &format!("{name}: view_depth of {p:?}"),
                cam.view_depth(p) as f64,
                c.z,
                1e-5,
            );

            let h: Vec4 = m * p.extend(1.0);
            let expected_w = r.divisor(c.z);
            assert_rel(
                &format!("{name}: homogeneous w of raster_from_world * {p:?}"),
                h.w as f64,
                expected_w,
                1e-5,
            );
            let projected = cam.project(p).as_dvec3();
            let via_matrix = (h.truncate() / h.w).as_dvec3();
            for (what, got) in [("project", projected), ("raster_from_world", via_matrix)] {
                let label = format!("{name}: {what} of {p:?} (camera {c:?})");
                assert_close(&format!("{label}: column"), got.x, expected.x, px_tol);
                assert_close(&format!("{label}: row"), got.y, expected.y, px_tol);
                assert_close(&format!("{label}: depth"), got.z, expected.z, depth_tol);
            }
        }
    }
}

/// The Vulkan clip matrix is the same chain: clip = 2 ndc - 1 in x and y, depth unchanged.
#[test]
fn clip_from_world_is_ndc_rescaled() {
    let mut rng = Rng::new(4);
    for setup in setups() {
        let cam = setup.camera();
        let r = setup.reference();
        for _ in 0..200 {
            let p = r.random_point(&mut rng, 1.2).as_vec3();
            let expected = r.raster(p.as_dvec3());
            let (clip, _) = transform_h(&cam.clip_from_world(), p);
            let want = DVec3::new(
                2.0 * expected.x / r.width - 1.0,
                2.0 * expected.y / r.height - 1.0,
                expected.z,
            );
            assert_vec_close(
                &format!("{}: clip_from_world of {p:?}", setup.name),
                clip.as_dvec3(),
                want,
                1e-4,
            );
        }
    }
}
