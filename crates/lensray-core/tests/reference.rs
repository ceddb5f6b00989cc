//! The CPU reference renderer against analytic answers.
//!
//! Run with `cargo test --test reference`.

use glam::Vec3;
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::sampler::{hash_u32, SamplerKind};
use lensray_core::scene::{Material, Mesh};
use lensray_core::settings::{RenderSettings, Shading};

mod edge_fit;

#[path = "reference/depth_of_field.rs"]
mod depth_of_field;
#[path = "reference/emitters.rs"]
mod emitters;
#[path = "reference/glass.rs"]
mod glass;
#[path = "reference/scheimpflug.rs"]
mod scheimpflug;
#[path = "reference/shading.rs"]
mod shading;
#[path = "reference/shadow.rs"]
mod shadow;
#[path = "reference/sky.rs"]
mod sky;
#[path = "reference/traversal.rs"]
mod traversal;

fn rand01(state: &mut u32) -> f32 {
    *state = hash_u32(state.wrapping_add(0x9e37_79b9));
    (*state >> 8) as f32 / 16_777_216.0
}

/// An axis-aligned quad in the plane z = `z`, facing -z, covering [x0, x1] x [y0, y1].
fn quad(x0: f32, x1: f32, y0: f32, y1: f32, z: f32, material: u32) -> Mesh {
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
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
        ..Default::default()
    }
}

fn material(name: &str, diffuse: Vec3, emission: Vec3) -> Material {
    Material {
        name: name.into(),
        diffuse,
        emission,
        ..Default::default()
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
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera")
}

fn settings(shading: Shading, spp: u32) -> RenderSettings {
    RenderSettings {
        spp,
        seed: 1,
        sampler: SamplerKind::default(),
        shading,
        background: Vec3::new(0.2, 0.3, 0.4),
        environment: Vec3::ZERO,
        shared_samples: false,
        noise_threshold: None,
        environment_seen: false,
        bounces: 1,
    }
}
