//! The samplers' error and cost (docs/sampler.md holds the figures):
//!
//! 1. RMSE against a converged reference at 4, 16, 64 and 256 spp, both samplers, on the default
//!    scene and the Cornell scene (their own camera and lit shading), through the CPU renderer;
//!    the slope of log RMSE between 16 and 256 spp; the reference's own error.
//! 2. What the error does between powers of two (default scene).
//! 3. The design decision, unlit so that only the visibility through the lens (depth of field) is
//!    measured: the default (film and lens pairs jointly stratified through the lens index)
//!    against padded, randomly shuffled 2-D pairs (Burley 2020), Joe and Kuo's 4-D Sobol' points,
//!    the pairs without any shuffle, and independent samples; with the t-values of each design.
//! 4. The same designs on single straight edges seen through the lens, by blur radius: the floor
//!    of the error ratio to independent sampling on the integrand that dominates the renders'.
//! 5. The cost of sample generation as a fraction of the render time, CPU and GPU.
//!
//! `cargo bench --bench sampler [-- --width W --height H --reference-spp N --only PART]` measures
//! (default 320x240, reference 4096 spp; PART is one of t-values, cost, rmse, between, decision,
//! edges). Under `cargo test --all-targets` (no `--bench` argument) it only
//! runs a tiny smoke version. The GPU part is skipped with a line when no ray-query device exists.
//! `cargo bench --bench sampler -- --search-lens-index [--seed S --iterations N]` reruns the
//! search that chose `LENS_INDEX_COLUMNS` (from their first 12 columns, or from scratch with
//! `--from-scratch`).

#[path = "sampler/cost.rs"]
mod cost;
#[path = "sampler/designs.rs"]
mod designs;
#[path = "sampler/edges.rs"]
mod edges;
#[path = "sampler/lens_index.rs"]
mod lens_index;
#[path = "sampler/rmse.rs"]
mod rmse;

use std::time::Instant;

use lensray_core::film::compare::rmse;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::file::SceneDescription;
use lensray_core::settings::shot;
use lensray_core::settings::Settings;
use lensray_core::settings::{RenderSettings, Shading, Shot};

use cost::cost;
use designs::{decision, edges_table, t_value_table};
use lens_index::search_lens_index;
use rmse::{between_powers, rmse_table};

const KINDS: [SamplerKind; 2] = [SamplerKind::Sobol, SamplerKind::Independent];
/// Seeds of the measured renders; the reference uses others.
const SEEDS: [u32; 4] = [1, 2, 3, 4];
const REFERENCE_SEEDS: [u32; 2] = [1_000_001, 1_000_002];

struct Options {
    width: u32,
    height: u32,
    reference_spp: u32,
    powers: Vec<u32>,
    between: Vec<u32>,
    cost_width: u32,
    cost_height: u32,
    full: bool,
}

fn options() -> Options {
    let args: Vec<String> = std::env::args().collect();
    let full = args.iter().any(|a| a == "--bench");
    let value = |name: &str, default: u32| -> u32 {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .map(|v| {
                v.parse()
                    .unwrap_or_else(|_| panic!("{name} {v}: not a number"))
            })
            .unwrap_or(default)
    };
    if full {
        Options {
            width: value("--width", 320),
            height: value("--height", 240),
            reference_spp: value("--reference-spp", 4096),
            powers: vec![4, 16, 64, 256],
            between: vec![8, 10, 12, 14, 16, 20, 24, 28, 32],
            cost_width: 640,
            cost_height: 480,
            full,
        }
    } else {
        Options {
            width: 24,
            height: 16,
            reference_spp: 64,
            powers: vec![4, 16],
            between: vec![4, 6],
            cost_width: 24,
            cost_height: 16,
            full,
        }
    }
}

fn scenes() -> Vec<(&'static str, SceneDescription)> {
    let cornell =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/cornell/cornell.toml");
    vec![
        ("default", lensray_core::scene::builtin::default_scene()),
        (
            "cornell",
            lensray_core::scene::file::load(&cornell).expect("load the Cornell box"),
        ),
    ]
}

fn resolved(desc: &SceneDescription, width: u32, height: u32, shading: Option<Shading>) -> Shot {
    let mut over = Settings::default();
    over.image.width = Some(width);
    over.image.height = Some(height);
    over.render.shading = shading;
    shot(&desc.settings.clone().overridden_by(&over), &desc.scene).expect("resolve")
}

/// The CPU reference's image of `shot`.
fn render(renderer: &Renderer, shot: &Shot) -> Image {
    renderer.render(shot, &mut |_, _| {}).0
}

/// The average of `images`.
fn average(images: &[Image]) -> Image {
    let mut out = Image::new(images[0].width, images[0].height);
    for img in images {
        for (o, p) in out.pixels.iter_mut().zip(&img.pixels) {
            *o += *p;
        }
    }
    for o in &mut out.pixels {
        *o /= images.len() as f32;
    }
    out
}

/// The converged image of `shot` (the Sobol' sampler at `spp`, as two halves with other seeds)
/// and an estimate of its own RMSE: half the RMSE between the halves.
fn reference(renderer: &Renderer, shot: &Shot, spp: u32) -> (Image, f64) {
    let halves: Vec<Image> = REFERENCE_SEEDS
        .iter()
        .map(|&seed| {
            let half = Shot {
                camera: shot.camera.clone(),
                render: RenderSettings {
                    spp: spp / 2,
                    seed,
                    sampler: SamplerKind::Sobol,
                    ..shot.render
                },
            };
            render(renderer, &half)
        })
        .collect();
    let own_error = rmse(&halves[0], &halves[1]) / 2.0;
    (average(&halves), own_error)
}

/// RMSE at `spp`, the root of the mean square over a few seeds (more at low spp, where a single
/// image's RMSE is noisier).
fn mean_rmse(estimate: &dyn Fn(u32, u32) -> Image, reference: &Image, spp: u32, full: bool) -> f64 {
    let seeds = if spp <= 16 && full {
        &SEEDS[..]
    } else {
        &SEEDS[..1]
    };
    let sum: f64 = seeds
        .iter()
        .map(|&seed| rmse(&estimate(spp, seed), reference).powi(2))
        .sum();
    (sum / seeds.len() as f64).sqrt()
}

fn slope(spp: &[u32], errors: &[f64], from: u32, to: u32) -> Option<f64> {
    let at = |n| spp.iter().position(|&s| s == n).map(|i| errors[i]);
    Some((at(from)? / at(to)?).ln() / (f64::from(to) / f64::from(from)).ln())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--search-lens-index") {
        search_lens_index(&args);
        return;
    }
    let o = options();
    let start = Instant::now();
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1));
    let run = |part: &str| only.is_none_or(|o| o == part);
    if o.full && run("t-values") {
        t_value_table();
    }
    if run("cost") {
        cost(&o);
    }
    if run("rmse") {
        rmse_table(&o);
    }
    if run("between") {
        between_powers(&o);
    }
    if run("decision") {
        decision(&o);
    }
    if run("edges") {
        edges_table(&o);
    }
    println!("(benchmark took {:.0} s)", start.elapsed().as_secs_f64());
}
