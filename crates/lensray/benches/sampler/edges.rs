//! How well each sampler design integrates one straight edge seen through the thin lens, away
//! from any scene: the error ratio to independent sampling that a design can reach on the
//! integrand that dominates a render's error (docs/sampler.md, "The floor on edges").
//!
//! A pixel sees the point `p = (film - 1/2) + r * disk(lens)` of an occluder's plane, in pixels,
//! where `r` is the blur radius there (the circle of confusion's radius in pixels, 0 in focus)
//! and `disk` the lens's concentric map. The occluder covers the half-plane `n . p > c`, with the
//! direction `n` uniform and the offset `c` uniform over the positions where the edge crosses
//! what the pixel sees: a pixel-sized edge at a random place. The pixel's value is the covered
//! fraction.

use glam::Vec2;
use rayon::prelude::*;

use lensray_core::camera::thin_lens::concentric_sample_disk;
use lensray_core::sampler::owen::owen_scramble_reversed;
use lensray_core::sampler::scrambled_sobol::scramble_seed;
use lensray_core::sampler::sobol::{sobol_reversed, LENS_INDEX_COLUMNS};
use lensray_core::sampler::{hash_u32, pixel_key, unit_float};

/// A sampler design: film x, film y, lens x, lens y of sample `index` of the pixel with `key`.
pub type Design<'a> = &'a (dyn Fn(u32, u32) -> [f32; 4] + Sync);

/// Where the edge lies: through the pixel and the lens jointly, or through the lens only.
#[derive(Clone, Copy)]
pub enum Blur {
    /// Film and lens, with the blur radius in pixels (0: in focus).
    Radius(f32),
    /// The lens alone (a blur radius far above a pixel), mapped to the disk.
    LensOnly,
    /// The lens alone without the disk map (a square aperture): what the map costs.
    LensOnlySquare,
}

impl Blur {
    pub fn label(self) -> String {
        match self {
            Blur::Radius(0.0) => "in focus".into(),
            Blur::Radius(r) => format!("blur radius {r} px"),
            Blur::LensOnly => "lens only (radius >> 1 px)".into(),
            Blur::LensOnlySquare => "lens only, square aperture (control)".into(),
        }
    }
}

/// One random edge: its normal and offset.
struct Edge {
    normal: Vec2,
    offset: f32,
}

impl Edge {
    /// Edge `trial`, uniform among those crossing what the pixel sees under `blur`.
    fn random(trial: u32, blur: Blur) -> Edge {
        let h = hash_u32(trial ^ 0x5bd1_e995);
        let angle = std::f32::consts::TAU * unit_float(h);
        let normal = Vec2::new(angle.cos(), angle.sin());
        let square = normal.x.abs() + normal.y.abs();
        // Half the extent, along the normal, of what the pixel sees.
        let half_extent = match blur {
            Blur::Radius(r) => 0.5 * square + r,
            Blur::LensOnly => 1.0,
            Blur::LensOnlySquare => square,
        };
        let offset = (2.0 * unit_float(hash_u32(h)) - 1.0) * half_extent;
        Edge { normal, offset }
    }

    /// 1 where the sample `u` (film x, film y, lens x, lens y) sees the occluder, else 0.
    fn covers(&self, blur: Blur, u: [f32; 4]) -> f64 {
        let film = Vec2::new(u[0], u[1]) - Vec2::splat(0.5);
        let lens = Vec2::new(u[2], u[3]);
        let p = match blur {
            Blur::Radius(r) => film + r * concentric_sample_disk(lens),
            Blur::LensOnly => concentric_sample_disk(lens),
            Blur::LensOnlySquare => 2.0 * lens - Vec2::ONE,
        };
        f64::from(u8::from(p.dot(self.normal) > self.offset))
    }

    fn estimate(&self, blur: Blur, candidate: Design, key: u32, spp: u32) -> f64 {
        (0..spp)
            .map(|i| self.covers(blur, candidate(key, i)))
            .sum::<f64>()
            / f64::from(spp)
    }
}

/// Mean squared error over `trials` random edges of each candidate at each of `spp`, against a
/// `reference_spp` estimate with the first candidate and other keys; `[candidate][spp]`.
pub fn mean_squared_errors(
    blur: Blur,
    candidates: &[Design],
    spp: &[u32],
    trials: u32,
    reference_spp: u32,
) -> Vec<Vec<f64>> {
    let per_trial: Vec<Vec<Vec<f64>>> = (0..trials)
        .into_par_iter()
        .map(|trial| {
            let edge = Edge::random(trial, blur);
            let reference = edge.estimate(
                blur,
                candidates[0],
                pixel_key(1_000_001, trial),
                reference_spp,
            );
            let key = pixel_key(1, trial);
            candidates
                .iter()
                .map(|&c| {
                    spp.iter()
                        .map(|&n| (edge.estimate(blur, c, key, n) - reference).powi(2))
                        .collect()
                })
                .collect()
        })
        .collect();
    (0..candidates.len())
        .map(|c| {
            (0..spp.len())
                .map(|s| per_trial.iter().map(|t| t[c][s]).sum::<f64>() / f64::from(trials))
                .collect()
        })
        .collect()
}

/// The default design with other lens index columns 0..4, which alone decide the first 16
/// samples' lens points (column c has bit c set and any lower bits: 2 x 4 x 8 choices).
fn with_first_columns(columns: [u32; 4]) -> impl Fn(u32, u32) -> [f32; 4] + Sync {
    move |key, index| {
        let mut lens = index & 0xffff_0000;
        for (bit, &column) in LENS_INDEX_COLUMNS.iter().enumerate().skip(4) {
            lens ^= column & 0u32.wrapping_sub((index >> bit) & 1);
        }
        for (bit, &column) in columns.iter().enumerate() {
            lens ^= column & 0u32.wrapping_sub((index >> bit) & 1);
        }
        let indices = [index, index, lens, lens];
        std::array::from_fn(|d| {
            unit_float(owen_scramble_reversed(
                sobol_reversed(d as u32 % 2, indices[d]),
                scramble_seed(key, d as u32),
            ))
        })
    }
}

/// Every choice of the first four lens index columns, scored on edges blurred by 0.25-4 px at 4
/// and 16 spp (the error ratio to `independent`, geometric mean over the radii), best first.
pub fn first_sixteen_lens_maps(
    independent: Design,
    trials: u32,
    reference_spp: u32,
) -> Vec<([u32; 4], Vec<f64>)> {
    let shipped = with_first_columns(std::array::from_fn(|c| LENS_INDEX_COLUMNS[c]));
    for index in 0..1024 {
        let pixel = lensray_core::sampler::sobol_pixel(7);
        assert_eq!(
            shipped(7, index),
            lensray_core::sampler::sobol_sample(&pixel, index),
            "the benchmark's design differs from the sampler"
        );
    }
    let radii = [0.25, 0.5, 1.0, 2.0, 4.0];
    let spp = [4, 16];
    let mut maps = Vec::new();
    for c1 in 0..2 {
        for c2 in 0..4 {
            for c3 in 0..8 {
                maps.push([1, 2 | c1, 4 | c2, 8 | c3]);
            }
        }
    }
    let designs: Vec<_> = maps.iter().map(|&m| with_first_columns(m)).collect();
    let mut all: Vec<Design> = designs.iter().map(|d| d as Design).collect();
    all.push(independent);
    // log of the error ratio to independent sampling, per map and spp, summed over the radii
    let mut log_ratio = vec![vec![0.0f64; spp.len()]; maps.len()];
    for r in radii {
        let mse = mean_squared_errors(Blur::Radius(r), &all, &spp, trials, reference_spp);
        let independent = mse.last().expect("independent is last");
        for (sums, errors) in log_ratio.iter_mut().zip(&mse) {
            for ((sum, e), i) in sums.iter_mut().zip(errors).zip(independent) {
                *sum += 0.5 * (e / i).ln();
            }
        }
    }
    let mut scored: Vec<([u32; 4], Vec<f64>)> = maps
        .into_iter()
        .zip(log_ratio)
        .map(|(m, sums)| {
            (
                m,
                sums.iter()
                    .map(|s| (s / radii.len() as f64).exp())
                    .collect(),
            )
        })
        .collect();
    scored.sort_by(|a, b| a.1[1].total_cmp(&b.1[1]));
    scored
}
