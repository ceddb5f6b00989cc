//! What a textured sample costs: the same scene rendered with its textures and without them
//! (every material's diffuse, emission and alpha texture references taken away; the textures
//! stay loaded), on each path (default `cpu`, `software`, `rayquery`), lit, timed in turns
//! (`variants`). The target: a textured sample costs at most 1.3x an untextured one. Two scenes:
//!
//! - `card`: the test card (`scene::test_card`: a checker floor repeated through a texture
//!   transform, a gradient card, a leaf cut out by its alpha texture, a blended pane, an emissive
//!   sign; textures of 16-64 texels a side, 10 triangles);
//! - `apple`: Poly Haven's food_apple_01 (`assets/food_apple_01/food_apple_01_4k.gltf`: 7,012
//!   triangles, a 4096 x 4096 JPEG base colour, 85 MiB with its mip levels), framed by default.
//!
//! `cargo bench --bench textures -- [--repeat N] [--width W] [--height H] [--spp N]
//! [--paths cpu,software,rayquery] [--scene card|apple] [--json FILE]` measures (default 7 rounds,
//! 160x120, 4 spp, both scenes); under `cargo test --all-targets` (no `--bench` argument) it runs
//! a tiny smoke version of the test card on the CPU.

#[path = "variants/mod.rs"]
mod variants;

use std::path::Path;

use glam::Vec3;
use lensray_core::scene::generate::camera_settings;
use lensray_core::scene::{Scene, SceneDescription};
use lensray_core::settings::Settings;
use variants::{Args, SceneResults, Variant};

/// `scene` with no material reading a texture.
fn untextured(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    for m in &mut scene.materials {
        m.diffuse_texture = None;
        m.emission_texture = None;
        m.alpha_texture = None;
    }
    scene
}

/// The test card seen as its documentation says: from (0, 1.2, 4) towards (0, 0.6, 0).
fn card() -> SceneDescription {
    let scene = lensray_core::scene::test_card::test_card();
    let (eye, target) = (Vec3::new(0.0, 1.2, 4.0), Vec3::new(0.0, 0.6, 0.0));
    let settings = Settings {
        camera: camera_settings(eye, target, target, 45.0, 0.02, scene.bounds()),
        ..Default::default()
    };
    SceneDescription {
        scene,
        settings,
        source: "the test card".into(),
        ..Default::default()
    }
}

fn apple() -> SceneDescription {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/food_apple_01/food_apple_01_4k.gltf");
    let mut description = lensray_core::scene::load(&file).expect("the apple loads");
    description.source = "food_apple_01_4k.gltf".into();
    description
}

fn measure(name: &str, description: &SceneDescription, args: &Args) -> SceneResults {
    let (shot, scene) = args.shot(description);
    let variants = [
        Variant {
            name: "untextured".into(),
            scene: untextured(&scene),
        },
        Variant {
            name: "textured".into(),
            scene,
        },
    ];
    let results = SceneResults {
        scene: format!("{name}: {}", description.source),
        triangles: variants[0].scene.triangle_count(),
        paths: variants::measure(&variants, &shot, args).expect("textures bench"),
    };
    println!(
        "{}",
        variants::table("textures", &results, Some(("textured", "untextured")), args)
    );
    results
}

fn main() {
    let args = Args::from_env();
    let only = args.value("--scene");
    let mut results = vec![];
    if only.is_none_or(|s| s == "card") {
        results.push(measure("card", &card(), &args));
    }
    // The smoke version leaves out the apple: decoding its 4k texture takes a third of a second.
    if args.measure && only.is_none_or(|s| s == "apple") {
        results.push(measure("apple", &apple(), &args));
    }
    variants::write_json("textures", &args, &results).expect("write the JSON");
}
