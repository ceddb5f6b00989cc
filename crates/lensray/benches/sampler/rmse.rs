//! Parts 1 and 2: RMSE against a converged reference at powers of two, and between them.

use std::time::Instant;

use lensray_core::film::compare::rmse;
use lensray_core::reference::Renderer;
use lensray_core::settings::{RenderSettings, Shot};

use crate::{mean_rmse, reference, render, resolved, scenes, slope, Options, KINDS, SEEDS};

/// Both samplers' RMSE at powers of two on each scene, with the slope between 16 and 256 spp.
pub fn rmse_table(o: &Options) {
    println!(
        "== RMSE against a converged reference ({}x{}, reference {} spp, lit; RMS over {} seeds at <= 16 spp)",
        o.width,
        o.height,
        o.reference_spp,
        SEEDS.len()
    );
    for (name, desc) in scenes() {
        let renderer = Renderer::new(&desc.scene);
        let shot = resolved(&desc, o.width, o.height, None);
        let start = Instant::now();
        let (reference, own) = reference(&renderer, &shot, o.reference_spp);
        println!(
            "{name}: reference in {:.1} s, its own RMSE ~ {own:.5}",
            start.elapsed().as_secs_f64()
        );
        let mut rows = Vec::new();
        for kind in KINDS {
            let estimate = |spp, seed| {
                let s = Shot {
                    camera: shot.camera.clone(),
                    render: RenderSettings {
                        spp,
                        seed,
                        sampler: kind,
                        ..shot.render
                    },
                };
                render(&renderer, &s)
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

/// The error between powers of two on the default scene, each sampler scaled by its
/// convergence rate.
pub fn between_powers(o: &Options) {
    let (name, desc) = scenes().remove(0);
    println!(
        "== Between powers of two ({name} scene, {}x{}, lit, RMS over {} seeds)",
        o.width,
        o.height,
        SEEDS.len()
    );
    let renderer = Renderer::new(&desc.scene);
    let shot = resolved(&desc, o.width, o.height, None);
    let (reference, _) = reference(&renderer, &shot, o.reference_spp);
    println!("| spp | sobol RMSE | sobol RMSE x spp^0.75 | independent RMSE | independent RMSE x spp^0.5 |");
    for &spp in &o.between {
        let e: Vec<f64> = KINDS
            .iter()
            .map(|&kind| {
                let sum: f64 = SEEDS
                    .iter()
                    .map(|&seed| {
                        let s = Shot {
                            camera: shot.camera.clone(),
                            render: RenderSettings {
                                spp,
                                seed,
                                sampler: kind,
                                ..shot.render
                            },
                        };
                        rmse(&render(&renderer, &s), &reference).powi(2)
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
