//! Drawing the environment by its power and the BRDF (multiple importance sampling, the
//! renderers' estimator), the map's draw resampled among `SKY_CANDIDATES` directions (the
//! default), against the same with the map's power alone (one candidate,
//! `Renderer::with_sky_candidates(1)`) and against drawing it by the cosine alone (one ray a
//! sample, what lensray did before maps; `Renderer::with_cosine_sky`), at equal time: the CPU
//! reference renders the default scene, its materials made glossy (metals and plastics of
//! roughness 0.15-0.6), under the studio map (`assets/environments/studio.hdr`) at several spp
//! with each estimator, and the RMSE against a converged render of the default estimator is
//! scaled to the time of the default (RMSE falls as 1 / sqrt(time)).
//!
//! `cargo bench --bench environment -- [--width W] [--height H] [--reference-spp N]` (default
//! 160x120, reference 1024 spp); under `cargo test --all-targets` a tiny smoke version runs.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use lensray_core::film::compare::rmse;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::scene::environment::EnvironmentMap;
use lensray_core::scene::{default_scene, EnvironmentLight, Scene};
use lensray_core::settings::{shot, ImageSettings, RenderStyle, Settings, Shot};

fn arg(name: &str, default: u32) -> u32 {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().expect("a number"))
}

/// The default scene, glossy, under the studio map, with no lights of its own.
fn scene() -> Scene {
    let mut scene = default_scene().scene;
    for (k, m) in scene.materials.iter_mut().enumerate() {
        m.specular = 1.0;
        m.metallic = if k % 2 == 0 { 1.0 } else { 0.0 };
        m.roughness = [0.15, 0.3, 0.6][k % 3];
    }
    scene.lights.clear();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/environments/studio.hdr");
    let (map, _) = EnvironmentMap::load(&path).expect("the studio map");
    scene.environment = Some(Arc::new(EnvironmentLight::new(map)));
    scene
}

/// The image with each channel clamped at 1: what a display shows without a tone map, where the
/// pepper a user sees is, rather than the few pixels that see a lamp in thousands.
fn displayed(image: &Image) -> Image {
    let mut image = image.clone();
    for p in &mut image.pixels {
        *p = p.min(glam::Vec3::ONE);
    }
    image
}

fn render(renderer: &Renderer, shot: &Shot, spp: u32, seed: u32) -> (Image, f64) {
    let mut shot = shot.clone();
    shot.render.spp = spp;
    shot.render.seed = seed;
    let start = Instant::now();
    let (image, _) = renderer.render(&shot, &mut |_, _| {});
    (image, start.elapsed().as_secs_f64())
}

fn main() {
    let measure = std::env::args().any(|a| a == "--bench");
    let (width, height) = if measure {
        (arg("--width", 160), arg("--height", 120))
    } else {
        (32, 24)
    };
    let reference_spp = if measure {
        arg("--reference-spp", 1024)
    } else {
        16
    };
    let scene = scene();
    let settings = Settings {
        image: ImageSettings {
            width: Some(width),
            height: Some(height),
            ..ImageSettings::default()
        },
        render: RenderStyle {
            environment: Some(lensray_core::settings::EnvironmentSetting::Map(
                "studio".into(),
            )),
            ..RenderStyle::default()
        },
        ..Settings::default()
    };
    let shot = shot(&settings, &scene).expect("the shot");
    let mis = Renderer::new(&scene);
    let others = [
        ("power alone", Renderer::new(&scene).with_sky_candidates(1)),
        ("cosine", Renderer::new(&scene).with_cosine_sky()),
    ];
    let (reference, seconds) = render(&mis, &shot, reference_spp, 1000);
    println!("reference: {width}x{height}, {reference_spp} spp, {seconds:.1} s");
    let shown = displayed(&reference);
    println!(
        "spp | MIS s | MIS RMSE | other | its s | its RMSE | its RMSE at MIS's time | ratio | \
         the same of the displayed images: MIS RMSE | its at MIS's time | ratio"
    );
    let spps: &[u32] = if measure { &[4, 16, 64] } else { &[2] };
    for &spp in spps {
        let (a, ta) = render(&mis, &shot, spp, 1);
        let ea = rmse(&a, &reference);
        let da = rmse(&displayed(&a), &shown);
        for (name, other) in &others {
            let (b, tb) = render(other, &shot, spp, 1);
            let eb = rmse(&b, &reference);
            let at_equal_time = eb * (tb / ta).sqrt();
            let db = rmse(&displayed(&b), &shown) * (tb / ta).sqrt();
            println!(
                "{spp} | {ta:.2} | {ea:.4} | {name} | {tb:.2} | {eb:.4} | {at_equal_time:.4} | {:.2} \
                 | {da:.4} | {db:.4} | {:.2}",
                at_equal_time / ea,
                db / da
            );
        }
    }
}
