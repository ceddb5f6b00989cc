//! 9. `CameraParams::build` rejects bad parameters with the matching error.

use glam::Vec3;
use lensray_core::camera::params::MAX_IMAGE_SIDE;
use lensray_core::camera::{CameraError, CameraParams, LensParams, ProjectionParams};

fn perspective() -> CameraParams {
    CameraParams {
        eye: Vec3::new(1.0, 2.0, 3.0),
        target: Vec3::new(-1.0, 0.5, -2.0),
        up: Vec3::new(0.1, 1.0, 0.0),
        projection: ProjectionParams::Perspective { vfov_degrees: 45.0 },
        lens: LensParams::ThinLens {
            aperture_radius: 0.1,
            focus_distance: 5.0,
        },
        near: 0.1,
        far: 100.0,
        width: 64,
        height: 48,
        movements: lensray_core::camera::Movements::NONE,
    }
}

fn orthographic() -> CameraParams {
    CameraParams {
        projection: ProjectionParams::Orthographic { height: 2.0 },
        near: 1.0,
        ..perspective()
    }
}

fn thin_lens(aperture_radius: f64, focus_distance: f64) -> LensParams {
    LensParams::ThinLens {
        aperture_radius,
        focus_distance,
    }
}

#[track_caller]
fn rejects(what: &str, params: CameraParams, ok: impl Fn(&CameraError) -> bool, want: &str) {
    match params.build() {
        Ok(cam) => panic!(
            "{what}: build accepted it (expected {want}); camera frame {:?}",
            cam.frame
        ),
        Err(e) => assert!(ok(&e), "{what}: got error {e:?} (\"{e}\"), expected {want}"),
    }
}

#[track_caller]
fn accepts(what: &str, params: CameraParams) {
    if let Err(e) = params.build() {
        panic!("{what}: valid parameters rejected with {e:?} (\"{e}\")");
    }
}

#[test]
fn build_accepts_valid_and_boundary_parameters() {
    accepts("perspective base", perspective());
    accepts("orthographic base", orthographic());
    accepts(
        "pinhole",
        CameraParams {
            lens: LensParams::Pinhole,
            ..perspective()
        },
    );
    accepts(
        "aperture exactly 0",
        CameraParams {
            lens: thin_lens(0.0, 5.0),
            ..perspective()
        },
    );
    accepts(
        "perspective focus closer than near",
        CameraParams {
            lens: thin_lens(0.1, 0.05),
            ..perspective()
        },
    );
    accepts(
        "orthographic focus just beyond near",
        CameraParams {
            lens: thin_lens(0.1, 1.001),
            ..orthographic()
        },
    );
    for vfov_degrees in [0.01, 179.9] {
        accepts(
            &format!("vfov {vfov_degrees}"),
            CameraParams {
                projection: ProjectionParams::Perspective { vfov_degrees },
                ..perspective()
            },
        );
    }
    for (width, height) in [(1, 1), (MAX_IMAGE_SIDE, 1), (1, MAX_IMAGE_SIDE)] {
        accepts(
            &format!("image {width}x{height}"),
            CameraParams {
                width,
                height,
                ..perspective()
            },
        );
    }
    accepts(
        "up not normalised and not perpendicular",
        CameraParams {
            up: Vec3::new(3.0, 7.0, -2.0),
            ..perspective()
        },
    );
}

#[test]
fn build_rejects_non_finite_vectors() {
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
    for x in bad {
        for (field, params) in [
            (
                "eye",
                CameraParams {
                    eye: Vec3::new(1.0, x, 3.0),
                    ..perspective()
                },
            ),
            (
                "target",
                CameraParams {
                    target: Vec3::new(x, 0.0, 0.0),
                    ..perspective()
                },
            ),
            (
                "up",
                CameraParams {
                    up: Vec3::new(0.0, 1.0, x),
                    ..perspective()
                },
            ),
        ] {
            rejects(
                &format!("{field} with a {x} component"),
                params,
                |e| matches!(e, CameraError::NotFinite(name, _) if *name == field),
                &format!("NotFinite(\"{field}\", ..)"),
            );
        }
    }
}

#[test]
fn build_rejects_degenerate_frames() {
    let base = perspective();
    for (what, target) in [
        ("eye == target", base.eye),
        ("target 1e-9 from eye", base.eye + Vec3::splat(1e-9)),
    ] {
        rejects(
            what,
            CameraParams {
                target,
                ..base.clone()
            },
            |e| *e == CameraError::EyeIsTarget,
            "EyeIsTarget",
        );
    }
    let forward = base.target - base.eye;
    for (what, up) in [
        ("up along the view direction", forward),
        ("up opposite the view direction", -3.0 * forward),
        ("up zero", Vec3::ZERO),
        (
            "up parallel to view up to 1e-8",
            forward.normalize() + Vec3::new(0.0, 1e-8, 0.0),
        ),
    ] {
        rejects(
            what,
            CameraParams { up, ..base.clone() },
            |e| *e == CameraError::UpParallelToView(up),
            &format!("UpParallelToView({up:?})"),
        );
    }
}

#[test]
fn build_rejects_bad_field_of_view_and_view_height() {
    for vfov_degrees in [0.0, -10.0, 180.0, 200.0, f64::NAN, f64::INFINITY] {
        rejects(
            &format!("vfov {vfov_degrees} degrees"),
            CameraParams {
                projection: ProjectionParams::Perspective { vfov_degrees },
                ..perspective()
            },
            |e| matches!(e, CameraError::FieldOfView(v) if v.to_bits() == vfov_degrees.to_bits()),
            &format!("FieldOfView({vfov_degrees})"),
        );
    }
    for height in [0.0, -2.0] {
        rejects(
            &format!("orthographic height {height}"),
            CameraParams {
                projection: ProjectionParams::Orthographic { height },
                ..orthographic()
            },
            |e| *e == CameraError::NotPositive("orthographic view height", height),
            "NotPositive(\"orthographic view height\", ..)",
        );
    }
    for height in [f64::NAN, f64::INFINITY] {
        rejects(
            &format!("orthographic height {height}"),
            CameraParams {
                projection: ProjectionParams::Orthographic { height },
                ..orthographic()
            },
            |e| matches!(e, CameraError::NotFinite("orthographic view height", _)),
            "NotFinite(\"orthographic view height\", ..)",
        );
    }
}

#[test]
fn build_rejects_bad_lens() {
    for aperture in [-0.1, -1e-9] {
        rejects(
            &format!("aperture radius {aperture}"),
            CameraParams {
                lens: thin_lens(aperture, 5.0),
                ..perspective()
            },
            |e| *e == CameraError::Negative("aperture radius", aperture),
            "Negative(\"aperture radius\", ..)",
        );
    }
    rejects(
        "aperture radius NaN",
        CameraParams {
            lens: thin_lens(f64::NAN, 5.0),
            ..perspective()
        },
        |e| matches!(e, CameraError::NotFinite("aperture radius", _)),
        "NotFinite(\"aperture radius\", ..)",
    );
    for focus in [0.0, -1.0] {
        rejects(
            &format!("perspective focus distance {focus}"),
            CameraParams {
                lens: thin_lens(0.1, focus),
                ..perspective()
            },
            |e| *e == CameraError::FocusNotInFront { focus, min: 0.0 },
            "FocusNotInFront { min: 0 }",
        );
    }
    // Orthographic rays start on the near plane (1.0 here): focus must lie beyond it.
    for focus in [1.0, 0.5, 0.0, -2.0] {
        rejects(
            &format!("orthographic focus distance {focus} with near 1"),
            CameraParams {
                lens: thin_lens(0.1, focus),
                ..orthographic()
            },
            |e| *e == CameraError::FocusNotInFront { focus, min: 1.0 },
            "FocusNotInFront { min: near = 1 }",
        );
    }
    rejects(
        "focus distance infinite",
        CameraParams {
            lens: thin_lens(0.1, f64::INFINITY),
            ..perspective()
        },
        |e| matches!(e, CameraError::NotFinite("focus distance", _)),
        "NotFinite(\"focus distance\", ..)",
    );
}

#[test]
fn build_rejects_bad_near_far() {
    for near in [0.0, -0.5] {
        rejects(
            &format!("near {near}"),
            CameraParams {
                near,
                ..perspective()
            },
            |e| *e == CameraError::NotPositive("near", near),
            "NotPositive(\"near\", ..)",
        );
    }
    rejects(
        "near NaN",
        CameraParams {
            near: f64::NAN,
            ..perspective()
        },
        |e| matches!(e, CameraError::NotFinite("near", _)),
        "NotFinite(\"near\", ..)",
    );
    rejects(
        "far infinite",
        CameraParams {
            far: f64::INFINITY,
            ..perspective()
        },
        |e| matches!(e, CameraError::NotFinite("far", _)),
        "NotFinite(\"far\", ..)",
    );
    for (near, far) in [(1.0, 1.0), (2.0, 1.0), (0.1, 0.05)] {
        rejects(
            &format!("near {near}, far {far}"),
            CameraParams {
                near,
                far,
                ..perspective()
            },
            |e| *e == CameraError::NearFar { near, far },
            "NearFar",
        );
    }
}

#[test]
fn build_rejects_bad_image_size() {
    for (width, height) in [
        (0, 48),
        (64, 0),
        (0, 0),
        (MAX_IMAGE_SIDE + 1, 48),
        (64, 20_000),
        (u32::MAX, u32::MAX),
    ] {
        rejects(
            &format!("image {width}x{height}"),
            CameraParams {
                width,
                height,
                ..perspective()
            },
            |e| *e == CameraError::ImageSize(width, height),
            &format!("ImageSize({width}, {height})"),
        );
    }
    assert_eq!(MAX_IMAGE_SIDE, 16384, "the documented limit");
}

/// A vfov whose f32 half angle reaches pi/2 (or underflows) is rejected; the largest one still
/// fine in f32 builds a positive, finite window.
fn check_vfov_degenerate_in_f32() {
    for vfov_degrees in [179.999_999, 179.999_999_9, 1e-50] {
        let params = CameraParams {
            projection: ProjectionParams::Perspective { vfov_degrees },
            ..perspective()
        };
        if let Ok(cam) = params.build() {
            panic!(
                "vfov {vfov_degrees} degrees accepted: screen half height {} (tan of the f32 \
                 half angle), expected FieldOfView({vfov_degrees})",
                cam.screen_window.half_height
            );
        }
        rejects(
            &format!("vfov {vfov_degrees} degrees"),
            params,
            |e| *e == CameraError::FieldOfView(vfov_degrees),
            &format!("FieldOfView({vfov_degrees})"),
        );
    }
    // The largest vfov still fine in f32 is accepted, with a positive, finite window.
    let cam = CameraParams {
        projection: ProjectionParams::Perspective {
            vfov_degrees: 179.999_9,
        },
        ..perspective()
    }
    .build()
    .expect("vfov 179.9999 degrees");
    // tan(90 - 5e-5 degrees) = 1.146e6; its f32 value is off by up to ~20% because the half
    // angle is within a few ulps of pi/2 (the ulp of 1.57 is 1.2e-7 rad, the distance 8.7e-7), so
    // only its sign, finiteness and order of magnitude are the camera's to get right.
    let hh = cam.screen_window.half_height as f64;
    let expected = (0.5 * 179.999_9f64.to_radians()).tan();
    assert!(
        hh.is_finite() && hh > 0.5 * expected && hh < 2.0 * expected,
        "vfov 179.9999: half height {hh}, expected about {expected}"
    );
}

/// Near, far and the orthographic height that underflow, overflow or become equal in f32 are
/// rejected.
fn check_distances_degenerate_in_f32() {
    for near in [1e-50, 1e-46] {
        rejects(
            &format!("near {near} (0 in f32)"),
            CameraParams {
                near,
                lens: thin_lens(0.1, 5.0),
                ..perspective()
            },
            |e| *e == CameraError::NotPositive("near", near),
            "NotPositive(\"near\", ..)",
        );
    }
    rejects(
        "far 1e39 (infinite in f32)",
        CameraParams {
            far: 1e39,
            ..perspective()
        },
        |e| matches!(e, CameraError::NotFinite("far", _)),
        "NotFinite(\"far\", ..)",
    );
    let (near, far) = (1.0, 1.0 + 1e-9);
    rejects(
        "near 1, far 1 + 1e-9 (equal in f32)",
        CameraParams {
            near,
            far,
            ..perspective()
        },
        |e| *e == CameraError::NearFar { near, far },
        "NearFar",
    );
    rejects(
        "orthographic height 1e-50 (0 in f32)",
        CameraParams {
            projection: ProjectionParams::Orthographic { height: 1e-50 },
            ..orthographic()
        },
        |e| *e == CameraError::NotPositive("orthographic view height", 1e-50),
        "NotPositive(\"orthographic view height\", 1e-50)",
    );
    rejects(
        "orthographic height 1e39 (infinite in f32)",
        CameraParams {
            projection: ProjectionParams::Orthographic { height: 1e39 },
            ..orthographic()
        },
        |e| matches!(e, CameraError::NotFinite("orthographic view height", _)),
        "NotFinite(\"orthographic view height\", ..)",
    );
}

/// A lens whose aperture radius or focus distance overflows in f32, or whose focus distance is
/// no longer in front of the camera once in f32 (0, or the near distance), is rejected.
fn check_lens_degenerate_in_f32() {
    rejects(
        "aperture radius 1e39 (infinite in f32)",
        CameraParams {
            lens: thin_lens(1e39, 5.0),
            ..perspective()
        },
        |e| matches!(e, CameraError::NotFinite("aperture radius", _)),
        "NotFinite(\"aperture radius\", ..)",
    );
    rejects(
        "focus distance 1e39 (infinite in f32)",
        CameraParams {
            lens: thin_lens(0.1, 1e39),
            ..perspective()
        },
        |e| matches!(e, CameraError::NotFinite("focus distance", _)),
        "NotFinite(\"focus distance\", ..)",
    );
    let focus = 1e-50;
    rejects(
        "perspective focus distance 1e-50 (0 in f32)",
        CameraParams {
            lens: thin_lens(0.1, focus),
            ..perspective()
        },
        |e| *e == CameraError::FocusNotInFront { focus, min: 0.0 },
        "FocusNotInFront { min: 0 }",
    );
    let focus = 1.0 + 1e-12;
    rejects(
        "orthographic focus distance near + 1e-12 (= near in f32)",
        CameraParams {
            lens: thin_lens(0.1, focus),
            ..orthographic()
        },
        |e| *e == CameraError::FocusNotInFront { focus, min: 1.0 },
        "FocusNotInFront { min: near = 1 }",
    );
}

/// The camera is built in f32 from f64 parameters: values that pass the f64 checks but are
/// degenerate once converted (a vfov whose f32 half angle passes pi/2, values that underflow to
/// 0 or overflow to infinity, near and far that become equal) must be rejected too, not turned
/// into a mirrored image or infinite matrices.
#[test]
fn build_rejects_values_degenerate_in_f32() {
    check_vfov_degenerate_in_f32();
    check_distances_degenerate_in_f32();
    check_lens_degenerate_in_f32();
}
