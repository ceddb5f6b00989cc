//! Sampling an environment by its power: a piecewise-constant density over the texels,
//! proportional to each texel's luminance times the solid angle it spans (sin theta at its
//! row's centre), drawn by inversion of a marginal table over the rows and a conditional table
//! over each row's texels (pbrt's `Distribution2D`; Pharr, Jakob and Humphreys, "Physically
//! Based Rendering", 3rd ed., 13.6.7 and 14.2.4). The tables are sums in f32 in texel order, so
//! that the GLSL mirror draws the same texel from the same point.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::{luminance, EnvironmentMap};

/// A direction drawn from an environment, with its density and what arrives along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvironmentSample {
    /// Unit, pointing away from the scene.
    pub direction: Vec3,
    /// Density per unit solid angle.
    pub pdf: f32,
    /// The texel's scaled radiance.
    pub radiance: Vec3,
    /// The texel drawn (column, row).
    pub texel: (u32, u32),
}

/// The inversion tables of one map.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentSampler {
    width: u32,
    height: u32,
    /// Per row, the cumulative weights of its texels (`width` + 1 each, from 0): a row's last
    /// entry is its weight.
    row_cdfs: Vec<f32>,
    /// Cumulative weights of the rows (`height` + 1, from 0).
    rows_cdf: Vec<f32>,
    /// The sum of every weight.
    total: f32,
}

impl EnvironmentSampler {
    /// The tables of `map`; `None` when nothing in it emits (sample the BSDF alone then).
    pub fn new(map: &EnvironmentMap) -> Option<Self> {
        let (width, height) = (map.width as usize, map.height as usize);
        let mut row_cdfs = Vec::with_capacity(height * (width + 1));
        let mut row_weights = Vec::with_capacity(height);
        for row in 0..height {
            let sin_theta = ((row as f32 + 0.5) / height as f32 * PI).sin();
            let mut sum = 0.0f32;
            row_cdfs.push(0.0);
            for column in 0..width {
                let texel = map.texels[row * width + column];
                sum += luminance(texel).max(0.0) * sin_theta;
                row_cdfs.push(sum);
            }
            row_weights.push(sum);
        }
        let mut rows_cdf = Vec::with_capacity(height + 1);
        let mut total = 0.0f32;
        rows_cdf.push(0.0);
        for &w in &row_weights {
            total += w;
            rows_cdf.push(total);
        }
        (total > 0.0 && total.is_finite()).then_some(Self {
            width: map.width,
            height: map.height,
            row_cdfs,
            rows_cdf,
            total,
        })
    }

    /// The direction point `u` ([0, 1)^2) draws: a row by `u.y`, a texel in it by `u.x`, then
    /// a uniform point in the texel's (u, v) rectangle by what is left of each coordinate.
    pub fn sample(&self, map: &EnvironmentMap, u: Vec2) -> Option<EnvironmentSample> {
        let (row, v_in) = invert(&self.rows_cdf, u.y * self.total);
        let stride = self.width as usize + 1;
        let row_weight = self.row_cdfs[row * stride + self.width as usize];
        if row_weight <= 0.0 {
            return None;
        }
        let cdf = &self.row_cdfs[row * stride..(row + 1) * stride];
        let (column, u_in) = invert(cdf, u.x * row_weight);
        let uv = Vec2::new(
            (column as f32 + u_in) / self.width as f32,
            (row as f32 + v_in) / self.height as f32,
        );
        let direction = map.world_from_uv(uv);
        let pdf = self.texel_pdf(column as u32, row as u32, uv.y);
        (pdf > 0.0).then(|| EnvironmentSample {
            direction,
            pdf,
            radiance: map.texel(column as u32, row as u32),
            texel: (column as u32, row as u32),
        })
    }

    /// The rows' cumulative tables, `width` + 1 entries a row (what the GPU samples with).
    pub fn row_cdfs(&self) -> &[f32] {
        &self.row_cdfs
    }

    /// The cumulative table over the rows, `height` + 1 entries.
    pub fn rows_cdf(&self) -> &[f32] {
        &self.rows_cdf
    }

    /// The sum of every texel's weight.
    pub fn total(&self) -> f32 {
        self.total
    }

    /// Density per unit solid angle of drawing direction `d` (unit).
    pub fn pdf(&self, map: &EnvironmentMap, d: Vec3) -> f32 {
        let uv = map.uv_from_world(d);
        let (column, row) = map.texel_at(uv);
        self.texel_pdf(column, row, uv.y)
    }

    /// The density of the texel (`column`, `row`) per solid angle at image height `v`: its
    /// weight over the total per unit area of [0, 1)^2, over the 2 pi^2 sin(theta) of the map.
    fn texel_pdf(&self, column: u32, row: u32, v: f32) -> f32 {
        let stride = self.width as usize + 1;
        let base = row as usize * stride + column as usize;
        let weight = self.row_cdfs[base + 1] - self.row_cdfs[base];
        let sin_theta = (v * PI).sin();
        if weight <= 0.0 || sin_theta <= 0.0 {
            return 0.0;
        }
        let pdf_uv = weight / self.total * (self.width * self.height) as f32;
        pdf_uv / (2.0 * PI * PI * sin_theta)
    }
}

/// The interval of the cumulative table `cdf` (from 0, increasing) that `x` falls in, and
/// where in it (0..1): the last entry whose start is at most `x` and whose width is not 0.
fn invert(cdf: &[f32], x: f32) -> (usize, f32) {
    let last = cdf.len() - 2;
    // The first index whose cumulative sum passes x, minus one: x's interval.
    let mut index = cdf.partition_point(|&c| c <= x).saturating_sub(1).min(last);
    // Skip back over intervals of width 0 (texels that do not emit) at the end.
    while index > 0 && cdf[index + 1] <= cdf[index] {
        index -= 1;
    }
    let width = cdf[index + 1] - cdf[index];
    let within = if width > 0.0 {
        ((x - cdf[index]) / width).clamp(0.0, 1.0 - f32::EPSILON / 2.0)
    } else {
        0.5
    };
    (index, within)
}
