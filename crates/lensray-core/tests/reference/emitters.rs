//! Emissive triangles as lights: a white Lambert wall lit only by an emissive rectangle between
//! it and the camera reflects a / pi E, E from Lambert's formula for a polygonal luminaire.
//!
//! The rectangle is single-sided and faces the wall, so camera rays pass through its back and
//! only the wall is seen. With one bounce the emitters' draw alone lights the wall; with two,
//! that draw and the BRDF's draw that meets the rectangle share the light by multiple
//! importance sampling, so both must give the same E.

use std::f32::consts::PI;

use glam::{UVec2, Vec3};
use lensray_core::camera::LensParams;
use lensray_core::reference::Renderer;
use lensray_core::sampler::camera_sample;
use lensray_core::scene::{Material, Mesh, Scene};
use lensray_core::settings::{Shading, Shot};

use crate::{camera, material, quad};

/// The wall's plane, world z; it faces the camera (+z).
const WALL: f32 = -2.0;
/// The emitter's plane, world z: one unit in front of the wall.
const EMITTER: f32 = -1.0;
/// Half the emitter's width (x) and height (y).
const HALF: (f32, f32) = (0.5, 0.3);
/// The emitter's radiance.
const RADIANCE: f32 = 2.0;
/// The wall's albedo.
const ALBEDO: f32 = 0.5;

/// Irradiance at `p` (normal `n`) from a polygon of radiance `l` whose vertices `v` all lie
/// above `p`'s plane: Lambert's formula E = L / 2 sum_i beta_i cos gamma_i, with beta_i the angle
/// edge i subtends at `p` and gamma_i the angle between `n` and the normal of the plane through
/// `p` and the edge.
fn polygon_irradiance(p: Vec3, n: Vec3, v: &[Vec3], l: f32) -> f32 {
    let mut sum = 0.0f64;
    for i in 0..v.len() {
        let a = (v[i] - p).normalize().as_dvec3();
        let b = (v[(i + 1) % v.len()] - p).normalize().as_dvec3();
        let beta = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += beta * a.cross(b).normalize().dot(n.as_dvec3());
    }
    (0.5 * f64::from(l) * sum.abs()) as f32
}

/// The irradiance on the axis of a centred a x b rectangle at distance c (four corner
/// rectangles' form factors; E = pi L F).
fn axis_irradiance(half_a: f32, half_b: f32, c: f32, l: f32) -> f32 {
    let (a, b) = (f64::from(half_a / c), f64::from(half_b / c));
    let (sa, sb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
    let f = a / sa * (b / sa).atan() + b / sb * (a / sb).atan();
    (2.0 * f64::from(l) * f) as f32
}

/// The emitter's corners, counter-clockwise seen from the wall (its front faces -z).
fn emitter_corners() -> [Vec3; 4] {
    let (w, h) = HALF;
    [
        Vec3::new(-w, -h, EMITTER),
        Vec3::new(-w, h, EMITTER),
        Vec3::new(w, h, EMITTER),
        Vec3::new(w, -h, EMITTER),
    ]
}

fn scene() -> Scene {
    let emitter = Mesh {
        name: "emitter".into(),
        positions: emitter_corners().to_vec(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![1; 2],
        ..Default::default()
    };
    Scene {
        meshes: vec![quad(-50.0, 50.0, -50.0, 50.0, WALL, 0), emitter],
        materials: vec![
            material("wall", Vec3::splat(ALBEDO), Vec3::ZERO),
            Material {
                double_sided: false,
                ..material("emitter", Vec3::ZERO, Vec3::splat(RADIANCE))
            },
        ],
        ..Default::default()
    }
}

/// The worst relative error of an 8 x 8 render (`bounces`, `spp`) against a / pi E at each
/// sample's point on the wall, averaged over the pixel's samples, and the mean signed one.
fn errors(bounces: u32, spp: u32) -> (f32, f32) {
    let (width, height) = (8, 8);
    let mut render = crate::settings(Shading::Lit, spp);
    render.bounces = bounces;
    let shot = Shot {
        camera: camera(width, height, LensParams::Pinhole),
        render,
    };
    let (image, _) = Renderer::new(&scene()).render(&shot, &mut |_, _| {});
    let corners = emitter_corners();
    let (mut worst, mut mean) = (0.0f32, 0.0f32);
    for row in 0..height {
        for col in 0..width {
            let mut expected = 0.0;
            for i in 0..spp {
                let s = camera_sample(render.sampler, render.seed, UVec2::new(col, row), width, i);
                let ray = shot.camera.first_order_ray(s);
                let p = ray.at((WALL - ray.origin.z) / ray.direction.z);
                expected += ALBEDO / PI * polygon_irradiance(p, Vec3::Z, &corners, RADIANCE);
            }
            expected /= spp as f32;
            let got = image.get(col, row);
            assert!(
                (got.x - got.y).abs() < 1e-6 && (got.x - got.z).abs() < 1e-6,
                "grey light gives grey pixels: {got}"
            );
            let error = got.x / expected - 1.0;
            worst = worst.max(error.abs());
            mean += error / (width * height) as f32;
        }
    }
    println!("bounces {bounces}, {spp} spp: worst {worst:+.5}, mean {mean:+.5}");
    (worst, mean)
}

#[test]
fn lamberts_polygon_formula_is_the_closed_form_on_the_axis() {
    let p = Vec3::new(0.0, 0.0, WALL);
    let polygon = polygon_irradiance(p, Vec3::Z, &emitter_corners(), RADIANCE);
    let closed = axis_irradiance(HALF.0, HALF.1, EMITTER - WALL, RADIANCE);
    assert!(
        (polygon / closed - 1.0).abs() < 1e-5,
        "polygon {polygon}, closed form {closed}"
    );
    // Test set-up: a rectangle that covers a good part of the wall's hemisphere.
    assert!(closed > 0.3 * RADIANCE, "E = {closed}");
}

#[test]
fn an_emissive_rectangle_lights_a_lambert_wall_by_the_emitters_draw() {
    let (worst, mean) = errors(1, 1024);
    assert!(worst < 0.01, "worst relative error {worst}");
    assert!(mean.abs() < 0.002, "mean relative error {mean}");
}

#[test]
fn the_emitters_and_the_brdfs_draws_share_the_light_by_mis() {
    let (worst, mean) = errors(2, 1024);
    assert!(worst < 0.01, "worst relative error {worst}");
    assert!(mean.abs() < 0.002, "mean relative error {mean}");
}
