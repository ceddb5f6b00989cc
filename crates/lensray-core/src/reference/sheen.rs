//! A sheen over the metallic-roughness BRDF, as `KHR_materials_sheen` layers it: the
//! "Charlie" lobe of Estevez and Kulla ("Production Friendly Microfacet Sheen BRDF",
//! SIGGRAPH 2017), of colour `sheenColor` and alpha = sheenRoughness^2 (roughness clamped to
//! [`MIN_ROUGHNESS`], 1] as GGX's is), over the base scaled by what the sheen takes from it:
//!
//! ```text
//! D = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi)
//! V = clamp(1 / ((1 + Lambda(n.v) + Lambda(n.l)) 4 n.v n.l), 0, 1)
//! f = sheenColor D V + f_base min(1 - max3(sheenColor) E(n.v), 1 - max3(sheenColor) E(n.l))
//! ```
//!
//! V is the Charlie visibility with Estevez and Kulla's fitted Lambda, as the extension's
//! implementation notes and the glTF Sample Viewer (`V_Sheen`, with its clamp) give it; the
//! simpler Ashikhmin term would not conserve energy under the albedo scaling. E(mu, roughness)
//! is the lobe's directional albedo: `SHEEN_ALBEDO`, a table of the interface that
//! `sheen_table.rs` computes by quadrature of this lobe and checks, bilinear between its
//! nodes; the GPU reads the same numbers. A clear coat stays on top (`clearcoat.rs`: coat over
//! sheen over base). Draws pick the sheen's lobe, uniform over the hemisphere, with probability
//! max3(sheenColor) E(n.v), the base's mixture otherwise; the density is the mixture of both.
//! shaders/include/brdf.glsl mirrors it function by function.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::interface::{MIN_ROUGHNESS, SHEEN_ALBEDO, SHEEN_ALBEDO_SIZE};
use crate::scene::light::orthonormal_frame;

/// The sheen of a surface point: its colour (`sheenColorFactor` times its texture's RGB,
/// linear) and its perceptual roughness (`sheenRoughnessFactor` times its texture's alpha).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sheen {
    pub colour: Vec3,
    pub roughness: f32,
}

impl Sheen {
    /// The lobe's alpha: roughness^2, roughness clamped to [`MIN_ROUGHNESS`], 1].
    pub fn alpha(&self) -> f32 {
        let r = self.roughness.clamp(MIN_ROUGHNESS, 1.0);
        r * r
    }

    /// The lobe's D V (1/sr) for n.l = `n_dot_l`, n.v = `n_dot_v` and n.h = `n_dot_h`; 0
    /// unless both directions are above the surface.
    pub fn lobe(&self, n_dot_l: f32, n_dot_v: f32, n_dot_h: f32) -> f32 {
        if n_dot_l <= 0.0 || n_dot_v <= 0.0 {
            return 0.0;
        }
        let alpha = self.alpha();
        charlie_distribution(n_dot_h, alpha) * charlie_visibility(n_dot_l, n_dot_v, alpha)
    }

    /// What the base keeps: min(1 - max3(colour) E(n.v), 1 - max3(colour) E(n.l)), at least
    /// 0: a smooth lobe's E passes 1 at grazing directions (`directional_albedo`).
    pub fn albedo_scaling(&self, n_dot_l: f32, n_dot_v: f32) -> f32 {
        let strength = self.colour.max_element();
        let e_v = directional_albedo(n_dot_v, self.roughness);
        let e_l = directional_albedo(n_dot_l, self.roughness);
        (1.0 - strength * e_v).min(1.0 - strength * e_l).max(0.0)
    }

    /// The share of the draws beneath a coat that go to the sheen's lobe: max3(colour) E(n.v);
    /// none without a sheen or a viewer above.
    pub fn probability(&self, n_dot_v: f32) -> f32 {
        let strength = self.colour.max_element();
        if strength <= 0.0 || n_dot_v <= 0.0 {
            return 0.0;
        }
        (strength * directional_albedo(n_dot_v, self.roughness)).clamp(0.0, 1.0)
    }
}

/// The direction point `u` ([0, 1)^2) draws uniformly over the hemisphere about unit `n`
/// (density 1 / (2 pi)): the sheen's lobe peaks towards the horizon, where the cosine draws
/// too few directions.
pub fn uniform_direction(n: Vec3, u: Vec2) -> Vec3 {
    let (t, b) = orthonormal_frame(n);
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin, cos) = (2.0 * PI * u.y).sin_cos();
    t * (r * cos) + b * (r * sin) + n * z
}

/// The Charlie distribution D for n.h = `n_dot_h` and alpha `alpha`.
pub fn charlie_distribution(n_dot_h: f32, alpha: f32) -> f32 {
    let inverse = 1.0 / alpha;
    let sin2 = (1.0 - n_dot_h * n_dot_h).max(0.0);
    (2.0 + inverse) * sin2.powf(0.5 * inverse) / (2.0 * PI)
}

/// Estevez and Kulla's fit L(x) of their Lambda's logarithm, its parameters interpolated by
/// (1 - alpha)^2 between alpha 1 and alpha 0.
fn charlie_fit(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let mix = |at_one: f32, at_zero: f32| at_one + (at_zero - at_one) * t;
    let a = mix(21.5473, 25.3245);
    let b = mix(3.82987, 3.32435);
    let c = mix(0.19823, 0.16801);
    let d = mix(-1.97760, -1.27393);
    let e = mix(-4.32054, -4.85967);
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// Lambda of a direction at cosine `cos` from the normal: exp L(cos) below 0.5, mirrored
/// about it above (exp(2 L(0.5) - L(1 - cos))) as Estevez and Kulla extend the fit.
fn charlie_lambda(cos: f32, alpha: f32) -> f32 {
    if cos < 0.5 {
        charlie_fit(cos, alpha).exp()
    } else {
        (2.0 * charlie_fit(0.5, alpha) - charlie_fit(1.0 - cos, alpha)).exp()
    }
}

/// The Charlie visibility V = 1 / ((1 + Lambda(n.v) + Lambda(n.l)) 4 n.v n.l), clamped to
/// [0, 1] as the Sample Viewer clamps it; both cosines > 0.
pub fn charlie_visibility(n_dot_l: f32, n_dot_v: f32, alpha: f32) -> f32 {
    let lambda = charlie_lambda(n_dot_v, alpha) + charlie_lambda(n_dot_l, alpha);
    (1.0 / ((1.0 + lambda) * (4.0 * n_dot_v * n_dot_l))).clamp(0.0, 1.0)
}

/// E(mu, roughness), the lobe's directional albedo at n.v = `mu`: bilinear in `SHEEN_ALBEDO`,
/// whose nodes stand at the centres of SHEEN_ALBEDO_SIZE equal cells of [0, 1] in mu and in
/// roughness (node (i, j) at index j SHEEN_ALBEDO_SIZE + i); outside the outer nodes the
/// nearest holds. Where the view grazes a smooth sheen (n.v < 0.05, roughness < 0.1) E passes
/// 1, up to 1.45: there the fitted Lambda masks less than the lobe's peak at grazing half
/// vectors reflects, and V's clamp to 1 does not make up for it.
pub fn directional_albedo(mu: f32, roughness: f32) -> f32 {
    let size = SHEEN_ALBEDO_SIZE as f32;
    let x = (mu.clamp(0.0, 1.0) * size - 0.5).clamp(0.0, size - 1.0);
    let y = (roughness.clamp(0.0, 1.0) * size - 0.5).clamp(0.0, size - 1.0);
    let (i, j) = (
        (x as u32).min(SHEEN_ALBEDO_SIZE - 2),
        (y as u32).min(SHEEN_ALBEDO_SIZE - 2),
    );
    let (fx, fy) = (x - i as f32, y - j as f32);
    let at = |i: u32, j: u32| SHEEN_ALBEDO[(j * SHEEN_ALBEDO_SIZE + i) as usize];
    let low = at(i, j) + (at(i + 1, j) - at(i, j)) * fx;
    let high = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * fx;
    low + (high - low) * fy
}

#[cfg(test)]
#[path = "sheen_tests.rs"]
mod tests;
