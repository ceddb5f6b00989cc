//! Adaptive sampling (`--noise-threshold`) against uniform sampling at equal error, on the CPU
//! reference: the default scene (lit, its own camera) and the apples (`shared/assets/
//! food_apple_01`) under the studio map through the double Gauss 50 mm at f/2. For each, a
//! converged reference (another seed), uniform renders at several spp and adaptive renders at
//! several thresholds: wall time (median of `--repeat` runs), RMSE against the reference and
//! the mean samples a pixel took. Then the fastest adaptive render whose RMSE is at most the
//! uniform 64-spp render's, and its speed-up.
//!
//! `cargo bench --bench adaptive -- [--width W] [--height H] [--reference-spp N] [--repeat N]
//! [--cap N]` (default 640x480, reference 1024 spp, 3 runs, cap 256); the apples render at half
//! the size. Under `cargo test --all-targets` a tiny smoke version runs.

use std::path::Path;
use std::time::Instant;

use lensray_core::film::compare::rmse;
use lensray_core::film::{Image, Sums};
use lensray_core::reference::Renderer;
use lensray_core::scene::{default_scene, load, Scene};
use lensray_core::settings::{
    light_scene, shot, CameraSettings, EnvironmentSetting, ImageSettings, LensSettings,
    RenderStyle, Settings, Shot,
};
use lensray_core::stats::median;

fn arg(name: &str, default: u32) -> u32 {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().expect("a number"))
}

/// One render: its image, wall seconds and the samples it took.
fn render_once(renderer: &Renderer, shot: &Shot) -> (Image, f64, u64) {
    let start = Instant::now();
    match shot.render.noise_threshold {
        Some(threshold) => {
            let mut sums = Sums::new(shot.camera.width, shot.camera.height);
            let (_, report) = renderer.render_adaptive(shot, threshold, &mut sums, &mut |_, _| {});
            (sums.image(), start.elapsed().as_secs_f64(), report.samples)
        }
        None => {
            let (image, _) = renderer.render(shot, &mut |_, _| {});
            let pixels = (shot.camera.width * shot.camera.height) as u64;
            let samples = pixels * shot.render.spp as u64;
            (image, start.elapsed().as_secs_f64(), samples)
        }
    }
}

/// A row of the table: the median time of `repeat` renders (each the same image).
struct Row {
    label: String,
    seconds: f64,
    rmse: f64,
    mean_spp: f64,
}

fn measure(renderer: &Renderer, shot: &Shot, reference: &Image, repeat: u32, label: String) -> Row {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..repeat {
        let (image, seconds, samples) = render_once(renderer, shot);
        times.push(seconds);
        last = Some((image, samples));
    }
    let (image, samples) = last.expect("at least one run");
    let pixels = (shot.camera.width * shot.camera.height) as f64;
    Row {
        label,
        seconds: median(&times),
        rmse: rmse(&image, reference),
        mean_spp: samples as f64 / pixels,
    }
}

/// Uniform renders and adaptive ones of `base`, the table and the speed-up at uniform 64 spp's
/// error.
fn compare(name: &str, scene: &Scene, base: &Shot, options: &Options) {
    let renderer = Renderer::new(scene);
    let mut reference_shot = base.clone();
    reference_shot.render.spp = options.reference_spp;
    reference_shot.render.seed = 1000;
    let start = Instant::now();
    let (reference, _) = renderer.render(&reference_shot, &mut |_, _| {});
    println!(
        "\n{name}: {}x{}, reference {} spp (seed 1000) in {:.1} s",
        base.camera.width,
        base.camera.height,
        options.reference_spp,
        start.elapsed().as_secs_f64()
    );
    println!("render | median s | RMSE | mean spp");
    let mut uniform_64 = None;
    for &spp in &options.uniform {
        let mut shot = base.clone();
        shot.render.spp = spp;
        let row = measure(
            &renderer,
            &shot,
            &reference,
            options.repeat,
            format!("uniform {spp} spp"),
        );
        print_row(&row);
        if spp == 64 {
            uniform_64 = Some(row);
        }
    }
    let mut best: Option<Row> = None;
    for &threshold in &options.thresholds {
        let mut shot = base.clone();
        shot.render.spp = options.cap;
        shot.render.noise_threshold = Some(threshold);
        let label = format!("adaptive T = {threshold}, cap {}", options.cap);
        let row = measure(&renderer, &shot, &reference, options.repeat, label);
        print_row(&row);
        let good = uniform_64.as_ref().is_some_and(|u| row.rmse <= u.rmse);
        if good && best.as_ref().is_none_or(|b| row.seconds < b.seconds) {
            best = Some(row);
        }
    }
    match (uniform_64, best) {
        (Some(u), Some(b)) => println!(
            "{name}: uniform 64 spp's error ({:.5}) in {:.3} s: {} takes {:.3} s (RMSE {:.5}), {:.2}x faster",
            u.rmse,
            u.seconds,
            b.label,
            b.seconds,
            b.rmse,
            u.seconds / b.seconds
        ),
        (Some(u), None) => println!(
            "{name}: no adaptive render reached uniform 64 spp's error ({:.5})",
            u.rmse
        ),
        _ => {}
    }
}

fn print_row(row: &Row) {
    println!(
        "{} | {:.3} | {:.5} | {:.1}",
        row.label, row.seconds, row.rmse, row.mean_spp
    );
}

struct Options {
    reference_spp: u32,
    repeat: u32,
    cap: u32,
    uniform: Vec<u32>,
    thresholds: Vec<f32>,
}

/// The apples under the studio map through the double Gauss at f/2, `width` x `height`.
fn apples(width: u32, height: u32) -> Option<(Scene, Shot)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let gltf = root.join("../shared/assets/food_apple_01/food_apple_01_4k.gltf");
    if !gltf.exists() {
        println!("\napples: {} is not here, skipped", gltf.display());
        return None;
    }
    let description = load(&gltf).expect("the apples");
    let over = Settings {
        camera: CameraSettings {
            f_number: Some(2.0),
            lens: LensSettings {
                prescription: Some("double-gauss-50".into()),
                ..Default::default()
            },
            ..Default::default()
        },
        image: ImageSettings {
            width: Some(width),
            height: Some(height),
            ..Default::default()
        },
        render: RenderStyle {
            environment: Some(EnvironmentSetting::Map(
                root.join("assets/environments/studio.hdr"),
            )),
            ..Default::default()
        },
        ..Default::default()
    };
    let settings = description.settings.clone().overridden_by(&over);
    let mut scene = description.scene;
    light_scene(&settings, &mut scene).expect("the studio map");
    let shot = shot(&settings, &scene).expect("the apples' shot");
    Some((scene, shot))
}

fn main() {
    let full = std::env::args().any(|a| a == "--bench");
    let (width, height) = if full {
        (arg("--width", 640), arg("--height", 480))
    } else {
        (32, 24)
    };
    let options = if full {
        Options {
            reference_spp: arg("--reference-spp", 1024),
            repeat: arg("--repeat", 3),
            cap: arg("--cap", 256),
            uniform: vec![16, 32, 64, 128],
            thresholds: vec![1.0, 0.5, 0.3, 0.2, 0.15, 0.1, 0.05],
        }
    } else {
        Options {
            reference_spp: 64,
            repeat: 1,
            cap: 64,
            uniform: vec![16, 64],
            thresholds: vec![0.1],
        }
    };
    let description = default_scene();
    let settings = description.settings.clone().overridden_by(&Settings {
        image: ImageSettings {
            width: Some(width),
            height: Some(height),
            ..Default::default()
        },
        ..Default::default()
    });
    let base = shot(&settings, &description.scene).expect("the default shot");
    compare("default scene", &description.scene, &base, &options);
    if let Some((scene, shot)) = apples(width / 2, height / 2) {
        compare(
            "apples, studio map, double Gauss 50 mm f/2",
            &scene,
            &shot,
            &options,
        );
    }
}
