//! A clear coat over the metallic-roughness BRDF, as `KHR_materials_clearcoat` layers it: a
//! GGX lobe of its own roughness (alpha = clearcoatRoughness^2, `specular_brdf` of the core
//! specification's Appendix B without its Fresnel) about its own normal nc, mixed over the base
//! by the coat's Fresnel at the view (`fresnel_coat`, IOR 1.5: f0 = 0.04), weighed by the
//! coat's factor. Each layer's light is weighed by its own normal's cosine:
//!
//! ```text
//! Fc = f0 + (1 - f0) (1 - |nc.v|)^5
//! f cos = f_base |n.l| (1 - clearcoat Fc) + clearcoat Fc D_c V_c nc.l
//! ```
//!
//! f_base is what lies beneath the coat: the base under its sheen (`sheen.rs`), about the
//! base's shading normal n. The base loses what the coat reflects, so the pair never reflects
//! more than the base alone does plus the coat's lobe (at most 1). nc is the interpolated
//! vertex normal tilted by the coat's own normal map (`clearcoatNormalTexture`); the base's
//! normal map does not tilt it, as the extension says. Draws pick the coat's lobe (Heitz's
//! visible normals about nc, `brdf_sampling`) with probability clearcoat (0.2 + 0.8 Fc), the
//! base's mixture otherwise; the density is the mixture of both.
//! shaders/include/layers.glsl mirrors it function by function.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::brdf::{ggx_distribution, smith_visibility, MetallicRoughness};
use super::brdf_sampling::{finish_draw, visible_normal_around, visible_normal_pdf, BrdfSample};
use super::sheen::{uniform_direction, Sheen};
use crate::interface::{CLEARCOAT_F0, MIN_ROUGHNESS};

/// The coat of a surface point: its weight (`clearcoatFactor` times its texture's R) and its
/// perceptual roughness (`clearcoatRoughnessFactor` times its texture's G), each in [0, 1],
/// and its unit normal nc, facing the viewer (read only where the weight is above 0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Clearcoat {
    pub weight: f32,
    pub roughness: f32,
    pub normal: Vec3,
}

/// A surface point's BRDF: the metallic-roughness base under its sheen (`sheen.rs`), under
/// its clear coat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayeredBrdf {
    pub base: MetallicRoughness,
    pub clearcoat: Clearcoat,
    pub sheen: Sheen,
}

impl Clearcoat {
    /// The coat's GGX alpha: roughness^2, roughness clamped to [`MIN_ROUGHNESS`], 1].
    pub fn alpha(&self) -> f32 {
        let r = self.roughness.clamp(MIN_ROUGHNESS, 1.0);
        r * r
    }

    /// The share of the light the coat reflects where the viewer is at n.v = `n_dot_v`:
    /// clearcoat x Fc.
    pub fn blend(&self, n_dot_v: f32) -> f32 {
        let m = (1.0 - n_dot_v.abs()).clamp(0.0, 1.0);
        let m2 = m * m;
        self.weight * (CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * (m2 * m2 * m))
    }

    /// The coat's lobe D V (1/sr) for n.l = `n_dot_l`, n.v = `n_dot_v` and n.h = `n_dot_h`;
    /// 0 unless both directions are above the surface.
    fn lobe(&self, n_dot_l: f32, n_dot_v: f32, n_dot_h: f32) -> f32 {
        if n_dot_l <= 0.0 || n_dot_v <= 0.0 {
            return 0.0;
        }
        let alpha = self.alpha();
        ggx_distribution(n_dot_h, alpha) * smith_visibility(n_dot_l, n_dot_v, alpha)
    }

    /// The share of draws that go to the coat's lobe: none without a coat or a viewer above.
    pub fn probability(&self, n_dot_v: f32) -> f32 {
        if self.weight <= 0.0 || n_dot_v <= 0.0 {
            return 0.0;
        }
        let fresnel = self.blend(n_dot_v) / self.weight;
        (self.weight * (0.2 + 0.8 * fresnel)).clamp(0.0, 1.0)
    }
}

impl LayeredBrdf {
    /// Whether light goes through the surface (its base transmits).
    pub fn transmits(&self) -> bool {
        self.base.transmits()
    }

    /// Whether the coat's lobe reflects light from `l` (unit) at base normal `n`: `l` above
    /// the coat's normal and, where the base transmits, above the base's (light from below it
    /// goes through the surface, and the coat does not reflect it).
    pub fn coat_reflects(&self, n: Vec3, l: Vec3) -> bool {
        self.clearcoat.weight > 0.0
            && self.clearcoat.normal.dot(l) > 0.0
            && (n.dot(l) > 0.0 || !self.transmits())
    }

    /// The light reflected (or transmitted) towards `v` per unit of light arriving from `l`
    /// across a plane facing it: f(l, v) weighed by each layer's own cosine, |n.l| beneath the
    /// coat (`n`: the base's unit shading normal, n.l != 0) and nc.l for the coat's lobe;
    /// 1/sr.
    pub fn reflected(&self, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
        let base = self.beneath_evaluate(n, l, v) * n.dot(l).abs();
        if self.clearcoat.weight <= 0.0 {
            return base;
        }
        let nc = self.clearcoat.normal;
        let n_dot_v = nc.dot(v);
        let blend = self.clearcoat.blend(n_dot_v);
        let coat = if self.coat_reflects(n, l) {
            let (h, n_dot_l) = ((l + v).normalize(), nc.dot(l));
            self.clearcoat.lobe(n_dot_l, n_dot_v, nc.dot(h)) * n_dot_l
        } else {
            0.0
        };
        base * (1.0 - blend) + Vec3::splat(blend * coat)
    }

    /// The density (per solid angle) of drawing `l` at base normal `n` seen from `v`: the
    /// coat's share of its lobe's visible-normal density about nc plus the rest of the base's
    /// mixture.
    pub fn pdf(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        let base = self.beneath_pdf(n, l, v);
        let nc = self.clearcoat.normal;
        let n_dot_v = nc.dot(v);
        let p = self.clearcoat.probability(n_dot_v);
        if p <= 0.0 {
            return base;
        }
        let coat = if self.coat_reflects(n, l) {
            let h = (l + v).normalize();
            visible_normal_pdf(n_dot_v, nc.dot(h), self.clearcoat.alpha())
        } else {
            0.0
        };
        p * coat + (1.0 - p) * base
    }

    /// The direction point `u` ([0, 1)^3) draws at base normal `n` seen from `v`, with its
    /// density and weight (`reflected` over the density); `None` where it carries no light.
    /// The first coordinate picks the coat or the base and is stretched back to [0, 1) within
    /// it; the third is the base's glass's (`MetallicRoughness::sample`).
    pub fn sample(&self, n: Vec3, v: Vec3, u: Vec3) -> Option<BrdfSample> {
        let nc = self.clearcoat.normal;
        let p = self.clearcoat.probability(nc.dot(v));
        if p <= 0.0 {
            return self.beneath_sample(n, v, u);
        }
        let direction = if u.x < p {
            let alpha = self.clearcoat.alpha();
            let h = visible_normal_around(nc, v, alpha, Vec2::new(u.x / p, u.y));
            // The lobe's density counts only what it reflects.
            Some(2.0 * v.dot(h) * h - v).filter(|l| self.coat_reflects(n, *l))?
        } else {
            let stretched = Vec3::new((u.x - p) / (1.0 - p), u.y, u.z);
            self.beneath_sample(n, v, stretched)?.direction
        };
        let pdf = self.pdf(n, direction, v);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BrdfSample {
            direction,
            pdf,
            weight: self.reflected(n, direction, v) / pdf,
        })
    }
}

impl LayeredBrdf {
    /// What lies beneath the coat, the base under its sheen: f(l, v) for unit normal `n`,
    /// direction to the light `l` and to the viewer `v`, with n.l != 0 (light from below
    /// crosses the sheen at |n.l|); 1/sr.
    pub fn beneath_evaluate(&self, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
        let base = self.base.evaluate(n, l, v);
        if self.sheen.colour.max_element() <= 0.0 {
            return base;
        }
        let (n_dot_l, n_dot_v) = (n.dot(l), n.dot(v));
        let h = (l + v).normalize();
        let lobe = self.sheen.lobe(n_dot_l, n_dot_v, n.dot(h));
        base * self.sheen.albedo_scaling(n_dot_l.abs(), n_dot_v) + self.sheen.colour * lobe
    }

    /// The density (per solid angle) of drawing `l` beneath the coat: the sheen's share of
    /// the uniform hemisphere plus the rest of the base's mixture.
    pub fn beneath_pdf(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        let base = self.base.pdf(n, l, v);
        let n_dot_l = n.dot(l);
        let p = self.sheen.probability(n.dot(v));
        if p <= 0.0 {
            return base;
        }
        let sheen = if n_dot_l > 0.0 { 0.5 * FRAC_1_PI } else { 0.0 };
        p * sheen + (1.0 - p) * base
    }

    /// The direction point `u` ([0, 1)^3) draws beneath the coat, with its density and
    /// weight; `None` where it carries no light. The first coordinate picks the sheen
    /// or the base and is stretched back to [0, 1) within it.
    pub fn beneath_sample(&self, n: Vec3, v: Vec3, u: Vec3) -> Option<BrdfSample> {
        let p = self.sheen.probability(n.dot(v));
        if p <= 0.0 {
            return self.base.sample(n, v, u);
        }
        let direction = if u.x < p {
            uniform_direction(n, Vec2::new(u.x / p, u.y))
        } else {
            let stretched = Vec3::new((u.x - p) / (1.0 - p), u.y, u.z);
            self.base.sample(n, v, stretched)?.direction
        };
        let pdf = self.beneath_pdf(n, direction, v);
        finish_draw(n, direction, pdf, || self.beneath_evaluate(n, direction, v))
    }
}

#[cfg(test)]
#[path = "clearcoat_tests.rs"]
mod tests;
