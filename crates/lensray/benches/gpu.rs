//! Throughput of the Vulkan compute pass: rays per second from timestamp queries, at 640x480 and
//! 16 spp on a ~79k-triangle scene (36 spheres of 2208 triangles on a floor) (AS build and first dispatch reported apart).
//!
//! `cargo bench --bench gpu` measures; under `cargo test --all-targets` (no `--bench` argument)
//! it only runs a tiny smoke version. Without a ray-query device it fails, unless
//! LENSRAY_SKIP_GPU_TESTS=1 (then it records the skip, as the GPU tests do).

#[path = "../../lensray-vulkan/tests/support/mod.rs"]
mod gpu_support;

use glam::Vec3;
use lensray_core::camera::{CameraParams, LensParams, ProjectionParams};
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::{Light, Material, Mesh, Scene};
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{bench, GpuOptions, PassBenchOptions};

/// A UV sphere with vertex normals (the scene generators' own).
fn sphere(center: Vec3, radius: f32, rings: u32, segments: u32, material: u32) -> Mesh {
    lensray_core::scene::generate::uv_sphere("sphere", center, radius, segments, rings, material)
}

/// `n x n` spheres on a floor.
fn scene(n: u32, rings: u32) -> Scene {
    let mut meshes = vec![Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "floor".into(),
        positions: vec![
            Vec3::new(-20.0, 0.0, -20.0),
            Vec3::new(20.0, 0.0, -20.0),
            Vec3::new(20.0, 0.0, 20.0),
            Vec3::new(-20.0, 0.0, 20.0),
        ],
        normals: vec![],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![0; 2],
        ..Default::default()
    }];
    for i in 0..n * n {
        let (x, z) = ((i % n) as f32, (i / n) as f32);
        let c = Vec3::new(
            (x - (n - 1) as f32 / 2.0) * 1.2,
            0.5,
            (z - (n - 1) as f32 / 2.0) * 1.2,
        );
        meshes.push(sphere(c, 0.5, rings, 2 * rings, 1 + i % 3));
    }
    let material = |name: &str, diffuse: Vec3| Material {
        name: name.into(),
        diffuse,
        emission: Vec3::ZERO,
        ..Default::default()
    };
    Scene {
        meshes,
        materials: vec![
            material("floor", Vec3::splat(0.7)),
            material("red", Vec3::new(0.8, 0.2, 0.1)),
            material("green", Vec3::new(0.2, 0.8, 0.1)),
            material("blue", Vec3::new(0.1, 0.2, 0.8)),
        ],
        lights: vec![Light::point(Vec3::new(3.0, 8.0, 4.0), Vec3::splat(100.0))],
        ..Default::default()
    }
}

fn main() {
    let measure = std::env::args().any(|a| a == "--bench");
    let (scene, width, height, spp, repeats) = if measure {
        (scene(6, 24), 640, 480, 16, 3)
    } else {
        (scene(2, 6), 32, 24, 2, 1)
    };
    let camera = CameraParams {
        eye: Vec3::new(0.0, 4.0, 7.5),
        target: Vec3::new(0.0, 0.3, 0.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 50.0 },
        lens: LensParams::ThinLens {
            aperture_radius: 0.15,
            focus_distance: 7.0,
        },
        near: 0.1,
        far: 100.0,
        width,
        height,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera");
    let options = PassBenchOptions {
        gpu: GpuOptions::default(),
        repeats,
    };
    for shading in [Shading::Unlit, Shading::Lit] {
        let shot = Shot {
            camera: camera.clone(),
            render: RenderSettings {
                spp,
                seed: 1,
                sampler: SamplerKind::default(),
                shading,
                background: Vec3::new(0.1, 0.2, 0.3),
                environment: Vec3::ZERO,
                shared_samples: false,
                noise_threshold: None,
                environment_seen: false,
                bounces: 1,
            },
        };
        match bench(&scene, &shot, &options) {
            Ok(report) => println!("--- gpu bench, {shading:?}\n{report}\n"),
            Err(e) if gpu_support::may_skip(&e) => {
                gpu_support::record_skip("benches/gpu", &e.to_string());
                return;
            }
            Err(e) => panic!("gpu bench: {e}"),
        }
    }
}
