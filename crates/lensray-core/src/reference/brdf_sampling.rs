//! Drawing directions from the metallic-roughness BRDF (`brdf.rs`): a mixture of its specular
//! lobe, drawn by GGX's distribution of visible normals (Heitz, "Sampling the GGX Distribution
//! of Visible Normals", JCGT 7(4), 2018), its glass, whose visible microfacet reflects or
//! refracts by its own Fresnel (Walter et al., "Microfacet Models for Refraction through Rough
//! Surfaces", EGSR 2007, section 5.3), and its diffuse lobe, drawn by the cosine. The
//! mixture's density is what both the estimate and multiple importance sampling against the
//! environment (`sky.rs`) weigh by. shaders/include/brdf.glsl mirrors it function by function.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::brdf::{ggx_distribution, MetallicRoughness};
use crate::scene::light::{cosine_direction, orthonormal_frame};

/// A direction drawn from a BRDF: where the light comes from, the mixture's density of it, and
/// f cos / density, what the light arriving along it is multiplied by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrdfSample {
    pub direction: Vec3,
    pub pdf: f32,
    pub weight: Vec3,
}

impl MetallicRoughness {
    /// The shares of draws that go to the specular reflection and to the glass where the
    /// viewer is at n.v = `n_dot_v`; the diffuse lobe draws the rest. A metal's draws all go
    /// to its specular lobe; an opaque dielectric's half to it (weighed by `specular`); a
    /// transmitting dielectric's share T to the glass, whose draws find a visible microfacet
    /// and reflect off it or refract through it as its own Fresnel says
    /// ([`Self::glass_reflectance`]; Walter et al. 2007, section 5.3). None where the viewer
    /// is not above the surface (no visible normal then).
    pub fn lobe_probabilities(&self, n_dot_v: f32) -> (f32, f32) {
        if n_dot_v <= 0.0 {
            return (0.0, 0.0);
        }
        let dielectric = 1.0 - self.metallic;
        let t = self.dielectric.transmission;
        let specular = self.metallic + dielectric * ((1.0 - t) * 0.5 * self.specular);
        let glass = dielectric * t;
        (
            specular.clamp(0.0, 1.0),
            glass.clamp(0.0, 1.0 - specular.clamp(0.0, 1.0)),
        )
    }

    /// The share of a glass draw's microfacets at cosine `v_dot_h` to the viewer that reflect:
    /// the mean of their Fresnel, 1 beyond the critical angle. f's share of each side is then
    /// what draws it, so a glass draw's weight is G2 / G1 either way: no draw carries much
    /// more than the light it finds.
    pub fn glass_reflectance(&self, v_dot_h: f32) -> f32 {
        let f = self.fresnel(v_dot_h);
        ((f.x + f.y + f.z) / 3.0).clamp(0.0, 1.0)
    }

    /// The mixture's density (per solid angle) of drawing `l` at unit normal `n` seen from
    /// `v`; below the surface the glass's refraction, 0 without one. The glass's share of
    /// either side is found once, at the microfacet that sends `v` to `l`.
    pub fn pdf(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        let n_dot_l = n.dot(l);
        let n_dot_v = n.dot(v);
        let (p, g) = self.lobe_probabilities(n_dot_v);
        let below = n_dot_l < 0.0;
        let nothing_drawn = if below { g <= 0.0 } else { n_dot_l <= 0.0 };
        if nothing_drawn {
            return 0.0;
        }
        let (normal_pdf, v_dot_h) = if below {
            self.transmission_pdf(n, l, v)
        } else {
            let h = (l + v).normalize();
            (
                visible_normal_pdf(n_dot_v, n.dot(h), self.alpha()),
                v.dot(h),
            )
        };
        let reflecting = if g > 0.0 {
            self.glass_reflectance(v_dot_h)
        } else {
            0.0
        };
        if below {
            return g * (1.0 - reflecting) * normal_pdf;
        }
        let diffuse = (1.0 - p - g) * n_dot_l * FRAC_1_PI;
        let share = p + g * reflecting;
        if share <= 0.0 {
            return diffuse;
        }
        share * normal_pdf + diffuse
    }

    /// The direction point `u` ([0, 1)^3) draws at unit normal `n` seen from `v`, with its
    /// density and weight; `None` where it carries no light (a reflection below or a
    /// refraction above the surface). The first coordinate picks the lobe and is stretched
    /// back to [0, 1) within it; the specular lobe and the glass draw one visible normal
    /// alike, and the third coordinate picks whether the glass's reflects.
    pub fn sample(&self, n: Vec3, v: Vec3, u: Vec3) -> Option<BrdfSample> {
        let (p, g) = self.lobe_probabilities(n.dot(v));
        let direction = if u.x < p + g {
            let glass = u.x >= p;
            let at = Vec2::new(if glass { (u.x - p) / g } else { u.x / p }, u.y);
            let h = visible_normal_around(n, v, self.alpha(), at);
            if !glass || u.z < self.glass_reflectance(v.dot(h)) {
                // The draws' density counts only what goes above the surface.
                Some(2.0 * v.dot(h) * h - v).filter(|l| n.dot(*l) > 0.0)?
            } else {
                self.transmitted_through(n, v, h)?
            }
        } else {
            let stretched = Vec2::new((u.x - p - g) / (1.0 - p - g), u.y);
            cosine_direction(n, stretched)
        };
        let pdf = self.pdf(n, direction, v);
        finish_draw(n, direction, pdf, || self.evaluate(n, direction, v))
    }
}

/// A normal of GGX's distribution (alpha `alpha`) about unit normal `n` visible from `v`,
/// drawn by `u` (`visible_normal` in the frame of `n`).
pub fn visible_normal_around(n: Vec3, v: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    let (t, b) = orthonormal_frame(n);
    let m = visible_normal(Vec3::new(v.dot(t), v.dot(b), v.dot(n)), alpha, u);
    t * m.x + b * m.y + n * m.z
}

/// The draw of `direction` at unit normal `n` from a mixture whose density of it is `pdf`,
/// weighed by f |cos| / pdf with f = `f()`; `None` where it grazes the surface or the mixture
/// could not have drawn it. Every BRDF's `sample` ends here, so that all weigh alike.
pub fn finish_draw(
    n: Vec3,
    direction: Vec3,
    pdf: f32,
    f: impl FnOnce() -> Vec3,
) -> Option<BrdfSample> {
    let cos = n.dot(direction).abs();
    if cos <= 0.0 || pdf <= 0.0 || !pdf.is_finite() {
        return None;
    }
    Some(BrdfSample {
        direction,
        pdf,
        weight: f() * (cos / pdf),
    })
}

/// The density per solid angle of l drawn through a visible normal h: D_v(h) / (4 v.h) =
/// G1(v) D(h) / (4 n.v), with Smith's G1 = 2 n.v / (n.v + sqrt(a^2 + (1 - a^2) n.v^2)).
pub fn visible_normal_pdf(n_dot_v: f32, n_dot_h: f32, alpha: f32) -> f32 {
    if n_dot_v <= 0.0 || n_dot_h <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let lambda = (a2 + (1.0 - a2) * n_dot_v * n_dot_v).sqrt();
    ggx_distribution(n_dot_h, alpha) / (2.0 * (n_dot_v + lambda))
}

/// A normal of GGX's distribution (alpha `alpha`) visible from `v` (local frame, normal +Z,
/// v.z > 0) drawn by `u`: Heitz's listing 1.
pub fn visible_normal(v: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    // The view direction in the hemisphere configuration.
    let vh = Vec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
    } else {
        Vec3::X
    };
    let t2 = vh.cross(t1);
    // A point on the projected disk, its half under vh squeezed.
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let p1 = r * phi.cos();
    let mut p2 = r * phi.sin();
    let s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    // Back to the ellipsoid configuration.
    Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::brdf::Dielectric;

    fn surface(base: Vec3, metallic: f32, roughness: f32) -> MetallicRoughness {
        MetallicRoughness {
            base_colour: base,
            metallic,
            roughness,
            specular: 1.0,
            dielectric: Dielectric::OPAQUE,
        }
    }

    /// A stratified grid of `steps`^2 points of [0, 1)^2.
    fn grid(steps: usize) -> impl Iterator<Item = Vec2> {
        (0..steps * steps).map(move |k| {
            Vec2::new(
                ((k / steps) as f32 + 0.5) / steps as f32,
                ((k % steps) as f32 + 0.5) / steps as f32,
            )
        })
    }

    /// The mean weight of the drawn directions is the directional albedo, which a midpoint
    /// rule over the hemisphere computes independently of the sampling; and every draw's
    /// density is `pdf` of its direction.
    #[test]
    fn draws_estimate_the_albedo_and_carry_their_density() {
        let n = Vec3::new(0.1, 0.2, 0.95).normalize();
        let (t, b) = orthonormal_frame(n);
        for (metallic, roughness) in [(0.0, 1.0), (0.0, 0.3), (1.0, 0.2), (1.0, 0.7), (0.5, 0.5)] {
            let s = surface(Vec3::new(0.9, 0.6, 0.3), metallic, roughness);
            for mu in [0.3f32, 0.8, 1.0] {
                let v = t * (1.0 - mu * mu).sqrt() + n * mu;
                let steps = 512;
                let mut drawn = glam::DVec3::ZERO;
                for u in grid(steps) {
                    if let Some(d) = s.sample(n, v, u.extend(0.5)) {
                        let pdf = s.pdf(n, d.direction, v);
                        assert!((pdf - d.pdf).abs() <= 1e-6 * pdf, "{pdf} against {}", d.pdf);
                        drawn += d.weight.as_dvec3();
                    }
                }
                let drawn = drawn / (steps * steps) as f64;
                // Midpoint rule over (theta, phi) about n: fine enough in theta for the
                // narrowest lobe (alpha 0.04) at normal incidence.
                let (qt, qp) = (1000, 1000);
                let (dt, dp) = (0.5 * PI / qt as f32, 2.0 * PI / qp as f32);
                let mut quadrature = glam::DVec3::ZERO;
                for i in 0..qt {
                    let (sin, cos) = ((i as f32 + 0.5) * dt).sin_cos();
                    for j in 0..qp {
                        let phi = (j as f32 + 0.5) * dp;
                        let l = t * (sin * phi.cos()) + b * (sin * phi.sin()) + n * cos;
                        quadrature += (s.evaluate(n, l, v) * (cos * sin)).as_dvec3();
                    }
                }
                let quadrature = quadrature * (dt * dp) as f64;
                let error = ((drawn - quadrature).abs() / quadrature).max_element();
                println!(
                    "metallic {metallic}, roughness {roughness}, n.v {mu}: drawn {drawn:.4}, \
                     quadrature {quadrature:.4}, relative error {error:.2e}"
                );
                assert!(error < 5e-3, "{drawn} against {quadrature}");
            }
        }
    }

    /// The mixture's density integrates over the hemisphere to the share of draws that land
    /// above the surface (the specular lobe sends some below, more the rougher and the more
    /// grazing the view).
    #[test]
    fn the_density_integrates_to_the_share_of_draws_above() {
        let n = Vec3::Z;
        for (metallic, roughness, mu) in [(0.0, 0.5, 0.9f32), (1.0, 0.3, 1.0), (1.0, 1.0, 0.5)] {
            let s = surface(Vec3::ONE, metallic, roughness);
            let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let q = 800;
            let mut sum = 0.0f64;
            for i in 0..q {
                let cos = (i as f32 + 0.5) / q as f32;
                let sin = (1.0 - cos * cos).sqrt();
                for j in 0..2 * q {
                    let phi = (j as f32 + 0.5) / (2 * q) as f32 * 2.0 * PI;
                    let l = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                    sum += s.pdf(n, l, v) as f64;
                }
            }
            let integral = sum * std::f64::consts::PI / (q * q) as f64;
            let steps = 512;
            let above = grid(steps)
                .filter(|&u| s.sample(n, v, u.extend(0.5)).is_some())
                .count();
            let share = above as f64 / (steps * steps) as f64;
            println!(
                "metallic {metallic}, roughness {roughness}, n.v {mu}: integral {integral:.5}, \
                 share of draws above {share:.5}"
            );
            assert!(
                (integral - share).abs() < 2e-3,
                "{integral} against {share}"
            );
        }
    }

    /// Seen from the normal, a visible normal is drawn by D (n.h): n.h's distribution is
    /// GGX's, whose median cos^2 is 1 / (1 + a^2).
    #[test]
    fn visible_normals_seen_head_on_follow_the_distribution() {
        let alpha = 0.5f32;
        let mut below = 0usize;
        let steps = 256;
        for u in grid(steps) {
            let m = visible_normal(Vec3::Z, alpha, u);
            if m.z * m.z < 1.0 / (1.0 + alpha * alpha) {
                below += 1;
            }
        }
        let share = below as f32 / (steps * steps) as f32;
        println!("share of normals past the median: {share}");
        assert!((share - 0.5).abs() < 2e-3, "{share}");
    }
}
