//! What a pixel shows: unlit colour, Lambert shading with the inverse square law, the depth
//! AOV, and renders that repeat exactly.

use glam::{Vec2, Vec3};
use lensray_core::camera::LensParams;
use lensray_core::reference::Renderer;
use lensray_core::scene::{Light, Material, Scene};
use lensray_core::settings::{Shading, Shot};

use crate::{camera, material, quad, settings};

#[test]
fn unlit_shows_diffuse_colour_and_background() {
    let red = Vec3::new(0.9, 0.1, 0.1);
    // Left half of the view covered by a red wall at z = -5.
    let scene = Scene {
        meshes: vec![quad(-10.0, 0.0, -10.0, 10.0, -5.0, 0)],
        materials: vec![material("red", red, Vec3::ZERO)],
        ..Default::default()
    };
    let shot = Shot {
        camera: camera(32, 24, LensParams::Pinhole),
        render: settings(Shading::Unlit, 4),
    };
    let s = &shot.render;
    let (image, stats) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    assert_eq!(stats.rays, 32 * 24 * 4);
    for row in 0..24 {
        assert_eq!(image.get(5, row), red, "left pixel ({row})");
        assert_eq!(image.get(26, row), s.background, "right pixel ({row})");
    }
}

#[test]
fn lit_matches_lambert_with_inverse_square() {
    // A white wall at z = -4, facing the camera; light at (1, 0.5, -1), intensity 10 W/sr.
    let kd = Vec3::new(0.5, 0.6, 0.7);
    let ke = Vec3::new(0.01, 0.02, 0.03);
    let light = Light::point(Vec3::new(1.0, 0.5, -1.0), Vec3::splat(10.0));
    let scene = Scene {
        meshes: vec![quad(-50.0, 50.0, -50.0, 50.0, -4.0, 0)],
        materials: vec![material("wall", kd, ke)],
        lights: vec![light],
        ..Default::default()
    };
    let s = settings(Shading::Lit, 1);
    let shot = Shot {
        camera: camera(16, 16, LensParams::Pinhole),
        render: s,
    };
    let cam = &shot.camera;
    let renderer = Renderer::new(&scene);
    let (image, _) = renderer.render(&shot, &mut |_, _| {});
    let mut worst = 0.0f32;
    for row in 0..16 {
        for col in 0..16 {
            // Recompute the sample's hit point with the same sampler, then the formula by hand.
            let sample = lensray_core::sampler::camera_sample(
                s.sampler,
                s.seed,
                glam::UVec2::new(col, row),
                16,
                0,
            );
            let ray = cam.first_order_ray(sample);
            let t = (-4.0 - ray.origin.z) / ray.direction.z;
            let p = ray.at(t);
            let to_light = light.position - p;
            let d2 = to_light.length_squared();
            let cos = to_light.normalize().z.max(0.0); // wall normal facing the camera is +z
            let expected = ke + kd / std::f32::consts::PI * light.intensity * cos / d2;
            let got = image.get(col, row);
            worst = worst.max(((got - expected) / expected).abs().max_element());
        }
    }
    assert!(
        worst < 1e-3,
        "worst relative error against Lambert: {worst}"
    );
}

#[test]
fn depth_aov_is_distance_along_view_axis() {
    let scene = Scene {
        meshes: vec![quad(-50.0, 50.0, -50.0, 50.0, -7.5, 0)],
        materials: vec![Material::default()],
        ..Default::default()
    };
    let shot = Shot {
        camera: camera(20, 10, LensParams::Pinhole),
        render: settings(Shading::Depth, 2),
    };
    let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    let worst = image
        .pixels
        .iter()
        .map(|d| (d.x - 7.5).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "depth differs from 7.5 by up to {worst}");
}

#[test]
fn renders_are_deterministic() {
    let scene = Scene {
        meshes: vec![quad(-1.0, 1.0, -1.0, 1.0, -3.0, 0)],
        materials: vec![Material::default()],
        ..Default::default()
    };
    let shot = Shot {
        camera: camera(
            24,
            16,
            LensParams::ThinLens {
                aperture_radius: 0.1,
                focus_distance: 2.0,
            },
        ),
        render: settings(Shading::Lit, 8),
    };
    let r = Renderer::new(&scene);
    let (a, _) = r.render(&shot, &mut |_, _| {});
    let (b, _) = r.render(&shot, &mut |_, _| {});
    assert_eq!(a, b);
    let _ = Vec2::ZERO;
}
