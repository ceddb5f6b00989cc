//! Emissive triangles drawn as lights (by power, weighed against the BRDF's draws by multiple
//! importance sampling: the renderers' estimator) against finding them only where a BRDF's draw
//! meets one (`Renderer::without_emitter_draws`, unbiased from two bounces on): the CPU
//! reference renders the Cornell box of `assets/cornell`, lit by its ceiling patch alone, with
//! 2 and 3 bounces. For each estimator: nanoseconds a pixel sample (the cost of the emitters'
//! draw is the difference), the RMSE against a converged render of the default estimator, and
//! the BRDF-only RMSE scaled to the default's time (RMSE falls as 1 / sqrt(time)).
//!
//! `cargo bench --bench emitters -- --bench [--width W] [--height H] [--reference-spp N]`
//! (default 160x120, reference 1024 spp); under `cargo test --all-targets` a tiny smoke version
//! runs.

use std::path::Path;
use std::time::Instant;

use lensray_core::film::compare::rmse;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::scene::file::load;
use lensray_core::settings::{light_scene, shot, Shot};

fn arg(name: &str, default: u32) -> u32 {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().expect("a number"))
}

/// The render of `shot` at `spp` and `seed` and its wall seconds.
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
        (24, 18)
    };
    let reference_spp = if measure {
        arg("--reference-spp", 1024)
    } else {
        16
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/cornell/cornell.toml");
    let mut description = load(&path).expect("the Cornell box");
    description.settings.image.width = Some(width);
    description.settings.image.height = Some(height);
    let warnings = light_scene(&description.settings, &mut description.scene).expect("lights");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(
        description.scene.lights.is_empty(),
        "the Cornell box is lit by its emissive patch alone"
    );
    let scene = &description.scene;
    let drawn = Renderer::new(scene);
    let brdf_only = Renderer::new(scene).without_emitter_draws();
    let pixels = f64::from(width * height);
    println!("Cornell box, {width}x{height}, reference {reference_spp} spp of the default");
    println!(
        "bounces | spp | drawn ns/sample | drawn RMSE | BRDF-only ns/sample | BRDF-only RMSE | \
         BRDF-only RMSE at drawn's time | ratio"
    );
    let spps: &[u32] = if measure { &[16, 64] } else { &[2] };
    for bounces in [2, 3] {
        let mut shot = shot(&description.settings, scene).expect("the shot");
        shot.render.bounces = bounces;
        let (reference, _) = render(&drawn, &shot, reference_spp, 1000);
        for &spp in spps {
            let (a, ta) = render(&drawn, &shot, spp, 1);
            let (b, tb) = render(&brdf_only, &shot, spp, 1);
            let (ea, eb) = (rmse(&a, &reference), rmse(&b, &reference));
            let at_equal_time = eb * (tb / ta).sqrt();
            let ns = |t: f64| t * 1e9 / (pixels * f64::from(spp));
            println!(
                "{bounces} | {spp} | {:.0} | {ea:.4} | {:.0} | {eb:.4} | {at_equal_time:.4} | {:.2}",
                ns(ta),
                ns(tb),
                at_equal_time / ea
            );
        }
    }
}
