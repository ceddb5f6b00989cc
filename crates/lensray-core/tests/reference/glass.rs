//! Glass (`KHR_materials_transmission`, `_ior`, `_volume`) against closed forms: a sphere of
//! smooth absorbing glass under a uniform white sky, seen through its centre, and spheres of
//! clear glass that the sky's light crosses whole (a white furnace).

use glam::Vec3;
use lensray_core::camera::{CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::reference::Renderer;
use lensray_core::scene::generate::{cuboid, uv_sphere};
use lensray_core::scene::{Material, Mesh, Scene};
use lensray_core::settings::{Shading, Shot};

use crate::settings;

/// A sphere of radius 0.5 at the origin, its triangles wound to face outwards (checked).
fn ball(material: u32) -> Mesh {
    let mesh = uv_sphere("ball", Vec3::ZERO, 0.5, 96, 48, material);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let outward = (b - a).cross(c - a).dot(a + b + c);
        assert!(outward >= 0.0, "a triangle of the sphere faces inwards");
    }
    mesh
}

fn glass(roughness: f32, thin: bool, attenuation: Vec3) -> Material {
    Material {
        diffuse: Vec3::ONE,
        metallic: 0.0,
        roughness,
        specular: 1.0,
        transmission: 1.0,
        ior: 1.5,
        thin,
        attenuation,
        ..Default::default()
    }
}

/// The mean of a `width` x `width` render of `material`'s ball under a white sky, seen from 3
/// units away through a window `half_width` units to each side of its centre.
fn centre(material: Material, half_width: f32, width: u32, spp: u32, bounces: u32) -> Vec3 {
    let eye = Vec3::new(0.0, 0.0, 3.0);
    furnace(ball(0), material, eye, (half_width, width), spp, bounces)
}

/// The mean of a render of `mesh` made of `material` under a white sky, seen from `eye`
/// towards the origin through a window (`half_width` units to each side of the origin,
/// `width` pixels square).
fn furnace(
    mesh: Mesh,
    material: Material,
    eye: Vec3,
    (half_width, width): (f32, u32),
    spp: u32,
    bounces: u32,
) -> Vec3 {
    let scene = Scene {
        meshes: vec![mesh],
        materials: vec![material],
        ..Default::default()
    };
    let distance = f64::from(eye.length());
    let camera = CameraParams {
        eye,
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: ProjectionParams::Perspective {
            vfov_degrees: 2.0 * (f64::from(half_width) / distance).atan().to_degrees(),
        },
        lens: LensParams::Pinhole,
        near: 0.01,
        far: 100.0,
        width,
        height: width,
        movements: Movements::NONE,
    }
    .build()
    .expect("a camera");
    let mut render = settings(Shading::Lit, spp);
    render.background = Vec3::ONE;
    render.environment = Vec3::ONE;
    render.bounces = bounces;
    let shot = Shot { camera, render };
    let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    let mut sum = Vec3::ZERO;
    for y in 0..width {
        for x in 0..width {
            sum += image.get(x, y);
        }
    }
    sum / (width * width) as f32
}

/// Smooth glass of extinction sigma seen through its centre under a white sky: the light
/// reflected at the front, F = 0.04, plus what crosses the ball (1 - F)^2 a, a = exp(-sigma
/// 2r), and every pair of inner reflections after it: F + (1 - F)^2 a / (1 - F a). One
/// bounce shows only the reflection: the sky's draws through the glass meet its back.
#[test]
fn absorbing_glass_keeps_what_beer_and_fresnel_say() {
    let sigma = Vec3::new(0.5, 1.0, 2.0);
    let a = (-sigma).exp();
    let f = 0.04;
    let want = Vec3::splat(f) + (1.0 - f) * (1.0 - f) * a / (Vec3::ONE - f * a);
    let got = centre(glass(0.0, false, sigma), 0.02, 3, 2048, 16);
    println!("through the centre: {got} against {want}");
    assert!(
        (got - want).abs().max_element() < 0.01,
        "{got} against {want}"
    );
    let one = centre(glass(0.0, false, sigma), 0.02, 3, 256, 1);
    println!("one bounce: {one} against F = {f}");
    assert!((one - Vec3::splat(f)).abs().max_element() < 0.005, "{one}");
}

/// Clear glass under a white sky returns it whole, less what paths longer than 16 surfaces
/// leave (smooth: within 0.1 %), and on rough glass less what GGX's single scattering loses
/// at each boundary, most where the view grazes them (`transmission.rs`'s table): a volume
/// and a thin wall, smooth and rough. 1024 samples a pixel, so that the estimate's noise is
/// well inside each bound.
#[test]
fn clear_glass_in_a_white_furnace_disappears() {
    for (roughness, thin, low, high) in [
        (0.0, false, 0.999, 1.001),
        (0.0, true, 0.999, 1.001),
        // Measured: 0.9518 and 0.9634; at 2048 samples 0.9516 and 0.9633, and the draws that
        // split by the macro normal's Fresnel converge to the same (0.9515 and 0.9635), whose
        // 64 samples read 0.974. Rough light that leaves from inside beyond the critical angle
        // is drawn (by the microfacet's own Fresnel); the lower bounds catch it lost (0.9075
        // then).
        (0.3, false, 0.94, 0.96),
        (0.3, true, 0.95, 0.975),
    ] {
        let got = centre(glass(roughness, thin, Vec3::ZERO), 0.45, 16, 1024, 16).x;
        println!("roughness {roughness}, thin {thin}: {got}");
        assert!(got >= low && got <= high, "{got} outside [{low}, {high}]");
    }
}

/// A slab of rough glass (roughness 0.3, 3 x 3 x 0.2) under a white sky returns it whole but
/// for what GGX's single scattering loses where light crosses and meets its faces, which
/// Mitsuba 3 finds for the same slab (`scripts/mitsuba/slab.sh`, 16 x 16 pixels, 2 x 4096
/// samples): with lensray's model (`gltf_dielectric.py`) 0.9896 seen face-on and 0.9483 seen
/// 60 degrees off the normal, with its own `roughdielectric` 0.9894 and 0.9481 (Schlick's
/// share is under 3e-4 here). Within 0.002 of the first pair (measured: 0.9893 and 0.9477;
/// at 4096 samples 0.9895 and 0.9480).
#[test]
fn a_rough_glass_slab_in_a_white_furnace_loses_what_mitsuba_finds() {
    let slab = || cuboid("slab", Vec3::ZERO, Vec3::new(1.5, 1.5, 0.1), 0.0, 0);
    for (degrees, mitsuba) in [(0.0f32, 0.9896f32), (60.0, 0.9483)] {
        let (sin, cos) = degrees.to_radians().sin_cos();
        let eye = Vec3::new(3.0 * sin, 0.0, 3.0 * cos);
        let rough = glass(0.3, false, Vec3::ZERO);
        let got = furnace(slab(), rough, eye, (0.2, 16), 256, 16).x;
        println!("seen {degrees} degrees off the normal: {got:.4} against Mitsuba's {mitsuba}");
        assert!((got - mitsuba).abs() <= 0.002, "{got} against {mitsuba}");
    }
}
