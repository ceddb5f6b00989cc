//! The dielectric's transmitted light (`KHR_materials_transmission`, `KHR_materials_ior`,
//! `KHR_materials_volume`): light from below the surface (n.l < 0) reaches the viewer through
//! it, tinted by the diffuse colour and weighed by the share T and what Fresnel lets through:
//!
//! ```text
//! f = (1 - F(v.h)) T c_diff f_t(l, v)
//! ```
//!
//! - Through a volume's boundary (`eta` != 1) f_t is Walter et al.'s microfacet BTDF
//!   ("Microfacet Models for Refraction through Rough Surfaces", EGSR 2007, eq. 21) without its
//!   Fresnel, for radiance: with h = -(v + eta l) / |v + eta l| turned to the normal's side,
//!   f_t = 4 |l.h| |v.h| D(h) V(|n.l|, n.v) / (v.h + eta l.h)^2, where D V is the GGX lobe
//!   of `brdf.rs` (G2 = 4 V |n.l| |n.v|). The radiance a ray carries out of glass of index
//!   1.5 into the air is 1 / 1.5^2 of the radiance inside, and the way in multiplies by
//!   1.5^2: paths that enter and leave carry what they found.
//! - Through a thin wall (`eta` = 1: nothing refracts) f_t is the reflection lobe mirrored
//!   through the surface, D(h) V(|n.l|, n.v) with h halfway between v and l mirrored
//!   (the specification's thin-walled transmission: straight through, blurred by the
//!   roughness).
//!
//! Glass draws (`brdf_sampling.rs`) refract (or mirror) the view about a visible normal
//! (`brdf_sampling::visible_normal`) that its own Fresnel lets through; the density of the
//! refracted direction is the normal's times Walter's Jacobian eta^2 |l.h| / (v.h + eta l.h)^2
//! (eq. 17) times that share. shaders/include/brdf.glsl mirrors it.

use glam::Vec3;

use super::brdf::{ggx_distribution, smith_visibility, Dielectric, MetallicRoughness};
use super::brdf_sampling::visible_normal_pdf;
use crate::scene::Material;

/// The dielectric optics of `material` where a ray meets it from its front (`back_face`
/// false) or back, with the transmission's share `transmission`: a volume's boundary
/// refracts into it (eta = ior) or out of it (1 / ior); a thin wall refracts nothing.
pub(super) fn dielectric_of(material: &Material, transmission: f32, back_face: bool) -> Dielectric {
    let eta = if transmission <= 0.0 {
        material.ior
    } else if material.thin {
        1.0
    } else if back_face {
        1.0 / material.ior
    } else {
        material.ior
    };
    Dielectric {
        ior: material.ior,
        transmission,
        eta,
    }
}

/// `l` mirrored through the plane of unit normal `n`.
fn mirrored(n: Vec3, l: Vec3) -> Vec3 {
    l - 2.0 * n.dot(l) * n
}

/// The refraction of the view `v` (unit, away from the surface) through a microfacet of unit
/// normal `m` (v.m > 0) into a medium of relative index `eta`; `None` beyond the critical
/// angle.
pub(super) fn refract(v: Vec3, m: Vec3, eta: f32) -> Option<Vec3> {
    let cos = v.dot(m);
    let sin2 = (1.0 - cos * cos).max(0.0) / (eta * eta);
    if sin2 >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2).sqrt();
    Some(-v / eta + m * (cos / eta - cos_t))
}

/// The microfacet normal that refracts `v` into `l` at relative index `eta`, on the side of
/// `n`, with v.h and l.h; `None` where no microfacet does (both on one side of it).
fn refraction_normal(n: Vec3, l: Vec3, v: Vec3, eta: f32) -> Option<(Vec3, f32, f32)> {
    let mut h = -(v + eta * l).normalize();
    if n.dot(h) < 0.0 {
        h = -h;
    }
    let (v_dot_h, l_dot_h) = (v.dot(h), l.dot(h));
    (h.is_finite() && v_dot_h > 0.0 && l_dot_h < 0.0).then_some((h, v_dot_h, l_dot_h))
}

impl MetallicRoughness {
    /// f(l, v) for light from below the surface (n.l < 0); 1/sr.
    pub(super) fn transmitted(&self, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
        let n_dot_v = n.dot(v);
        if !self.transmits() || n_dot_v <= 0.0 {
            return Vec3::ZERO;
        }
        let n_dot_l = -n.dot(l);
        let alpha = self.alpha();
        let eta = self.dielectric.eta;
        let (lobe, v_dot_h) = if eta == 1.0 {
            let h = (mirrored(n, l) + v).normalize();
            let lobe =
                ggx_distribution(n.dot(h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
            (lobe, v.dot(h))
        } else {
            let Some((h, v_dot_h, l_dot_h)) = refraction_normal(n, l, v, eta) else {
                return Vec3::ZERO;
            };
            let denominator = v_dot_h + eta * l_dot_h;
            let dv = ggx_distribution(n.dot(h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
            let lobe = 4.0 * v_dot_h * -l_dot_h * dv / (denominator * denominator);
            (lobe, v_dot_h)
        };
        let through = Vec3::ONE - self.fresnel(v_dot_h);
        through * self.diffuse_colour() * (self.dielectric.transmission * lobe)
    }

    /// The density (per solid angle) of `l` below the surface through the visible microfacet
    /// that sends `v` there (Walter's Jacobian), with that microfacet's v.h: what the glass
    /// draws give it once weighed by the share that refracts (1 - [`Self::glass_reflectance`]).
    pub(super) fn transmission_pdf(&self, n: Vec3, l: Vec3, v: Vec3) -> (f32, f32) {
        let n_dot_v = n.dot(v);
        let alpha = self.alpha();
        let eta = self.dielectric.eta;
        if eta == 1.0 {
            let h = (mirrored(n, l) + v).normalize();
            return (visible_normal_pdf(n_dot_v, n.dot(h), alpha), v.dot(h));
        }
        let Some((h, v_dot_h, l_dot_h)) = refraction_normal(n, l, v, eta) else {
            return (0.0, 1.0);
        };
        // visible_normal_pdf is D_v(h) / (4 v.h).
        let denominator = v_dot_h + eta * l_dot_h;
        let normal_pdf = 4.0 * v_dot_h * visible_normal_pdf(n_dot_v, n.dot(h), alpha);
        let pdf = normal_pdf * eta * eta * -l_dot_h / (denominator * denominator);
        (pdf, v_dot_h)
    }

    /// Where the view `v` goes through the visible microfacet `h` below the surface: refracted
    /// through a volume's boundary, mirrored through a thin wall; `None` beyond the critical
    /// angle or where it would go above the surface (the draws' density counts only what goes
    /// below).
    pub(super) fn transmitted_through(&self, n: Vec3, v: Vec3, h: Vec3) -> Option<Vec3> {
        let eta = self.dielectric.eta;
        let l = if eta == 1.0 {
            mirrored(n, 2.0 * v.dot(h) * h - v)
        } else {
            refract(v, h, eta)?
        };
        (n.dot(l) < 0.0).then_some(l)
    }
}

#[cfg(test)]
#[path = "transmission_tests.rs"]
mod tests;
