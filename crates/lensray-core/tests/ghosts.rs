//! Ghost paths (`optics::trace`'s `trace_ghost_at`) against an independent tracer: for each
//! lens, the real chief ray at 5 and 10 degrees reflected by surface j, back to surface i,
//! reflected again and on to the paraxial focal plane, for every pair of refracting surfaces,
//! at the d line. The standard-library Python tracer of scripts/optics/ghost_reference.py
//! stored where each ghost path lands and which paths the clear apertures and the stop block
//! (`optics_reference/ghosts.stdlib.json`).

use std::collections::BTreeMap;

use glam::DVec3;
use lensray_core::optics::builtin;
use lensray_core::optics::trace::wide::{Elements, LensRay};

#[derive(serde::Deserialize)]
struct Ghost {
    i: usize,
    j: usize,
    x_mm: f64,
    y_mm: f64,
}

#[derive(serde::Deserialize)]
struct ChiefRay {
    field_deg: f64,
    origin: [f64; 3],
    direction: [f64; 3],
    ghosts: Vec<Ghost>,
}

#[derive(serde::Deserialize)]
struct LensGhosts {
    plane_z_mm: f64,
    rays: Vec<ChiefRay>,
}

#[derive(serde::Deserialize)]
struct Reference {
    lenses: BTreeMap<String, LensGhosts>,
}

#[test]
fn ghost_paths_land_where_an_independent_tracer_puts_them() {
    let reference: Reference =
        serde_json::from_str(include_str!("optics_reference/ghosts.stdlib.json")).unwrap();
    let mut worst = 0.0f64;
    let mut compared = 0;
    for (name, lens) in &reference.lenses {
        let prescription = builtin::lens(name).expect("a built-in lens");
        let elements = Elements::new(&prescription);
        let n = elements.interfaces.len();
        for chief in &lens.rays {
            let ray = LensRay {
                origin: DVec3::from(chief.origin),
                direction: DVec3::from(chief.direction),
            };
            let expected: BTreeMap<(usize, usize), &Ghost> =
                chief.ghosts.iter().map(|g| ((g.i, g.j), g)).collect();
            for i in 0..n {
                for j in i + 1..n {
                    let landed = elements.trace_ghost_at(ray, (i, j), 0.0).map(|out| {
                        let t = (lens.plane_z_mm - out.origin.z) / out.direction.z;
                        out.origin + t * out.direction
                    });
                    let what = format!("{name} at {} deg, ghost ({i}, {j})", chief.field_deg);
                    match (landed, expected.get(&(i, j))) {
                        (Some(p), Some(g)) => {
                            let d = (p.x - g.x_mm).abs().max((p.y - g.y_mm).abs());
                            worst = worst.max(d);
                            compared += 1;
                            // Both trace in f64; Newton's iteration on an asphere stops at
                            // 1e-12 here and 1e-15 there: within 1e-6 mm on the film.
                            assert!(
                                d < 1e-6,
                                "{what}: lands at {p}, the reference at ({}, {})",
                                g.x_mm,
                                g.y_mm
                            );
                        }
                        (None, None) => {}
                        (got, want) => panic!(
                            "{what}: lensray {} it, the reference {}",
                            if got.is_some() { "passes" } else { "blocks" },
                            if want.is_some() {
                                "passes it"
                            } else {
                                "blocks it"
                            }
                        ),
                    }
                }
            }
        }
    }
    println!("{compared} ghost paths: largest difference {worst:.2e} mm");
    assert!(compared > 100, "only {compared} ghost paths compared");
}
