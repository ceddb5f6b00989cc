//! glTF's metallic-roughness BRDF, as the specification's Appendix B defines it: a GGX
//! (Trowbridge-Reitz) distribution with alpha = roughness^2, the height-correlated Smith
//! visibility term and Schlick's Fresnel, whose reflectance at normal incidence is the
//! dielectric's (((ior - 1) / (ior + 1))^2, `KHR_materials_ior`) for dielectrics and the base
//! colour for metals, mixed by `metallic`; the dielectric's Fresnel is weighed by `specular` as
//! `KHR_materials_specular` does (1: Appendix B; 0: no specular lobe, Lambert). A dielectric
//! that transmits (`KHR_materials_transmission`: weight T) sends that share of what it does not
//! reflect through the surface instead of diffusing it (`transmission.rs`):
//!
//! ```text
//! c_diff = base (1 - metallic)
//! f0 = lerp(f0(ior) specular, base, metallic)     f90 = lerp(specular, 1, metallic)
//! F = f0 + (f90 - f0) (1 - |v.h|)^5
//! f = (1 - F) (1 - T) c_diff / pi + F D V                      (l above the surface)
//! f = (1 - F) T c_diff f_t                                      (l below: transmission.rs)
//! ```
//!
//! Seen from inside a volume, Schlick's cosine is the one outside (the refracted one), and
//! beyond the critical angle F = 1 (total internal reflection).
//! shaders/include/brdf.glsl mirrors it function by function.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3;

use crate::interface::{DEFAULT_IOR, MIN_ROUGHNESS};

/// What the BRDF of a surface point needs: its base colour, metallic and roughness (each the
/// material's factor times its texture, in [0, 1]), the weight of a dielectric's specular
/// lobe (`Material::specular`) and what the dielectric refracts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    pub base_colour: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    pub specular: f32,
    pub dielectric: Dielectric,
}

/// The dielectric's optics at a surface point: its index of refraction, the share T of its
/// unreflected light that goes through the surface, and `eta`, the index beyond the surface
/// over the index on the viewer's side: `ior` where a ray enters a volume through its front
/// face, 1 / `ior` where it leaves through its back face, and 1 through a thin wall (which
/// refracts nothing: its transmission is its reflection lobe mirrored through the surface).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    pub ior: f32,
    pub transmission: f32,
    pub eta: f32,
}

impl Dielectric {
    /// An opaque dielectric of the default index.
    pub const OPAQUE: Self = Self {
        ior: DEFAULT_IOR,
        transmission: 0.0,
        eta: DEFAULT_IOR,
    };

    /// The reflectance at normal incidence, ((ior - 1) / (ior + 1))^2.
    pub fn f0(&self) -> f32 {
        let r = (self.ior - 1.0) / (self.ior + 1.0);
        r * r
    }

    /// The cosine Schlick's Fresnel takes for a microfacet at cosine `cos` to the viewer: `cos`
    /// itself, or from inside a volume (`eta` < 1) the refracted direction's; `None` beyond the
    /// critical angle.
    pub fn outside_cosine(&self, cos: f32) -> Option<f32> {
        if self.eta >= 1.0 {
            return Some(cos);
        }
        let sin2 = (1.0 - cos * cos).max(0.0) / (self.eta * self.eta);
        (sin2 < 1.0).then(|| (1.0 - sin2).sqrt())
    }
}

impl MetallicRoughness {
    /// GGX's alpha: roughness^2, roughness clamped to [`MIN_ROUGHNESS`], 1].
    pub fn alpha(&self) -> f32 {
        let r = self.roughness.clamp(MIN_ROUGHNESS, 1.0);
        r * r
    }

    /// The diffuse colour: metals have none.
    pub fn diffuse_colour(&self) -> Vec3 {
        self.base_colour * (1.0 - self.metallic)
    }

    /// The reflectance at normal incidence.
    pub fn f0(&self) -> Vec3 {
        Vec3::splat(self.dielectric.f0() * self.specular).lerp(self.base_colour, self.metallic)
    }

    /// The reflectance at grazing incidence.
    pub fn f90(&self) -> f32 {
        self.specular + (1.0 - self.specular) * self.metallic
    }

    /// Whether light goes through the surface (a dielectric share that transmits).
    pub fn transmits(&self) -> bool {
        self.dielectric.transmission > 0.0 && self.metallic < 1.0
    }

    /// Schlick's Fresnel of a microfacet at cosine `v_dot_h` to the viewer, 1 beyond the
    /// critical angle.
    pub fn fresnel(&self, v_dot_h: f32) -> Vec3 {
        match self.dielectric.outside_cosine(v_dot_h) {
            Some(cos) => schlick_fresnel(self.f0(), self.f90(), cos),
            None => Vec3::ONE,
        }
    }

    /// f(l, v) for unit normal `n`, direction to the light `l` and to the viewer `v`, with
    /// n.l != 0 and n.v >= 0 (the caller's cosine tests); 1/sr. Light from below the surface
    /// is transmitted light (`transmission.rs`).
    pub fn evaluate(&self, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
        let n_dot_l = n.dot(l);
        if n_dot_l < 0.0 {
            return self.transmitted(n, l, v);
        }
        let h = (l + v).normalize();
        let n_dot_v = n.dot(v).max(0.0);
        let alpha = self.alpha();
        let fresnel = self.fresnel(v.dot(h).abs());
        let specular =
            ggx_distribution(n.dot(h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
        let diffuse = self.diffuse_colour() * ((1.0 - self.dielectric.transmission) * FRAC_1_PI);
        (Vec3::ONE - fresnel) * diffuse + fresnel * specular
    }
}

/// GGX's normal distribution D(h) for n.h = `n_dot_h`; its projected area integrates to 1.
/// The denominator's n.h^2 (a2 - 1) + 1 is summed as (1 - n.h^2) + n.h^2 a2: near the peak the
/// first form loses a2's digits to the cancellation (3e-4 of D at alpha 0.01 in f32).
pub fn ggx_distribution(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let c2 = n_dot_h * n_dot_h;
    let d = (1.0 - c2) + c2 * a2;
    a2 / (PI * d * d)
}

/// The height-correlated Smith visibility V = G2 / (4 |n.l| |n.v|).
pub fn smith_visibility(n_dot_l: f32, n_dot_v: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let ggx_v = n_dot_l * (n_dot_v * n_dot_v * (1.0 - a2) + a2).sqrt();
    let ggx_l = n_dot_v * (n_dot_l * n_dot_l * (1.0 - a2) + a2).sqrt();
    0.5 / (ggx_v + ggx_l)
}

/// Schlick's Fresnel: f0 + (f90 - f0) (1 - v.h)^5.
pub fn schlick_fresnel(f0: Vec3, f90: f32, v_dot_h: f32) -> Vec3 {
    let m = (1.0 - v_dot_h).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (Vec3::splat(f90) - f0) * (m2 * m2 * m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(base: Vec3, metallic: f32, roughness: f32) -> MetallicRoughness {
        MetallicRoughness {
            base_colour: base,
            metallic,
            roughness,
            specular: 1.0,
            dielectric: Dielectric::OPAQUE,
        }
    }

    fn assert_close(got: Vec3, want: Vec3, relative: f32, what: &str) {
        let error = ((got - want).abs() / want.abs().max(Vec3::splat(1e-6))).max_element();
        println!("{what}: {got} against {want}, relative error {error:.2e}");
        assert!(error <= relative, "{what}: {got} against {want}");
    }

    /// n = l = v: h = n, D = 1 / (pi alpha^2), V = 1/4, F = f0.
    #[test]
    fn normal_incidence_matches_the_formulas() {
        let n = Vec3::Z;
        let grey = Vec3::splat(0.5);
        // Dielectric, roughness 1: 0.96 * 0.5 / pi + 0.04 * 1/4 / pi = 0.49 / pi.
        let f = surface(grey, 0.0, 1.0).evaluate(n, n, n);
        assert_close(
            f,
            Vec3::splat(0.155_971_84),
            1e-5,
            "dielectric, roughness 1",
        );
        // Roughness 0.1 (alpha 0.01): 0.04 / (4 pi 1e-4) + 0.48 / pi.
        let f = surface(grey, 0.0, 0.1).evaluate(n, n, n);
        assert_close(
            f,
            Vec3::splat(31.983_777),
            1e-5,
            "dielectric, roughness 0.1",
        );
        // Metal, roughness 1: no diffuse, F = the base colour: base / (4 pi).
        let base = Vec3::new(0.9, 0.6, 0.3);
        let f = surface(base, 1.0, 1.0).evaluate(n, n, n);
        let want = Vec3::new(0.071_619_72, 0.047_746_48, 0.023_873_24);
        assert_close(f, want, 1e-5, "metal, roughness 1");
    }

    /// l and v 80 degrees off the normal on either side: h = n, v.h = cos 80; roughness 0.5
    /// (alpha 0.25): D = 1 / (pi 0.0625) = 5.092958, V = 0.5 / (2 c sqrt(c^2 (1 - a2) + a2)) =
    /// 4.778601, F = 0.04 + 0.96 (1 - c)^5 = 0.409910; f = (1 - F) / pi + F D V.
    #[test]
    fn grazing_incidence_matches_the_formulas() {
        let (sin, cos) = 80f32.to_radians().sin_cos();
        let (l, v) = (Vec3::new(sin, 0.0, cos), Vec3::new(-sin, 0.0, cos));
        assert!((ggx_distribution(1.0, 0.25) - 5.092_958).abs() < 1e-5);
        assert!((smith_visibility(cos, cos, 0.25) - 4.778_601).abs() < 1e-4);
        let fresnel = schlick_fresnel(Vec3::splat(0.04), 1.0, cos);
        assert_close(
            fresnel,
            Vec3::splat(0.409_910),
            1e-5,
            "Fresnel at 80 degrees",
        );
        let f = surface(Vec3::ONE, 0.0, 0.5).evaluate(Vec3::Z, l, v);
        assert_close(f, Vec3::splat(10.163_902), 1e-5, "dielectric at 80 degrees");
    }

    /// Specular weight 0 leaves a dielectric Lambert (c / pi at any angle, whatever its
    /// roughness); half weighs F by a half (f0 0.02, f90 0.5); a metal ignores it.
    #[test]
    fn the_specular_weight_scales_the_dielectric_lobe() {
        let (sin, cos) = 80f32.to_radians().sin_cos();
        let (l, v) = (
            Vec3::new(sin, 0.0, cos),
            Vec3::new(-0.3, 0.1, 0.9).normalize(),
        );
        let base = Vec3::new(0.8, 0.5, 0.2);
        let lambert = MetallicRoughness {
            specular: 0.0,
            ..surface(base, 0.0, 0.2)
        };
        assert_close(lambert.evaluate(Vec3::Z, l, v), base / PI, 1e-6, "weight 0");
        let half = MetallicRoughness {
            specular: 0.5,
            ..surface(Vec3::ONE, 0.0, 1.0)
        };
        // n = l = v, alpha 1: (1 - 0.02) / pi + 0.02 / (4 pi).
        let n = Vec3::Z;
        let want = Vec3::splat(0.313_535_24);
        assert_close(half.evaluate(n, n, n), want, 1e-5, "weight 0.5");
        let metal = surface(base, 1.0, 0.5);
        let weighed = MetallicRoughness {
            specular: 0.0,
            ..metal
        };
        assert_eq!(metal.evaluate(n, l, v), weighed.evaluate(n, l, v));
    }

    #[test]
    fn the_brdf_is_reciprocal() {
        let n = Vec3::new(0.2, -0.3, 0.9).normalize();
        let l = Vec3::new(0.7, 0.1, 0.5).normalize();
        let v = Vec3::new(-0.4, 0.6, 0.6).normalize();
        for (metallic, roughness) in [(0.0, 1.0), (0.0, 0.2), (1.0, 0.3), (0.5, 0.6)] {
            let s = surface(Vec3::new(0.8, 0.5, 0.2), metallic, roughness);
            let what = format!("metallic {metallic}, roughness {roughness}");
            assert_close(s.evaluate(n, l, v), s.evaluate(n, v, l), 1e-5, &what);
        }
    }

    /// The directional albedo of f at n.v = `mu`: the integral of f cos over the hemisphere of
    /// l, a midpoint rule over (cos theta, phi).
    fn albedo(s: &MetallicRoughness, mu: f32, steps: usize) -> Vec3 {
        let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        let mut sum = glam::DVec3::ZERO;
        for i in 0..steps {
            let cos = (i as f32 + 0.5) / steps as f32;
            let sin = (1.0 - cos * cos).sqrt();
            for j in 0..2 * steps {
                let phi = (j as f32 + 0.5) / (2 * steps) as f32 * 2.0 * PI;
                let l = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                sum += (s.evaluate(Vec3::Z, l, v) * cos).as_dvec3();
            }
        }
        (sum * (std::f64::consts::PI / (steps * steps) as f64)).as_vec3()
    }

    /// The specular lobe alone (a white metal: F = 1) reflects at most what arrives; at alpha
    /// = 1 and normal incidence exactly 1 - ln 2 (D = 1 / pi, G2 = 2 mu / (1 + mu): the
    /// integral of mu / (1 + mu) over [0, 1]).
    #[test]
    fn directional_albedo_conserves_energy() {
        let at_one = albedo(&surface(Vec3::ONE, 1.0, 1.0), 1.0, 400).x;
        let want = 1.0 - std::f32::consts::LN_2;
        println!("specular albedo at alpha 1, n.v 1: {at_one} against 1 - ln 2 = {want}");
        assert!((at_one - want).abs() < 1e-4, "{at_one} against {want}");
        for roughness in [0.5, 0.7, 1.0] {
            for mu in [0.1, 0.5, 0.9, 1.0] {
                let metal = albedo(&surface(Vec3::ONE, 1.0, roughness), mu, 200).x;
                println!("roughness {roughness}, n.v {mu}: specular albedo {metal:.4}");
                assert!(metal <= 1.0, "roughness {roughness}, n.v {mu}: {metal}");
            }
        }
    }

    /// A smooth lobe reflects nearly all that arrives at normal incidence: the specular albedo
    /// at roughness 0.1, by importance sampling GGX's normals (pdf D (n.h) / (4 v.h) in l), is
    /// the mean of V 4 (v.h) (n.l) / (n.h), within 1e-3 of 1.
    #[test]
    fn a_smooth_lobe_reflects_almost_everything() {
        let alpha = surface(Vec3::ONE, 1.0, 0.1).alpha();
        let steps = 256;
        let mut sum = 0.0f64;
        for i in 0..steps {
            for j in 0..steps {
                let (u1, u2) = (
                    (i as f32 + 0.5) / steps as f32,
                    (j as f32 + 0.5) / steps as f32,
                );
                let cos = ((1.0 - u1) / (1.0 + (alpha * alpha - 1.0) * u1)).sqrt();
                let sin = (1.0 - cos * cos).sqrt();
                let phi = 2.0 * PI * u2;
                let h = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                let l = 2.0 * h.z * h - Vec3::Z;
                if l.z > 0.0 {
                    let weight = smith_visibility(l.z, 1.0, alpha) * 4.0 * h.z * l.z / h.z;
                    sum += weight as f64;
                }
            }
        }
        let e = sum / (steps * steps) as f64;
        println!("specular albedo at roughness 0.1, n.v 1: {e}");
        assert!((e - 1.0).abs() < 1e-3, "{e}");
    }

    /// D's projected area is 1: the integral of D(mu) mu 2 pi over mu in [0, 1].
    #[test]
    fn the_distribution_is_normalised() {
        for alpha in [0.04f32, 0.36, 1.0] {
            let steps = 200_000;
            let sum: f64 = (0..steps)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / steps as f64;
                    ggx_distribution(mu as f32, alpha) as f64 * mu
                })
                .sum();
            let area = sum * 2.0 * std::f64::consts::PI / steps as f64;
            println!("alpha {alpha}: projected area {area}");
            assert!((area - 1.0).abs() < 1e-3, "alpha {alpha}: {area}");
        }
    }
}
