//! A clear coat over the metallic-roughness BRDF, as `KHR_materials_clearcoat` layers it: a
//! GGX lobe of its own roughness (alpha = clearcoatRoughness^2, `specular_brdf` of the core
//! specification's Appendix B without its Fresnel), mixed over the base by the coat's Fresnel
//! at the view (`fresnel_coat`, IOR 1.5: f0 = 0.04), weighed by the coat's factor:
//!
//! ```text
//! Fc = f0 + (1 - f0) (1 - |n.v|)^5
//! f = f_base (1 - clearcoat Fc) + clearcoat Fc D_c V_c
//! ```
//!
//! f_base is what lies beneath the coat: the base under its sheen (`sheen.rs`), as the
//! extensions order them. The base loses what the coat reflects, so the pair never reflects
//! more than the base alone does plus the coat's lobe (at most 1). The coat shares the base's shading normal: a
//! `clearcoatNormalTexture` of its own is not read (the loader names it). Draws pick the coat's
//! lobe (Heitz's visible normals, `brdf_sampling`) with probability clearcoat (0.2 + 0.8 Fc),
//! the base's mixture otherwise; the density is the mixture of both.
//! shaders/include/brdf.glsl mirrors it function by function.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::brdf::{ggx_distribution, smith_visibility, MetallicRoughness};
use super::brdf_sampling::{finish_draw, visible_normal_around, visible_normal_pdf, BrdfSample};
use super::sheen::{uniform_direction, Sheen};
use crate::interface::{CLEARCOAT_F0, MIN_ROUGHNESS};

/// The coat of a surface point: its weight (`clearcoatFactor` times its texture's R) and its
/// perceptual roughness (`clearcoatRoughnessFactor` times its texture's G), each in [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Clearcoat {
    pub weight: f32,
    pub roughness: f32,
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

    /// f(l, v) for unit normal `n`, direction to the light `l` and to the viewer `v`, with
    /// n.l != 0 (the caller's cosine test; below the surface only the base transmits); 1/sr.
    pub fn evaluate(&self, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
        let base = self.beneath_evaluate(n, l, v);
        if self.clearcoat.weight <= 0.0 {
            return base;
        }
        let n_dot_v = n.dot(v);
        let blend = self.clearcoat.blend(n_dot_v);
        let h = (l + v).normalize();
        let lobe = self.clearcoat.lobe(n.dot(l), n_dot_v, n.dot(h));
        base * (1.0 - blend) + Vec3::splat(blend * lobe)
    }

    /// The density (per solid angle) of drawing `l` at unit normal `n` seen from `v`: the
    /// coat's share of its lobe's visible-normal density plus the rest of the base's mixture.
    pub fn pdf(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        let base = self.beneath_pdf(n, l, v);
        let n_dot_v = n.dot(v);
        let p = self.clearcoat.probability(n_dot_v);
        if p <= 0.0 {
            return base;
        }
        let coat = if n.dot(l) > 0.0 {
            let h = (l + v).normalize();
            visible_normal_pdf(n_dot_v, n.dot(h), self.clearcoat.alpha())
        } else {
            0.0
        };
        p * coat + (1.0 - p) * base
    }

    /// The direction point `u` ([0, 1)^2) draws at unit normal `n` seen from `v`, with its
    /// density and weight; `None` where it carries no light. The first coordinate
    /// picks the coat or the base and is stretched back to [0, 1) within it.
    pub fn sample(&self, n: Vec3, v: Vec3, u: Vec2) -> Option<BrdfSample> {
        let p = self.clearcoat.probability(n.dot(v));
        if p <= 0.0 {
            return self.beneath_sample(n, v, u);
        }
        let direction = if u.x < p {
            let alpha = self.clearcoat.alpha();
            let h = visible_normal_around(n, v, alpha, Vec2::new(u.x / p, u.y));
            // The lobe's density counts only what goes above the surface.
            Some(2.0 * v.dot(h) * h - v).filter(|l| n.dot(*l) > 0.0)?
        } else {
            let stretched = Vec2::new((u.x - p) / (1.0 - p), u.y);
            self.beneath_sample(n, v, stretched)?.direction
        };
        let pdf = self.pdf(n, direction, v);
        finish_draw(n, direction, pdf, || self.evaluate(n, direction, v))
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

    /// The direction point `u` ([0, 1)^2) draws beneath the coat, with its density and
    /// weight; `None` where it carries no light. The first coordinate picks the sheen
    /// or the base and is stretched back to [0, 1) within it.
    pub fn beneath_sample(&self, n: Vec3, v: Vec3, u: Vec2) -> Option<BrdfSample> {
        let p = self.sheen.probability(n.dot(v));
        if p <= 0.0 {
            return self.base.sample(n, v, u);
        }
        let direction = if u.x < p {
            uniform_direction(n, Vec2::new(u.x / p, u.y))
        } else {
            let stretched = Vec2::new((u.x - p) / (1.0 - p), u.y);
            self.base.sample(n, v, stretched)?.direction
        };
        let pdf = self.beneath_pdf(n, direction, v);
        finish_draw(n, direction, pdf, || self.beneath_evaluate(n, direction, v))
    }
}

#[cfg(test)]
#[path = "clearcoat_tests.rs"]
mod tests;
