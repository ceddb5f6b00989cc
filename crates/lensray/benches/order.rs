//! Triangle order must not decide speed. A dense mesh of ~100k triangles in one mesh (as a
//! scanned model comes) rendered with its triangle list
//!
//! - as generated (spatially coherent: ring by ring, sphere by sphere),
//! - randomly shuffled (a fixed seed),
//! - sorted (in the spatial order every path puts them in, `scene::order`, before loading),
//!
//! on each path (default `cpu`, `software`, `rayquery`), timed in turns (`variants`). Every path
//! puts each mesh's triangles in that order when it loads a scene, so the three should run
//! alike: the table gives each variant's median against the generated one's, and whether the
//! images are identical. Two meshes: `sphere` (one UV sphere of 101,760 triangles on a ground
//! quad) and `grid` (the dense generator's 10x10 spheres and ground, 111,360 triangles merged
//! into one mesh).
//!
//! `cargo bench --bench order -- [--repeat N] [--width W] [--height H] [--spp N]
//! [--paths cpu,software,rayquery] [--mesh sphere|grid] [--json FILE]` measures (default 7
//! rounds, 160x120, 4 spp, lit, both meshes); under `cargo test --all-targets` (no `--bench`
//! argument) it runs a tiny smoke version on the CPU.

#[path = "variants/mod.rs"]
mod variants;

use glam::Vec3;
use lensray_core::scene::generate::{self, append, camera_settings, quad, uv_sphere};
use lensray_core::scene::order::spatial_order;
use lensray_core::scene::{Material, Mesh, Scene, SceneDescription};
use lensray_core::settings::Settings;
use variants::{Args, SceneResults, Variant};

/// The shuffle's seed.
const SEED: u64 = 0x5eed_0f0d_e5c0_ffee;

/// SplitMix64: a fixed, portable sequence (the shuffle must be the same on every machine).
fn split_mix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce5_e4b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// `mesh` with its triangles (and their materials) in the order `order` gives.
fn reordered(mesh: &Mesh, order: &[u32]) -> Mesh {
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        triangles: order.iter().map(|&t| mesh.triangles[t as usize]).collect(),
        material_ids: order
            .iter()
            .map(|&t| mesh.material_ids[t as usize])
            .collect(),
        ..mesh.clone()
    }
}

/// Fisher-Yates over each mesh's triangles.
fn shuffled(scene: &Scene) -> Scene {
    let mut state = SEED;
    let meshes = scene
        .meshes
        .iter()
        .map(|mesh| {
            let mut order: Vec<u32> = (0..mesh.triangles.len() as u32).collect();
            for i in (1..order.len()).rev() {
                let j = (split_mix(&mut state) % (i as u64 + 1)) as usize;
                order.swap(i, j);
            }
            reordered(mesh, &order)
        })
        .collect();
    Scene {
        meshes,
        ..scene.clone()
    }
}

fn sorted(scene: &Scene) -> Scene {
    let meshes = scene
        .meshes
        .iter()
        .map(|mesh| reordered(mesh, &spatial_order(&mesh.positions, &mesh.triangles)))
        .collect();
    Scene {
        meshes,
        ..scene.clone()
    }
}

/// One UV sphere of `segments` x `segments / 2` (101,760 triangles at 320) on a ground quad,
/// filling most of the frame.
fn sphere(segments: u32) -> SceneDescription {
    let material = |name: &str, diffuse: Vec3| Material::new(name, diffuse, Vec3::ZERO);
    let centre = Vec3::new(0.0, 1.0, 0.0);
    let scene = Scene {
        meshes: vec![
            uv_sphere("sphere", centre, 1.0, segments, segments / 2, 0),
            quad(
                "ground",
                Vec3::new(-4.0, 0.0, 4.0),
                Vec3::X * 8.0,
                Vec3::NEG_Z * 8.0,
                1,
            ),
        ],
        materials: vec![
            material("sphere", Vec3::new(0.8, 0.5, 0.3)),
            material("ground", Vec3::splat(0.6)),
        ],
        ..Default::default()
    };
    let eye = Vec3::new(0.6, 1.8, 3.4);
    let settings = Settings {
        camera: camera_settings(eye, centre, centre, 40.0, 0.02, scene.bounds()),
        ..Default::default()
    };
    SceneDescription {
        scene,
        settings,
        source: format!("one UV sphere ({segments} segments) on a ground quad"),
        ..Default::default()
    }
}

/// The dense generator's scene of at least `triangles` triangles, every mesh merged into one.
fn grid(triangles: usize) -> SceneDescription {
    let mut description = generate::dense(triangles);
    let mut merged = Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "grid".into(),
        ..Mesh::default()
    };
    for mut mesh in std::mem::take(&mut description.scene.meshes) {
        mesh.texcoords.clear();
        append(&mut merged, mesh);
    }
    description.scene.meshes = vec![merged];
    description.source = "the dense generator's spheres and ground as one mesh".into();
    description
}

fn measure(name: &str, description: &SceneDescription, args: &Args) -> SceneResults {
    let (shot, scene) = args.shot(description);
    let variants = [
        Variant {
            name: "generated".into(),
            scene: scene.clone(),
        },
        Variant {
            name: "shuffled".into(),
            scene: shuffled(&scene),
        },
        Variant {
            name: "sorted".into(),
            scene: sorted(&scene),
        },
    ];
    let results = SceneResults {
        scene: format!("{name}: {}", description.source),
        triangles: scene.triangle_count(),
        paths: variants::measure(&variants, &shot, args).expect("order bench"),
    };
    println!(
        "{}",
        variants::table(
            "triangle order",
            &results,
            Some(("shuffled", "sorted")),
            args
        )
    );
    results
}

fn main() {
    let args = Args::from_env();
    let (sphere_segments, grid_triangles) = if args.measure {
        (320, 100_000)
    } else {
        (16, 1_000)
    };
    let mut results = Vec::new();
    let only = args.value("--mesh");
    if only.is_none_or(|m| m == "sphere") {
        results.push(measure("sphere", &sphere(sphere_segments), &args));
    }
    if only.is_none_or(|m| m == "grid") {
        results.push(measure("grid", &grid(grid_triangles), &args));
    }
    variants::write_json("order", &args, &results).expect("write the JSON");
}
