//! Parts 3 and 4: the sampler designs compared, unlit on the scenes and on single straight
//! edges, with the t-values of those that have a digital structure.

use glam::Vec2;
use glam::Vec3;
use rayon::prelude::*;

use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::sampler::owen::{owen_scramble_reversed, shuffle_index};
use lensray_core::sampler::quality::{camera_matrices, t_value, GeneratorMatrix};
use lensray_core::sampler::scrambled_sobol::{scramble_seed, shuffle_seed};
use lensray_core::sampler::sobol::{sobol, sobol_reversed, LENS_INDEX_COLUMNS, SOBOL_MATRICES};
use lensray_core::sampler::{pixel_key, sobol_pixel, sobol_sample, unit_float};
use lensray_core::scene::file::SceneDescription;
use lensray_core::settings::{RenderSettings, Shading, Shot};

use crate::{edges, mean_rmse, reference, render, resolved, scenes, slope, Options};
use lensray_core::sampler::CameraSample;

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

/// An unlit render of `shot` (the diffuse colour seen, or the background) with the candidate's
/// samples.
fn unlit_estimate(
    renderer: &Renderer,
    desc: &SceneDescription,
    shot: &Shot,
    candidate: Candidate,
    spp: u32,
    seed: u32,
) -> Image {
    let (camera, settings) = (&shot.camera, &shot.render);
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
                    let ray =
                        camera.first_order_ray(CameraSample::new(film, Vec2::new(u[2], u[3])));
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
pub fn edges_table(o: &Options) {
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

pub fn decision(o: &Options) {
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
        let shot = resolved(&desc, o.width, o.height, Some(Shading::Unlit));
        let (reference, own) = reference(&renderer, &shot, o.reference_spp);
        // The default candidate is the renderer's own sampler: same image, bit for bit.
        let check = Shot {
            camera: shot.camera.clone(),
            render: RenderSettings {
                spp: 4,
                seed: 9,
                ..shot.render
            },
        };
        assert_eq!(
            render(&renderer, &check).pixels,
            unlit_estimate(&renderer, &desc, &shot, candidate_default, 4, 9).pixels,
            "the benchmark's estimator differs from the renderer"
        );
        println!("{name}: reference's own RMSE ~ {own:.5}");
        print!("| {name} | candidate |");
        for spp in &o.powers {
            print!(" {spp} |");
        }
        println!(" slope 16-256 |");
        for (label, candidate) in candidates {
            let estimate =
                |spp, seed| unlit_estimate(&renderer, &desc, &shot, candidate, spp, seed);
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
pub fn t_value_table() {
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
