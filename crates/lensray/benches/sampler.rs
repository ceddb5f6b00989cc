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

#[path = "sampler/edges.rs"]
mod edges;

use std::hint::black_box;
use std::time::Instant;

use glam::{UVec2, Vec2, Vec3};
use rayon::prelude::*;

use lensray_core::camera::Camera;
use lensray_core::film::compare::rmse;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::sampler::owen::{owen_scramble_reversed, shuffle_index};
use lensray_core::sampler::quality::{camera_matrices, t_value, GeneratorMatrix};
use lensray_core::sampler::scrambled_sobol::{scramble_seed, shuffle_seed};
use lensray_core::sampler::sobol::{sobol, sobol_reversed, LENS_INDEX_COLUMNS, SOBOL_MATRICES};
use lensray_core::sampler::{
    pixel_camera_samples, pixel_key, pixel_sampler, sobol_pixel, sobol_sample, unit_float,
    SamplerKind,
};
use lensray_core::scene::file::SceneDescription;
use lensray_core::settings::shot;
use lensray_core::settings::Settings;
use lensray_core::settings::{RenderSettings, Shading};
use lensray_vulkan::{GpuOptions, GpuRenderer};

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

fn resolved(
    desc: &SceneDescription,
    width: u32,
    height: u32,
    shading: Option<Shading>,
) -> (Camera, RenderSettings) {
    let mut over = Settings::default();
    over.image.width = Some(width);
    over.image.height = Some(height);
    over.render.shading = shading;
    let r = shot(&desc.settings.clone().overridden_by(&over), &desc.scene).expect("resolve");
    (r.camera, r.render)
}

fn render(renderer: &Renderer, camera: &Camera, settings: &RenderSettings) -> Image {
    renderer.render(camera, settings, &mut |_, _| {}).0
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

/// The converged image (the Sobol' sampler at `spp`, as two halves with other seeds) and an
/// estimate of its own RMSE: half the RMSE between the halves.
fn reference(
    renderer: &Renderer,
    camera: &Camera,
    settings: &RenderSettings,
    spp: u32,
) -> (Image, f64) {
    let halves: Vec<Image> = REFERENCE_SEEDS
        .iter()
        .map(|&seed| {
            let s = RenderSettings {
                spp: spp / 2,
                seed,
                sampler: SamplerKind::Sobol,
                ..*settings
            };
            render(renderer, camera, &s)
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

fn rmse_table(o: &Options) {
    println!(
        "== RMSE against a converged reference ({}x{}, reference {} spp, lit; RMS over {} seeds at <= 16 spp)",
        o.width,
        o.height,
        o.reference_spp,
        SEEDS.len()
    );
    for (name, desc) in scenes() {
        let renderer = Renderer::new(&desc.scene);
        let (camera, settings) = resolved(&desc, o.width, o.height, None);
        let start = Instant::now();
        let (reference, own) = reference(&renderer, &camera, &settings, o.reference_spp);
        println!(
            "{name}: reference in {:.1} s, its own RMSE ~ {own:.5}",
            start.elapsed().as_secs_f64()
        );
        let mut rows = Vec::new();
        for kind in KINDS {
            let estimate = |spp, seed| {
                let s = RenderSettings {
                    spp,
                    seed,
                    sampler: kind,
                    ..settings
                };
                render(&renderer, &camera, &s)
            };
            let errors: Vec<f64> = o
                .powers
                .iter()
                .map(|&spp| mean_rmse(&estimate, &reference, spp, o.full))
                .collect();
            rows.push(errors);
        }
        print!("| {name} | spp |");
        for spp in &o.powers {
            print!(" {spp} |");
        }
        println!(" slope 16-256 |");
        for (kind, errors) in KINDS.iter().zip(&rows) {
            print!("| {name} | {kind} |");
            for e in errors {
                print!(" {e:.5} |");
            }
            match slope(&o.powers, errors, 16, 256) {
                Some(s) => println!(" {s:.3} |"),
                None => println!(" - |"),
            }
        }
        print!("| {name} | ratio |");
        for (s, i) in rows[0].iter().zip(&rows[1]) {
            print!(" {:.3} |", s / i);
        }
        println!();
    }
}

fn between_powers(o: &Options) {
    let (name, desc) = scenes().remove(0);
    println!(
        "== Between powers of two ({name} scene, {}x{}, lit, RMS over {} seeds)",
        o.width,
        o.height,
        SEEDS.len()
    );
    let renderer = Renderer::new(&desc.scene);
    let (camera, settings) = resolved(&desc, o.width, o.height, None);
    let (reference, _) = reference(&renderer, &camera, &settings, o.reference_spp);
    println!("| spp | sobol RMSE | sobol RMSE x spp^0.75 | independent RMSE | independent RMSE x spp^0.5 |");
    for &spp in &o.between {
        let e: Vec<f64> = KINDS
            .iter()
            .map(|&kind| {
                let sum: f64 = SEEDS
                    .iter()
                    .map(|&seed| {
                        let s = RenderSettings {
                            spp,
                            seed,
                            sampler: kind,
                            ..settings
                        };
                        rmse(&render(&renderer, &camera, &s), &reference).powi(2)
                    })
                    .sum();
                (sum / SEEDS.len() as f64).sqrt()
            })
            .collect();
        let n = f64::from(spp);
        println!(
            "| {spp} | {:.5} | {:.4} | {:.5} | {:.4} |",
            e[0],
            e[0] * n.powf(0.75),
            e[1],
            e[1] * n.sqrt()
        );
    }
}

/// Film offset and lens position of sample `index` of the pixel with key `key`.
type Candidate = fn(u32, u32) -> [f32; 4];

/// The default: film pair at the index, lens pair at the lens index.
fn candidate_default(key: u32, index: u32) -> [f32; 4] {
    sobol_sample(&sobol_pixel(key), index)
}

/// Padded 2-D pairs (Burley 2020): the lens pair at a per-pixel random shuffle of the index.
fn candidate_shuffled_pairs(key: u32, index: u32) -> [f32; 4] {
    let lens = shuffle_index(index, shuffle_seed(key, 1));
    std::array::from_fn(|d| {
        let i = if d < 2 { index } else { lens };
        let seed = scramble_seed(key, d as u32);
        unit_float(owen_scramble_reversed(
            sobol_reversed(d as u32 % 2, i),
            seed,
        ))
    })
}

/// Sobol' dimensions 1-4 (Joe-Kuo), each Owen-scrambled: jointly stratified 4-D points whose
/// lens pair is not a (0, 2)-sequence.
fn candidate_joe_kuo_4d(key: u32, index: u32) -> [f32; 4] {
    std::array::from_fn(|d| {
        let seed = scramble_seed(key, d as u32);
        unit_float(owen_scramble_reversed(sobol(d, index).reverse_bits(), seed))
    })
}

/// The pairs without the lens shuffle: lens point i goes with film point i.
fn candidate_pairs_unshuffled(key: u32, index: u32) -> [f32; 4] {
    std::array::from_fn(|d| {
        let seed = scramble_seed(key, d as u32);
        unit_float(owen_scramble_reversed(
            sobol(d % 2, index).reverse_bits(),
            seed,
        ))
    })
}

fn candidate_independent(key: u32, index: u32) -> [f32; 4] {
    lensray_core::sampler::independent_sample(key, index)
}

/// An unlit render (the diffuse colour seen, or the background) with the candidate's samples.
fn unlit_estimate(
    renderer: &Renderer,
    desc: &SceneDescription,
    camera: &Camera,
    settings: &RenderSettings,
    candidate: Candidate,
    spp: u32,
    seed: u32,
) -> Image {
    let mut image = Image::new(camera.width, camera.height);
    image
        .pixels
        .par_chunks_mut(camera.width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, out) in row.iter_mut().enumerate() {
                let key = pixel_key(seed, y as u32 * camera.width + x as u32);
                let mut sum = Vec3::ZERO;
                for s in 0..spp {
                    let u = candidate(key, s);
                    let film = Vec2::new(x as f32 + u[0], y as f32 + u[1]);
                    let ray = camera.generate_ray(film, Vec2::new(u[2], u[3]));
                    sum += match renderer.intersect(&ray) {
                        Some(hit) => {
                            let m = renderer.surface_point(&ray, &hit).material;
                            desc.scene.materials[m as usize].diffuse
                        }
                        None => settings.background,
                    };
                }
                *out = sum / spp as f32;
            }
        });
    image
}

/// The error ratio to independent sampling on single straight edges (`edges.rs`), by blur radius.
fn edges_table(o: &Options) {
    let (trials, reference_spp, spp) = if o.full {
        (4000, 4096, vec![4, 16, 64])
    } else {
        (40, 256, vec![4, 16])
    };
    println!(
        "== One straight edge through pixel and lens: RMSE / independent sampling's ({trials} random edges, reference {reference_spp} spp)"
    );
    let candidates: [(&str, Candidate); 4] = [
        ("pairs at the lens index (default)", candidate_default),
        ("Joe-Kuo 4-D", candidate_joe_kuo_4d),
        ("pairs, randomly shuffled", candidate_shuffled_pairs),
        ("independent", candidate_independent),
    ];
    print!("| where the edge is | design |");
    for n in &spp {
        print!(" {n} spp |");
    }
    println!();
    let blurs = [
        edges::Blur::Radius(0.0),
        edges::Blur::Radius(0.25),
        edges::Blur::Radius(0.5),
        edges::Blur::Radius(1.0),
        edges::Blur::Radius(2.0),
        edges::Blur::Radius(4.0),
        edges::Blur::Radius(16.0),
        edges::Blur::LensOnly,
        edges::Blur::LensOnlySquare,
    ];
    let functions: Vec<edges::Design> = candidates.iter().map(|c| &c.1 as edges::Design).collect();
    for blur in blurs {
        let mse = edges::mean_squared_errors(blur, &functions, &spp, trials, reference_spp);
        let independent = mse.last().expect("independent is the last candidate");
        for ((name, _), errors) in candidates.iter().zip(&mse).take(candidates.len() - 1) {
            print!("| {} | {name} |", blur.label());
            for (e, i) in errors.iter().zip(independent) {
                print!(" {:.3} |", (e / i).sqrt());
            }
            println!();
        }
    }
    println!("== Every lens index map of the first 16 samples on edges blurred by 0.25-4 px: RMSE / independent sampling's, geometric mean over the radii");
    println!("| rank | columns 0-3 | 4 spp | 16 spp |");
    let shipped: [u32; 4] = std::array::from_fn(|c| LENS_INDEX_COLUMNS[c]);
    let maps = edges::first_sixteen_lens_maps(&candidate_independent, trials, reference_spp);
    for (rank, (columns, ratios)) in maps.iter().enumerate() {
        if rank < 5 || rank + 1 == maps.len() || *columns == shipped {
            let mark = if *columns == shipped {
                " (shipped)"
            } else {
                ""
            };
            println!(
                "| {} | {columns:?}{mark} | {:.3} | {:.3} |",
                rank + 1,
                ratios[0],
                ratios[1]
            );
        }
    }
}

fn decision(o: &Options) {
    println!(
        "== Joint 4-D Sobol' or padded 2-D pairs: unlit RMSE ({}x{}, reference {} spp)",
        o.width, o.height, o.reference_spp
    );
    let candidates: [(&str, Candidate); 5] = [
        ("pairs at the lens index (default)", candidate_default),
        ("pairs, randomly shuffled", candidate_shuffled_pairs),
        ("Joe-Kuo 4-D", candidate_joe_kuo_4d),
        ("pairs, same index", candidate_pairs_unshuffled),
        ("independent", candidate_independent),
    ];
    for (name, desc) in scenes() {
        let renderer = Renderer::new(&desc.scene);
        let (camera, settings) = resolved(&desc, o.width, o.height, Some(Shading::Unlit));
        let (reference, own) = reference(&renderer, &camera, &settings, o.reference_spp);
        // The default candidate is the renderer's own sampler: same image, bit for bit.
        let check = RenderSettings {
            spp: 4,
            seed: 9,
            ..settings
        };
        assert_eq!(
            render(&renderer, &camera, &check).pixels,
            unlit_estimate(
                &renderer,
                &desc,
                &camera,
                &settings,
                candidate_default,
                4,
                9
            )
            .pixels,
            "the benchmark's estimator differs from the renderer"
        );
        println!("{name}: reference's own RMSE ~ {own:.5}");
        print!("| {name} | candidate |");
        for spp in &o.powers {
            print!(" {spp} |");
        }
        println!(" slope 16-256 |");
        for (label, candidate) in candidates {
            let estimate = |spp, seed| {
                unlit_estimate(&renderer, &desc, &camera, &settings, candidate, spp, seed)
            };
            let errors: Vec<f64> = o
                .powers
                .iter()
                .map(|&spp| mean_rmse(&estimate, &reference, spp, o.full))
                .collect();
            print!("| {name} | {label} |");
            for e in &errors {
                print!(" {e:.5} |");
            }
            match slope(&o.powers, &errors, 16, 256) {
                Some(s) => println!(" {s:.3} |"),
                None => println!(" - |"),
            }
        }
    }
}

/// The generator matrices of the candidates with a digital structure (the shuffled pairs have
/// none across pairs: their film-lens t-values are those of random pairings).
fn t_value_table() {
    let [i, p, c3, c4] = SOBOL_MATRICES;
    let default = camera_matrices();
    let designs: [(&str, [GeneratorMatrix; 4]); 2] = [
        ("pairs at the lens index (default)", default),
        ("Joe-Kuo 4-D", [i, p, c3, c4]),
    ];
    println!("== t-values of 2^m points (0 = one point in every elementary interval)");
    for (name, [fx, fy, lx, ly]) in designs {
        println!("{name}:");
        println!("| m | film | lens | film x, lens x | film y, lens y | film x, lens y | film y, lens x | 4-D |");
        for m in 1..=12 {
            let t = |ms: &[&GeneratorMatrix]| t_value(ms, m);
            println!(
                "| {m} | {} | {} | {} | {} | {} | {} | {} |",
                t(&[&fx, &fy]),
                t(&[&lx, &ly]),
                t(&[&fx, &lx]),
                t(&[&fy, &ly]),
                t(&[&fx, &ly]),
                t(&[&fy, &lx]),
                t(&[&fx, &fy, &lx, &ly])
            );
        }
    }
}

/// The weighted t-values that `--search-lens-index` minimises for lens index columns `u`:
/// matched film-lens pairs and the 4-D set weigh 3, crossed pairs 2, m = 1..16 (4-D to 12).
fn lens_index_objective(u: &[u32; 16]) -> u32 {
    let index = |i: u32| -> u32 {
        let mut lens = i & 0xffff_0000;
        for (bit, &column) in u.iter().enumerate() {
            if (i >> bit) & 1 == 1 {
                lens ^= column;
            }
        }
        lens
    };
    let [fx, fy, _, _] = SOBOL_MATRICES;
    let lx: GeneratorMatrix = std::array::from_fn(|j| sobol(0, index(1 << j)));
    let ly: GeneratorMatrix = std::array::from_fn(|j| sobol(1, index(1 << j)));
    (1..=16)
        .map(|m| {
            let t = |ms: &[&GeneratorMatrix]| t_value(ms, m);
            3 * (t(&[&fx, &lx]) + t(&[&fy, &ly]))
                + 2 * (t(&[&fx, &ly]) + t(&[&fy, &lx]))
                + if m <= 12 {
                    3 * t(&[&fx, &fy, &lx, &ly])
                } else {
                    0
                }
        })
        .sum()
}

/// Hill climbing over the free bits of the lens index columns (bit c set, random lower bits):
/// a random column's lower bits change, kept when the objective does not grow.
fn search_lens_index(args: &[String]) {
    let value = |name: &str, default: u32| -> u32 {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .map(|v| v.parse().expect("a number"))
            .unwrap_or(default)
    };
    let mut state = lensray_core::sampler::hash_u32(value("--seed", 3));
    let mut next = || {
        state = lensray_core::sampler::hash_u32(state.wrapping_add(0x9e37_79b9));
        state
    };
    let from_scratch = args.iter().any(|a| a == "--from-scratch");
    let fixed = if from_scratch { 1 } else { 12 };
    let mut u: [u32; 16] = std::array::from_fn(|c| {
        if c < fixed && !from_scratch {
            LENS_INDEX_COLUMNS[c]
        } else {
            (1 << c) | (next() & ((1 << c) - 1))
        }
    });
    let mut best = lens_index_objective(&u);
    println!(
        "start: objective {best}; the shipped columns score {}",
        lens_index_objective(&LENS_INDEX_COLUMNS)
    );
    for _ in 0..value("--iterations", 1500) {
        let c = fixed + (next() as usize % (16 - fixed));
        let mut v = u;
        v[c] ^= next() & ((1 << c) - 1);
        let o = lens_index_objective(&v);
        if o <= best {
            (u, best) = (v, o);
        }
    }
    println!("objective {best}: LENS_INDEX_COLUMNS = {u:?}");
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Seconds to generate every camera sample of a render, as the renderer does (rows in parallel;
/// per pixel the set-up, then packets of 16 samples).
fn generation_seconds(camera: &Camera, settings: &RenderSettings) -> f64 {
    let start = Instant::now();
    let total: f32 = (0..camera.height)
        .into_par_iter()
        .map(|y| {
            let mut sum = [0.0f32; 16];
            for x in 0..camera.width {
                let state = pixel_sampler(
                    settings.sampler,
                    settings.seed,
                    UVec2::new(x, y),
                    camera.width,
                );
                for first in (0..settings.spp).step_by(16) {
                    let dims = pixel_camera_samples::<16>(&state, first);
                    for dim in black_box(dims) {
                        for (s, v) in sum.iter_mut().zip(dim) {
                            *s += v;
                        }
                    }
                }
            }
            sum.iter().sum::<f32>()
        })
        .sum();
    black_box(total);
    start.elapsed().as_secs_f64()
}

fn cost(o: &Options) {
    let (_, desc) = scenes().remove(0);
    let runs = if o.full { 5 } else { 1 };
    println!(
        "== Cost of sample generation (default scene, {}x{}, 16 spp, lit; medians of {runs})",
        o.cost_width, o.cost_height
    );
    let renderer = Renderer::new(&desc.scene);
    let (camera, settings) = resolved(&desc, o.cost_width, o.cost_height, None);
    for kind in KINDS {
        let s = RenderSettings {
            spp: 16,
            sampler: kind,
            ..settings
        };
        let _ = render(&renderer, &camera, &s);
        let render_s = median(
            (0..runs)
                .map(|_| {
                    renderer
                        .render(&camera, &s, &mut |_, _| {})
                        .1
                        .elapsed
                        .as_secs_f64()
                })
                .collect(),
        );
        let generate_s = median((0..runs).map(|_| generation_seconds(&camera, &s)).collect());
        println!(
            "CPU {kind}: render {:.1} ms, samples alone {:.2} ms = {:.2} % ({:.2} ns per sample)",
            render_s * 1e3,
            generate_s * 1e3,
            100.0 * generate_s / render_s,
            generate_s * 1e9 / f64::from(camera.width * camera.height * 16)
        );
    }
    let mut gpu = match GpuRenderer::new(&GpuOptions::default()) {
        Ok(gpu) => gpu,
        Err(e) => {
            println!("GPU: skipped ({e})");
            return;
        }
    };
    gpu.load_scene(&desc.scene).expect("load scene");
    for kind in KINDS {
        let s = RenderSettings {
            spp: 16,
            sampler: kind,
            ..settings
        };
        let _ = gpu.render(&camera, &s, &mut |_, _| {}).expect("GPU render");
        let mut trace = Vec::new();
        let mut generate = Vec::new();
        for _ in 0..runs.min(3) {
            let before = gpu.timings().trace_gpu_ms;
            let _ = gpu.render(&camera, &s, &mut |_, _| {}).expect("GPU render");
            trace.push(gpu.timings().trace_gpu_ms - before);
            generate.push(
                gpu.sample_generation_ms(&camera, &s)
                    .expect("GPU sample cost"),
            );
        }
        let (trace, generate) = (median(trace), median(generate));
        println!(
            "GPU {kind} ({}): trace pass {trace:.1} ms, samples alone {generate:.2} ms = {:.2} %",
            gpu.device_name(),
            100.0 * generate / trace
        );
    }
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
