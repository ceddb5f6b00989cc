//! The CPU reference renderer against analytic answers.

use glam::{Vec2, Vec3, Vec3A};
use lensray::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray::reference::{Accel, Renderer, WatertightRay};
use lensray::render::{PointLight, RenderSettings, Shading};
use lensray::sampler::hash_u32;
use lensray::scene::{Material, Mesh, Scene};

fn rand01(state: &mut u32) -> f32 {
    *state = hash_u32(state.wrapping_add(0x9e37_79b9));
    (*state >> 8) as f32 / 16_777_216.0
}

/// An axis-aligned quad in the plane z = `z`, facing -z, covering [x0, x1] x [y0, y1].
fn quad(x0: f32, x1: f32, y0: f32, y1: f32, z: f32, material: u32) -> Mesh {
    Mesh {
        name: "quad".into(),
        positions: vec![
            Vec3::new(x0, y0, z),
            Vec3::new(x1, y0, z),
            Vec3::new(x1, y1, z),
            Vec3::new(x0, y1, z),
        ],
        normals: vec![],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![material; 2],
    }
}

fn material(name: &str, diffuse: Vec3, emission: Vec3) -> Material {
    Material {
        name: name.into(),
        diffuse,
        emission,
    }
}

/// Camera at the origin looking along world -z (so camera +x is world +x, camera +y world +y).
fn camera(width: u32, height: u32, lens: LensParams) -> Camera {
    CameraParams {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 40.0 },
        lens,
        near: 0.01,
        far: 100.0,
        width,
        height,
    }
    .build()
    .expect("valid camera")
}

fn settings(shading: Shading, spp: u32) -> RenderSettings {
    RenderSettings {
        spp,
        seed: 1,
        shading,
        background: Vec3::new(0.2, 0.3, 0.4),
        light: PointLight {
            position: Vec3::new(0.0, 0.0, 0.0),
            intensity: Vec3::splat(10.0),
        },
    }
}

#[test]
fn bvh_closest_hit_equals_brute_force() {
    let mut s = 17u32;
    let mut tris = Vec::new();
    for _ in 0..2000 {
        let c = Vec3A::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        let v = |s: &mut u32| c + Vec3A::new(rand01(s), rand01(s), rand01(s)) - 0.5;
        tris.push([v(&mut s), v(&mut s), v(&mut s)]);
    }
    let accel = Accel::build(&tris);
    let mut mismatches = Vec::new();
    for i in 0..2000 {
        let origin = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 14.0 - 2.0;
        let target = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        let dir = (target - origin).normalize();
        let wt = WatertightRay::new(origin, dir);
        let brute = tris
            .iter()
            .filter_map(|t| wt.intersect(t, 0.0, f32::INFINITY).map(|h| h.0))
            .fold(f32::INFINITY, f32::min);
        let bvh = accel
            .closest_hit(origin, dir, 0.0, f32::INFINITY)
            .map_or(f32::INFINITY, |h| h.t);
        if brute != bvh {
            mismatches.push((i, brute, bvh));
        }
    }
    assert!(
        mismatches.is_empty(),
        "BVH vs brute force (ray, brute t, bvh t): {mismatches:?}"
    );
}

#[test]
fn unlit_shows_diffuse_colour_and_background() {
    let red = Vec3::new(0.9, 0.1, 0.1);
    // Left half of the view covered by a red wall at z = -5.
    let scene = Scene {
        meshes: vec![quad(-10.0, 0.0, -10.0, 10.0, -5.0, 0)],
        materials: vec![material("red", red, Vec3::ZERO)],
    };
    let cam = camera(32, 24, LensParams::Pinhole);
    let s = settings(Shading::Unlit, 4);
    let (image, stats) = Renderer::new(&scene).render(&cam, &s, &mut |_, _| {});
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
    let scene = Scene {
        meshes: vec![quad(-50.0, 50.0, -50.0, 50.0, -4.0, 0)],
        materials: vec![material("wall", kd, ke)],
    };
    let cam = camera(16, 16, LensParams::Pinhole);
    let mut s = settings(Shading::Lit, 1);
    s.light.position = Vec3::new(1.0, 0.5, -1.0);
    let renderer = Renderer::new(&scene);
    let (image, _) = renderer.render(&cam, &s, &mut |_, _| {});
    let mut worst = 0.0f32;
    for row in 0..16 {
        for col in 0..16 {
            // Recompute the sample's hit point with the same sampler, then the formula by hand.
            let sample = lensray::sampler::camera_sample(s.seed, glam::UVec2::new(col, row), 16, 0);
            let ray = cam.generate_ray(sample.film, sample.lens);
            let t = (-4.0 - ray.origin.z) / ray.direction.z;
            let p = ray.at(t);
            let to_light = s.light.position - p;
            let d2 = to_light.length_squared();
            let cos = to_light.normalize().z.max(0.0); // wall normal facing the camera is +z
            let expected = ke + kd / std::f32::consts::PI * s.light.intensity * cos / d2;
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
fn shadow_ray_blocks_the_light() {
    let kd = Vec3::splat(0.8);
    let ke = Vec3::new(0.05, 0.0, 0.0);
    // Wall at z = -4, an occluder at z = -2 between it and a light at the eye.
    let scene = Scene {
        meshes: vec![
            quad(-50.0, 50.0, -50.0, 50.0, -4.0, 0),
            quad(-0.2, 0.2, -0.2, 0.2, -2.0, 1),
        ],
        materials: vec![
            material("wall", kd, ke),
            material("occluder", Vec3::ZERO, Vec3::ZERO),
        ],
    };
    let mut s = settings(Shading::Lit, 1);
    s.light.position = Vec3::new(0.0, 0.0, -1.0);
    let renderer = Renderer::new(&scene);
    // A ray to a wall point behind the occluder as seen from the light, but visible to the camera.
    let p = Vec3::new(0.5, 0.0, -4.0);
    let ray = lensray::camera::Ray {
        origin: Vec3::new(1.0, 0.0, 0.0),
        direction: (p - Vec3::new(1.0, 0.0, 0.0)).normalize(),
    };
    let hit = renderer.intersect(&ray).expect("wall");
    let surface = renderer.surface_point(&ray, &hit);
    let origin = lensray::reference::shadow_origin(&surface);
    assert!((origin - p).length() < 1e-3);
    // From (0.5, 0, -4) to (0, 0, -1) the segment crosses z = -2 at x = 1/6: inside the occluder.
    let cam = camera(8, 8, LensParams::Pinhole);
    let (image, _) = renderer.render(&cam, &s, &mut |_, _| {});
    // The centre pixels see the occluder itself (black); pixels that see the wall around the
    // occluder's shadow are lit. Check one wall pixel in the umbra exists with only emission.
    let shadowed = image.pixels.iter().filter(|&&c| c == ke).count();
    let lit = image.pixels.iter().filter(|&&c| c.y > 0.0).count();
    assert!(shadowed > 0, "no pixel in shadow: {:?}", image.pixels);
    assert!(lit > 0, "no lit pixel");
}

#[test]
fn depth_aov_is_distance_along_view_axis() {
    let scene = Scene {
        meshes: vec![quad(-50.0, 50.0, -50.0, 50.0, -7.5, 0)],
        materials: vec![Material::default()],
    };
    let cam = camera(20, 10, LensParams::Pinhole);
    let (image, _) =
        Renderer::new(&scene).render(&cam, &settings(Shading::Depth, 2), &mut |_, _| {});
    let worst = image
        .pixels
        .iter()
        .map(|d| (d.x - 7.5).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "depth differs from 7.5 by up to {worst}");
}

/// Width, in pixels, of the blurred transition of a vertical black/white edge at depth z.
fn edge_transition(z: f32, focus: f32, aperture: f32) -> (f32, f32) {
    let scene = Scene {
        meshes: vec![
            quad(-100.0, 0.0, -100.0, 100.0, -z, 0),
            quad(0.0, 100.0, -100.0, 100.0, -z, 1),
        ],
        materials: vec![
            material("black", Vec3::ZERO, Vec3::ZERO),
            material("white", Vec3::ONE, Vec3::ZERO),
        ],
    };
    let width = 128;
    let cam = camera(
        width,
        96,
        LensParams::ThinLens {
            aperture_radius: aperture as f64,
            focus_distance: focus as f64,
        },
    );
    let (image, _) =
        Renderer::new(&scene).render(&cam, &settings(Shading::Unlit, 64), &mut |_, _| {});
    // Sum of intensities along a row = area under the blurred step; the transition is where
    // values are strictly between 0.02 and 0.98.
    let row: Vec<f32> = (0..width).map(|c| image.get(c, 48).x).collect();
    let blurred = row.iter().filter(|&&v| v > 0.02 && v < 0.98).count() as f32;
    (blurred, cam.coc_radius_pixels(z))
}

#[test]
fn depth_of_field_blurs_by_the_circle_of_confusion() {
    // In focus: the edge stays within about one pixel (box filter).
    let (sharp, coc) = edge_transition(5.0, 5.0, 0.5);
    assert!(
        coc < 1e-3 && sharp <= 2.0,
        "in-focus edge spans {sharp} px (CoC {coc})"
    );
    // Out of focus, nearer and farther: the step is smeared over about the CoC diameter.
    for z in [2.5f32, 12.0] {
        let (blurred, coc) = edge_transition(z, 5.0, 0.5);
        let diameter = 2.0 * coc;
        assert!(diameter > 8.0, "test set-up: CoC diameter {diameter}");
        assert!(
            (blurred - diameter).abs() <= 0.25 * diameter + 2.0,
            "z = {z}: blurred over {blurred} px, CoC diameter {diameter} px"
        );
    }
}

#[test]
fn renders_are_deterministic() {
    let scene = Scene {
        meshes: vec![quad(-1.0, 1.0, -1.0, 1.0, -3.0, 0)],
        materials: vec![Material::default()],
    };
    let cam = camera(
        24,
        16,
        LensParams::ThinLens {
            aperture_radius: 0.1,
            focus_distance: 2.0,
        },
    );
    let r = Renderer::new(&scene);
    let s = settings(Shading::Lit, 8);
    let (a, _) = r.render(&cam, &s, &mut |_, _| {});
    let (b, _) = r.render(&cam, &s, &mut |_, _| {});
    assert_eq!(a, b);
    let _ = Vec2::ZERO;
}
