//! Scheimpflug: a lens tilted to lay its plane of focus on a receding floor renders every row
//! of the floor sharp at f/2, where the untilted lens blurs the near and far rows by pixels.

use glam::{DVec3, Vec2, Vec3};
use lensray_core::camera::movements::TiltModel;
use lensray_core::camera::physical::PhysicalLens;
use lensray_core::camera::{Camera, CameraParams, FocusPlane, LensParams, Movements};
use lensray_core::camera::{ProjectionParams, Ray};
use lensray_core::reference::Renderer;
use lensray_core::scene::{Mesh, Scene};
use lensray_core::settings::{Shading, Shot};

use crate::{edge_fit, material, settings};
use lensray_core::sampler::CameraSample;

const WIDTH: u32 = 256;
const HEIGHT: u32 = 192;
const FOCAL_LENGTH_MM: f64 = 100.0;
/// Rows per profile the edge is fitted to.
const BAND: u32 = 8;

/// The floor y = 0, black for x < 0 and white for x > 0, from 0.5 m to 40 m ahead.
fn floor() -> Scene {
    let half = |x0: f32, x1: f32, material: u32| Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "floor".into(),
        positions: vec![
            Vec3::new(x0, 0.0, -0.5),
            Vec3::new(x1, 0.0, -0.5),
            Vec3::new(x1, 0.0, -40.0),
            Vec3::new(x0, 0.0, -40.0),
        ],
        triangles: vec![[0, 2, 1], [0, 3, 2]],
        material_ids: vec![material; 2],
        ..Default::default()
    };
    Scene {
        meshes: vec![half(-5.0, 0.0, 0), half(0.0, 5.0, 1)],
        materials: vec![
            material("black", Vec3::ZERO, Vec3::ZERO),
            material("white", Vec3::ONE, Vec3::ZERO),
        ],
        ..Default::default()
    }
}

/// A 100 mm f/2 lens 0.3 m above the floor looking down along -z, so the floor's edge x = 0
/// runs down the image's middle column, from about 1 m (bottom rows) to 8 m (top rows).
fn camera(focus_distance: f64, movements: Movements) -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, 0.3, 0.0),
        target: Vec3::new(0.0, 0.3 - (9.0f32).to_radians().tan(), -1.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 40.0 },
        lens: LensParams::Physical {
            lens: PhysicalLens {
                focal_length_mm: FOCAL_LENGTH_MM,
                f_number: 2.0,
                sensor_height_mm: 24.0,
            },
            focus_distance,
        },
        near: 0.01,
        far: 100.0,
        width: WIDTH,
        height: HEIGHT,
        movements,
    }
    .build()
    .expect("valid camera")
}

/// The camera-space point of the surface under pixel `pixel`'s centre (the aperture-centre
/// ray, as `--focus-plane` finds it).
fn surface_point(renderer: &Renderer, cam: &Camera, pixel: [u32; 2]) -> DVec3 {
    let centre = Vec2::new(pixel[0] as f32 + 0.5, pixel[1] as f32 + 0.5);
    let ray: Ray = cam.first_order_ray(CameraSample::new(centre, Vec2::splat(0.5)));
    let hit = renderer
        .intersect(&ray)
        .expect("the floor is under every test pixel");
    cam.camera_point(centre, cam.view_depth(ray.at(hit.t)))
        .as_dvec3()
}

/// The blur radius (pixels) fitted to the edge in each band of rows.
fn band_blurs(renderer: &Renderer, cam: &Camera) -> Vec<(u32, f64)> {
    let shot = Shot {
        camera: cam.clone(),
        render: settings(Shading::Unlit, 256),
    };
    let (image, _) = renderer.render(&shot, &mut |_, _| {});
    // Columns around the edge: wide enough for the blur of the untilted lens.
    let (lo, hi) = (WIDTH / 2 - 24, WIDTH / 2 + 24);
    (0..HEIGHT / BAND)
        .map(|band| {
            let rows = band * BAND..(band + 1) * BAND;
            let profile: Vec<f64> = (lo..hi)
                .map(|c| rows.clone().map(|r| image.get(c, r).x as f64).sum::<f64>() / 8.0)
                .collect();
            (band * BAND, edge_fit::fit(&profile).radius)
        })
        .collect()
}

#[test]
fn a_plane_of_focus_laid_on_the_floor_makes_every_row_sharp() {
    let scene = floor();
    let renderer = Renderer::new(&scene);
    let flat = camera(2.0, Movements::NONE);
    // Three floor points, as `--focus-plane 40,176 216,176 128,16` picks them.
    let pixels = [[40, 176], [216, 176], [128, 16]];
    let points = pixels.map(|p| surface_point(&renderer, &flat, p));
    let f = FOCAL_LENGTH_MM / 1000.0;
    let plane = FocusPlane::through(points, TiltModel::FocalLength(f)).expect("a plane");
    let tilted = camera(
        plane.focus_distance,
        Movements {
            tilt_degrees: plane.tilt_degrees,
            tilt_direction_degrees: plane.tilt_direction_degrees,
            ..Movements::NONE
        },
    );
    println!("{plane:?}");
    // The plane passes through the three points...
    let lens = tilted.lens.first_order();
    let normal = lens.focus_tilt.as_dvec2().extend(1.0);
    for p in points {
        let miss = (normal.dot(p) - f64::from(lens.focus_distance)).abs() / normal.length();
        assert!(miss < 1e-3, "the plane misses {p:?} by {miss:.2e}");
    }
    // ... lies like the ground (hinge below) and obeys the hinge rule, J = f / sin(tilt).
    assert!(plane.tilt_direction_degrees.abs() < 1e-3 || plane.tilt_direction_degrees > 359.999);
    let hinge = f64::from(lens.focus_distance) / f64::from(lens.focus_tilt.length());
    let rule = f / plane.tilt_degrees.to_radians().sin();
    assert!(
        (hinge - rule).abs() < 1e-5 * rule,
        "hinge {hinge} m, f / sin(tilt) {rule} m"
    );
    // The floor is 0.3 m below the lens: the hinge lies on it.
    assert!(
        (hinge - 0.3 / (9.0f64).to_radians().cos()).abs() < 0.01,
        "hinge {hinge}"
    );

    let flat_blurs = band_blurs(&renderer, &flat);
    let tilted_blurs = band_blurs(&renderer, &tilted);
    for ((row, b_flat), (_, b_tilted)) in flat_blurs.iter().zip(&tilted_blurs) {
        println!("rows {row}..: untilted {b_flat:.2} px, on the floor {b_tilted:.2} px");
    }
    let (nearest, farthest) = (flat_blurs[flat_blurs.len() - 1].1, flat_blurs[0].1);
    assert!(
        nearest > 5.0 && farthest > 5.0,
        "the untilted lens must blur the near ({nearest:.2} px) and far ({farthest:.2} px) rows"
    );
    for (row, blur) in tilted_blurs {
        assert!(
            blur < 0.5,
            "rows {row}..: edge blur {blur:.2} px on the plane of focus"
        );
    }
}
