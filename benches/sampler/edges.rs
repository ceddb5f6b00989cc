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

use lensray::camera::thin_lens::concentric_sample_disk;
use lensray::sampler::{hash_u32, pixel_key, unit_float};

use super::Candidate;

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

    fn estimate(&self, blur: Blur, candidate: Candidate, key: u32, spp: u32) -> f64 {
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
    candidates: &[Candidate],
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
