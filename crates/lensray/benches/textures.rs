//! What a textured sample costs: the same scene rendered with its textures and without them
//! (every material's diffuse, emission and alpha texture references taken away; the textures
//! stay loaded), on each path (default `cpu`, `software`, `rayquery`), lit, timed in turns
//! (`variants`). The target: a textured sample costs at most 1.3x an untextured one. Two scenes:
//!
//! - `card`: the test card (`scene::test_card`: a checker floor repeated through a texture
//!   transform, a gradient card, a leaf cut out by its alpha texture, a blended pane, an emissive
//!   sign; textures of 16-64 texels a side, 10 triangles);
//! - `apples`: the README's real scene (`assets/food_apple_01/apples.gltf`: five copies of Poly
//!   Haven's scanned apple, 35,062 triangles sharing one 4096 x 4096 JPEG base colour, 85 MiB
//!   with its mip levels, on an untextured floor), with the file's camera and key light.
//!
//! `cargo bench --bench textures -- [--repeat N] [--width W] [--height H] [--spp N]
//! [--paths cpu,software,rayquery] [--scene card|apples] [--parts] [--json FILE]` measures
//! (default 7 rounds, 160x120, 4 spp, both scenes; `--parts` adds the variants with only the
//! alpha textures and with only the colour ones, which tell the alpha cut-out's share: it changes
//! what the rays see and pass through, not only the colour; and `linear`, every texture read as
//! linear, which tells the share of the sRGB decode of each texel); under `cargo test --all-targets` (no
//! `--bench` argument) it runs a tiny smoke version of the test card on the CPU.
//!
//! `--brdf` measures instead what glTF's metallic-roughness BRDF costs against Lambert, the
//! scenes textured as above (the target: at most 1.5x): `lambert` (every material's specular
//! weight and metallic 0, no metallic-roughness texture: the BRDF reduces to c / pi), `pbr`
//! (the apples as their file has them: specular 1 and the 4K roughness texture; the card's
//! materials given specular 1 and roughness 0.5) and, where a metallic-roughness texture is
//! read, `pbr factors` (the same without that texture), which tells the share of its reads;
//! `pbr clearcoat` is `pbr` with every material under a smooth clear coat (weight 1, roughness
//! 0.1): what the coat's lobe and its draws add; `pbr sheen` is `pbr` with every material
//! under a white sheen (colour 1, roughness 0.5): what the Charlie lobe, the albedo table's
//! reads and the sheen's draws add; `pbr transmission` is `pbr` with every material clear
//! glass (KHR_materials_transmission 1, IOR 1.5, thin walls): what the BTDF, its Fresnel split
//! and its draws add at the same bounces (the shot's, from `pbr`: a path that meets glass
//! stops where the others stop, so the cost is the surface's, not a longer path's).

#[path = "variants/mod.rs"]
mod variants;

use std::path::Path;

use glam::Vec3;
use lensray_core::scene::generate::camera_settings;
use lensray_core::scene::texture::Encoding;
use lensray_core::scene::{Scene, SceneDescription};
use lensray_core::settings::Settings;
use variants::{Args, SceneResults, Variant};

/// Which texture references a variant keeps.
#[derive(Clone, Copy)]
struct Keep {
    /// Diffuse and emission textures.
    colour: bool,
    /// Alpha textures (coverage: the leaf's cut-out).
    alpha: bool,
    /// Every texture read as linear: the same lookups without the sRGB decode of each texel.
    linear: bool,
}

/// `scene` with only the texture references `keep` names.
fn with_textures(scene: &Scene, keep: Keep) -> Scene {
    let mut scene = scene.clone();
    for m in &mut scene.materials {
        if !keep.colour {
            m.diffuse_texture = None;
            m.emission_texture = None;
        }
        if !keep.alpha {
            m.alpha_texture = None;
        }
    }
    if keep.linear {
        for t in &mut scene.textures {
            t.encoding = Encoding::Linear;
        }
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

fn apples() -> SceneDescription {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/food_apple_01/apples.gltf");
    let mut description = lensray_core::scene::load(&file).expect("the apples load");
    description.source = "apples.gltf".into();
    description
}

fn measure(name: &str, description: &SceneDescription, args: &Args) -> SceneResults {
    let (shot, scene) = args.shot(description);
    let keep = |colour, alpha, linear| Keep {
        colour,
        alpha,
        linear,
    };
    let mut kept = vec![("untextured", keep(false, false, false))];
    if args.flag("--parts") {
        kept.extend([
            ("alpha only", keep(false, true, false)),
            ("colour only", keep(true, false, false)),
            ("linear", keep(true, true, true)),
        ]);
    }
    kept.push(("textured", keep(true, true, false)));
    let variants: Vec<Variant> = kept
        .into_iter()
        .map(|(name, keep)| Variant {
            name: name.into(),
            scene: with_textures(&scene, keep),
        })
        .collect();
    let results = SceneResults {
        scene: format!("{name}: {}", description.source),
        triangles: scene.triangle_count(),
        paths: variants::measure(&variants, &shot, args).expect("textures bench"),
    };
    println!(
        "{}",
        variants::table("textures", &results, Some(("textured", "untextured")), args)
    );
    results
}

/// `scene` shaded as Lambert: no specular lobe, no metal, no metallic-roughness texture.
fn lambert(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    for m in &mut scene.materials {
        m.specular = 0.0;
        m.metallic = 0.0;
        m.metallic_roughness_texture = None;
    }
    scene
}

/// The textured `description` with glTF's metallic-roughness BRDF (`make_pbr` gives it where
/// the scene has none) against Lambert, on each path.
fn measure_brdf(
    name: &str,
    description: &SceneDescription,
    make_pbr: fn(&mut Scene),
    args: &Args,
) -> SceneResults {
    let (shot, mut pbr) = args.shot(description);
    make_pbr(&mut pbr);
    let mut variants = vec![Variant {
        name: "lambert".into(),
        scene: lambert(&pbr),
    }];
    if pbr
        .materials
        .iter()
        .any(|m| m.metallic_roughness_texture.is_some())
    {
        let mut factors = pbr.clone();
        for m in &mut factors.materials {
            m.metallic_roughness_texture = None;
        }
        variants.push(Variant {
            name: "pbr factors".into(),
            scene: factors,
        });
    }
    let triangles = pbr.triangle_count();
    // Every material under a smooth clear coat (KHR_materials_clearcoat 1, roughness 0.1).
    let mut coated = pbr.clone();
    for m in &mut coated.materials {
        (m.clearcoat, m.clearcoat_roughness) = (1.0, 0.1);
    }
    // Every material under a white velvet sheen (KHR_materials_sheen colour 1, roughness 0.5).
    let mut sheened = pbr.clone();
    for m in &mut sheened.materials {
        (m.sheen_colour, m.sheen_roughness) = (Vec3::ONE, 0.5);
    }
    // Every material clear glass (KHR_materials_transmission 1, thin walls).
    let mut glass = pbr.clone();
    for m in &mut glass.materials {
        m.transmission = 1.0;
    }
    variants.push(Variant {
        name: "pbr".into(),
        scene: pbr,
    });
    variants.push(Variant {
        name: "pbr clearcoat".into(),
        scene: coated,
    });
    variants.push(Variant {
        name: "pbr sheen".into(),
        scene: sheened,
    });
    variants.push(Variant {
        name: "pbr transmission".into(),
        scene: glass,
    });
    let results = SceneResults {
        scene: format!("{name}: {}", description.source),
        triangles,
        paths: variants::measure(&variants, &shot, args).expect("brdf bench"),
    };
    println!(
        "{}",
        variants::table("brdf", &results, Some(("pbr", "lambert")), args)
    );
    results
}

/// The test card's materials (Lambert, as the built-in scenes are) as glTF's default dielectric
/// with roughness 0.5.
fn card_pbr(scene: &mut Scene) {
    for m in &mut scene.materials {
        m.specular = 1.0;
        m.roughness = 0.5;
    }
}

fn main() {
    let args = Args::from_env();
    let only = args.value("--scene");
    // The smoke version runs both measurements on the card.
    let brdf = args.flag("--brdf") || !args.measure;
    let textures = !args.flag("--brdf");
    let mut results = vec![];
    if only.is_none_or(|s| s == "card") {
        if textures {
            results.push(measure("card", &card(), &args));
        }
        if brdf {
            results.push(measure_brdf("card", &card(), card_pbr, &args));
        }
    }
    // The smoke version leaves out the apples: decoding their 4k texture takes half a second.
    if args.measure && only.is_none_or(|s| s == "apples") {
        results.push(if brdf {
            measure_brdf("apples", &apples(), |_| {}, &args)
        } else {
            measure("apples", &apples(), &args)
        });
    }
    let bench = if brdf { "brdf" } else { "textures" };
    variants::write_json(bench, &args, &results).expect("write the JSON");
}
