//! 8. Physical units: focal length, f-number and sensor height in mm, distances in metres.

use glam::Vec3;
use lensray_core::camera::physical::PhysicalLens;
use lensray_core::camera::{CameraError, CameraParams, LensParams, Projection, ProjectionParams};

use crate::common::*;

const LENS_50_F2: PhysicalLens = PhysicalLens {
    focal_length_mm: 50.0,
    f_number: 2.0,
    sensor_height_mm: 24.0,
};

fn physical_params(lens: PhysicalLens, focus_distance: f64) -> CameraParams {
    CameraParams {
        eye: Vec3::new(0.0, 1.5, 4.0),
        target: Vec3::new(0.5, 1.0, 0.0),
        up: Vec3::Y,
        // Deliberately inconsistent: a physical lens sets the field of view itself.
        projection: ProjectionParams::Perspective { vfov_degrees: 90.0 },
        lens: LensParams::Physical {
            lens,
            focus_distance,
        },
        near: 0.01,
        far: 100.0,
        width: 1500,
        height: 1000,
        movements: lensray_core::camera::Movements::NONE,
    }
}

/// Hand-computed values (independently, in double precision):
/// - 50 mm f/2: aperture diameter 25 mm, radius 12.5 mm = 0.0125 m;
/// - focus 2 m: s_i = 1 / (1/50 - 1/2000) = 51.282051282 mm;
/// - 24 mm sensor: vfov = 2 atan(12 / 51.282051282) = 0.459728168807 rad, tan(vfov/2) = 0.234;
/// - 35 mm f/1.4 at 1 m: radius 0.0125 m, s_i = 36.269430052 mm;
/// - 85 mm f/8 at 10 m: radius 0.0053125 m, s_i = 85.728693898 mm.
#[test]
fn physical_lens_matches_hand_computed_values() {
    let lens = LENS_50_F2;
    assert_rel(
        "50 mm f/2 aperture radius (m)",
        lens.aperture_radius(),
        0.0125,
        1e-12,
    );
    let s_i = lens
        .film_distance_mm(2.0)
        .expect("focus 2 m forms an image");
    assert_rel(
        "50 mm focused at 2 m: film distance (mm)",
        s_i,
        51.282051282051285,
        1e-12,
    );
    let vfov = lens.vfov(2.0).expect("focus 2 m forms an image");
    assert_rel(
        "50 mm, 24 mm sensor at 2 m: vfov (rad)",
        vfov,
        0.45972816880671835,
        1e-12,
    );
    assert_rel("tan(vfov / 2)", (vfov / 2.0).tan(), 0.234, 1e-12);

    let lens35 = PhysicalLens {
        focal_length_mm: 35.0,
        f_number: 1.4,
        sensor_height_mm: 36.0,
    };
    assert_rel(
        "35 mm f/1.4 aperture radius",
        lens35.aperture_radius(),
        0.0125,
        1e-12,
    );
    assert_rel(
        "35 mm at 1 m: film distance",
        lens35.film_distance_mm(1.0).unwrap(),
        36.26943005181347,
        1e-12,
    );
    assert_rel(
        "35 mm, 36 mm sensor at 1 m: vfov",
        lens35.vfov(1.0).unwrap(),
        0.9213435359022276,
        1e-12,
    );
    let lens85 = PhysicalLens {
        focal_length_mm: 85.0,
        f_number: 8.0,
        sensor_height_mm: 24.0,
    };
    assert_rel(
        "85 mm f/8 aperture radius",
        lens85.aperture_radius(),
        0.0053125,
        1e-12,
    );
    assert_rel(
        "85 mm at 10 m: film distance",
        lens85.film_distance_mm(10.0).unwrap(),
        85.72869389813414,
        1e-12,
    );

    // At or inside the focal length no real image forms.
    for focus in [0.05, 0.03, 0.0, -1.0] {
        assert_eq!(
            lens.film_distance_mm(focus),
            None,
            "50 mm lens focused at {focus} m"
        );
        assert_eq!(lens.vfov(focus), None, "50 mm lens focused at {focus} m");
    }
    assert!(lens.film_distance_mm(0.0501).is_some(), "just beyond f");
}

#[test]
fn build_with_physical_lens() {
    let cam = physical_params(LENS_50_F2, 2.0).build().unwrap();
    assert_rel(
        "camera aperture radius",
        cam.lens.first_order().aperture_radius as f64,
        0.0125,
        1e-7,
    );
    assert_rel(
        "camera focus distance",
        cam.lens.first_order().focus_distance as f64,
        2.0,
        1e-7,
    );
    match cam.projection {
        Projection::Perspective { vfov } => {
            assert_rel("camera vfov (rad)", vfov as f64, 0.45972816880671835, 1e-6)
        }
        other => panic!("physical perspective camera has projection {other:?}"),
    }
    assert_rel(
        "screen half height = 12 / 51.282051",
        cam.screen_window.half_height as f64,
        0.234,
        1e-6,
    );
    assert_rel(
        "screen half width = 0.234 * 1.5",
        cam.screen_window.half_width as f64,
        0.351,
        1e-6,
    );

    // Circle of confusion on the sensor, from the photographic formula
    // c = (f / N) |z - F| / z * f / (F - f) (diameter, mm): for 50 mm f/2 focused at 2 m,
    // z = 1 m: 0.641025641 mm, z = 4 m: 0.320512821 mm, z = 1.5 m: 0.213675214 mm. In pixels:
    // radius / sensor height * image height.
    for (z, diameter_mm) in [
        (1.0, 0.6410256410256411),
        (4.0, 0.32051282051282054),
        (1.5, 0.2136752136752137),
    ] {
        let expected_px = diameter_mm / 2.0 / 24.0 * 1000.0;
        assert_rel(
            &format!("coc_radius_pixels at {z} m for 50 mm f/2 focused at 2 m"),
            cam.coc_radius_pixels(glam::Vec2::ZERO, z as f32) as f64,
            expected_px,
            1e-5,
        );
    }

    // Orthographic with a physical lens: aperture and focus apply, the view height stays.
    let mut ortho = physical_params(LENS_50_F2, 2.0);
    ortho.projection = ProjectionParams::Orthographic { height: 3.0 };
    let cam = ortho.build().unwrap();
    assert_eq!(cam.projection, Projection::Orthographic { height: 3.0 });
    assert_rel(
        "ortho aperture radius",
        cam.lens.first_order().aperture_radius as f64,
        0.0125,
        1e-7,
    );
}

#[test]
fn build_rejects_bad_physical_lens() {
    // Focus inside (or at) the focal length.
    for focus in [0.03, 0.05] {
        let result = physical_params(LENS_50_F2, focus).build();
        assert_eq!(
            result.as_ref().err(),
            Some(&CameraError::FocusWithinFocalLength {
                focus,
                focal_length_mm: 50.0
            }),
            "50 mm lens focused at {focus} m"
        );
    }
    let bad = |lens: PhysicalLens| physical_params(lens, 2.0).build().err();
    for (name, lens, field, value) in [
        (
            "focal length 0",
            PhysicalLens {
                focal_length_mm: 0.0,
                ..LENS_50_F2
            },
            "focal length (mm)",
            0.0,
        ),
        (
            "f-number -2",
            PhysicalLens {
                f_number: -2.0,
                ..LENS_50_F2
            },
            "f-number",
            -2.0,
        ),
        (
            "sensor height 0",
            PhysicalLens {
                sensor_height_mm: 0.0,
                ..LENS_50_F2
            },
            "sensor height (mm)",
            0.0,
        ),
    ] {
        assert_eq!(
            bad(lens),
            Some(CameraError::NotPositive(field, value)),
            "physical lens with {name}"
        );
    }
    let nan = bad(PhysicalLens {
        f_number: f64::NAN,
        ..LENS_50_F2
    });
    assert!(
        matches!(nan, Some(CameraError::NotFinite("f-number", _))),
        "f-number NaN gave {nan:?}"
    );
}
