//! `--search-lens-index`: the search that chose `LENS_INDEX_COLUMNS`.

use lensray_core::sampler::quality::{t_value, GeneratorMatrix};
use lensray_core::sampler::sobol::{sobol, LENS_INDEX_COLUMNS, SOBOL_MATRICES};

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
pub fn search_lens_index(args: &[String]) {
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
