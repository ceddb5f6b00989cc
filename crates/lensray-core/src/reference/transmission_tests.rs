use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec2, Vec3};

use super::*;
use crate::interface::MIN_ROUGHNESS;
use crate::reference::brdf::Dielectric;

/// The golden ratio's fraction: the step of a rank-1 lattice that spreads a third coordinate
/// (the glass draw's choice) evenly over a grid's points.
const GOLDEN: f64 = 0.618_033_988_749_895;

/// White glass (T = 1) of roughness `roughness`, seen through a boundary of relative index
/// `eta` (1: a thin wall).
fn glass(roughness: f32, eta: f32) -> MetallicRoughness {
    MetallicRoughness {
        base_colour: Vec3::ONE,
        metallic: 0.0,
        roughness,
        specular: 1.0,
        dielectric: Dielectric {
            ior: 1.5,
            transmission: 1.0,
            eta,
        },
    }
}

/// The view at n.v = `mu` (normal +Z).
fn view(mu: f32) -> Vec3 {
    Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu)
}

/// The integral of `g(l)` over the directions on `l.z`'s side `side` (+1 or -1) of the
/// surface: a midpoint rule in polar coordinates (psi, phi) about `centre`, psi = pi s^2, whose
/// steps are finest at a lobe's peak.
fn integrate(centre: Vec3, side: f32, g: impl Fn(Vec3) -> DVec3) -> DVec3 {
    let (e1, e2) = crate::scene::light::orthonormal_frame(centre);
    let (qs, qp) = (1500, 600);
    let (ds, dp) = (1.0 / qs as f64, TAU / qp as f64);
    let mut sum = DVec3::ZERO;
    for i in 0..qs {
        let t = (i as f64 + 0.5) * ds;
        let psi = PI * t * t;
        let jacobian = psi.sin() * 2.0 * PI * t;
        let (sin, cos) = (psi.sin() as f32, psi.cos() as f32);
        for j in 0..qp {
            let phi = ((j as f64 + 0.5) * dp) as f32;
            let l = centre * cos + (e1 * phi.cos() + e2 * phi.sin()) * sin;
            if l.z * side > 0.0 {
                sum += g(l) * jacobian;
            }
        }
    }
    sum * ds * dp
}

/// What `s` reflects and transmits of light arriving from every direction at n.v = `mu`:
/// the integrals of f |cos| above and below the surface.
fn reflected_and_transmitted(s: &MetallicRoughness, mu: f32) -> (f64, f64) {
    let v = view(mu);
    let f_cos = |l: Vec3| (s.evaluate(Vec3::Z, l, v) * l.z.abs()).as_dvec3();
    let mirror = Vec3::new(-v.x, 0.0, v.z);
    let reflected = integrate(mirror, 1.0, f_cos).x;
    let eta = s.dielectric.eta;
    let through = if eta == 1.0 {
        Some(-v)
    } else {
        refract(v, Vec3::Z, eta)
    };
    let transmitted = integrate(through.unwrap_or(-Vec3::Z), -1.0, f_cos).x;
    (reflected, transmitted)
}

/// At normal incidence on smooth glass every draw is the glass's, and 1 - f0 = 0.96 of its
/// microfacets refract (f0 = 0.04), each draw carrying 1 / 1.5^2 of the radiance (the lobe's
/// shadowing is 1 to 1e-5 at alpha 0.002) straight down, and at 45 degrees they leave along
/// Snell's direction, sin 45 / 1.5.
#[test]
fn smooth_glass_refracts_as_snell_and_fresnel_say() {
    let s = glass(MIN_ROUGHNESS, 1.5);
    let (p, g) = s.lobe_probabilities(1.0);
    let reflecting = s.glass_reflectance(1.0);
    assert!(
        p == 0.0 && g == 1.0 && (reflecting - 0.04).abs() < 1e-6,
        "{p} {g} {reflecting}"
    );
    let draw = s
        .sample(Vec3::Z, Vec3::Z, Vec3::new(0.5, 0.3, 0.5))
        .unwrap();
    let want = 1.0 / 2.25;
    println!(
        "normal incidence: weight {} against {want}, direction {}",
        draw.weight, draw.direction
    );
    assert!((draw.weight.x - want).abs() < 1e-4 * want);
    assert!(draw.direction.z < -0.9999);
    let v = view(std::f32::consts::FRAC_1_SQRT_2);
    let want = std::f32::consts::FRAC_1_SQRT_2 / 1.5;
    let mut deviations = Vec::new();
    for i in 0..64 {
        let u = Vec3::new(
            0.1 + 0.9 * (i as f32 + 0.5) / 64.0,
            (i % 8) as f32 / 8.0,
            (i as f64 * GOLDEN).fract() as f32,
        );
        if let Some(draw) = s.sample(Vec3::Z, v, u) {
            if draw.direction.z < 0.0 {
                let sin = draw.direction.truncate().length();
                deviations.push((sin - want).abs());
                assert!(draw.direction.x < 0.0, "{}", draw.direction);
            }
        }
    }
    // GGX's long tail tilts a few draws' microfacets by more than alpha.
    deviations.sort_by(f32::total_cmp);
    let (median, worst) = (
        deviations[deviations.len() / 2],
        deviations[deviations.len() - 1],
    );
    println!(
        "45 degrees: {} refracted draws, sin within {median} (median), {worst} of {want}",
        deviations.len()
    );
    assert!(
        deviations.len() > 50 && median < 1e-3 && worst < 0.02,
        "{median} {worst}"
    );
}

/// Glass reflects and transmits what arrives and no more: the reflected part plus eta^2
/// times the transmitted one (radiance is squeezed by eta^2 on the way in) is 1 less what
/// the GGX lobe's single scattering loses, more the rougher and the more grazing (measured:
/// at most 0.9 / 3.0 / 9.5 % at roughness 0.3 and n.v 1 / 0.5 / 0.2, 18 / 26 / 26.5 % at 0.6;
/// GGX alone at roughness 1 keeps 1 - ln 2, `brdf.rs`). From inside smooth glass beyond the
/// critical angle (n.v < 0.745 for 1 / 1.5) nothing goes through.
#[test]
fn glass_conserves_energy_through_its_boundary() {
    for eta in [1.5f32, 1.0 / 1.5, 1.0] {
        for (roughness, bounds) in [(0.3f32, [0.015, 0.035, 0.11]), (0.6, [0.19, 0.28, 0.28])] {
            for (mu, bound) in [1.0f32, 0.5, 0.2].into_iter().zip(bounds) {
                let s = glass(roughness, eta);
                let (r, t) = reflected_and_transmitted(&s, mu);
                let total = r + t * f64::from(eta * eta);
                println!(
                    "eta {eta:.3}, roughness {roughness}, n.v {mu}: reflected {r:.4}, \
                     transmitted {t:.4}, energy {total:.4}"
                );
                assert!(
                    total <= 1.002,
                    "energy {total} at eta {eta} roughness {roughness} n.v {mu}"
                );
                assert!(
                    total >= 1.0 - bound,
                    "energy {total} at eta {eta} roughness {roughness} n.v {mu}"
                );
            }
        }
    }
}

#[test]
fn nothing_leaves_smooth_glass_beyond_the_critical_angle() {
    let s = glass(MIN_ROUGHNESS, 1.0 / 1.5);
    let v = view(0.5);
    assert_eq!(s.fresnel(0.5), Vec3::ONE);
    assert_eq!(s.glass_reflectance(0.5), 1.0);
    for x in [-0.9f32, -0.5, 0.0, 0.5] {
        let l = Vec3::new(x, 0.1, -1.0).normalize();
        // GGX's tail still holds microfacets tilted enough to refract: 1e-5 of f at most.
        let f = s.evaluate(Vec3::Z, l, v).max_element();
        assert!(f < 1e-4, "{l}: {f}");
    }
    // Inside the critical angle it does: n.v 0.9 refracts at sin = 1.5 sin(acos 0.9).
    assert!(s.glass_reflectance(0.9) < 0.1);
}

/// A glass draw reflects or refracts as its microfacet's Fresnel says, so its weight is
/// G2 / G1 (at most 1) of the light it finds, radiance squeezed by eta^2 on the way in
/// aside: no draw is a firefly, at any angle, from outside or inside, through a volume or a
/// thin wall. Choosing by the macro normal's Fresnel weighed a refracted draw by
/// (1 - F(v.h)) / (1 - F(n.v)) of that: up to 1 / alpha beyond the critical angle.
#[test]
fn no_glass_draw_carries_more_than_the_light_it_finds() {
    for eta in [1.5f32, 1.0 / 1.5, 1.0] {
        for roughness in [0.1f32, 0.3, 0.7] {
            for mu in [0.05f32, 0.3, 0.7, 1.0] {
                let (s, v) = (glass(roughness, eta), view(mu));
                let (side, mut most, mut drawn) = (128, 0.0f32, 0);
                for i in 0..side * side {
                    let u = ((Vec2::new((i / side) as f32, (i % side) as f32) + 0.5) / side as f32)
                        .extend((i as f64 * GOLDEN).fract() as f32);
                    let Some(draw) = s.sample(Vec3::Z, v, u) else {
                        continue;
                    };
                    let squeeze = if draw.direction.z < 0.0 {
                        eta * eta
                    } else {
                        1.0
                    };
                    most = most.max(draw.weight.max_element() * squeeze);
                    drawn += 1;
                }
                println!(
                    "eta {eta:.3}, roughness {roughness}, n.v {mu}: {drawn} draws, the \
                     heaviest {most:.4}"
                );
                assert!(most <= 1.0 + 1e-3, "{most}");
            }
        }
    }
}

/// The draws' mean weight is what the quadrature of f |cos| finds over both sides, and each
/// draw carries the density `pdf` gives its direction.
#[test]
fn draws_estimate_what_the_quadrature_finds() {
    let tinted = |roughness, eta| MetallicRoughness {
        base_colour: Vec3::new(0.9, 0.7, 0.4),
        dielectric: Dielectric {
            transmission: 0.7,
            ..glass(roughness, eta).dielectric
        },
        ..glass(roughness, eta)
    };
    for (s, mu) in [
        (glass(0.3, 1.5), 0.8f32),
        (glass(0.5, 1.0 / 1.5), 0.9),
        (tinted(0.4, 1.5), 0.4),
        (tinted(0.3, 1.0), 0.6),
        // From inside beyond the critical angle (n.v 0.745 for 1.5): tilted microfacets let
        // light out that the macro normal's Fresnel would reflect.
        (glass(0.3, 1.0 / 1.5), 0.7),
        (glass(0.6, 1.0 / 1.5), 0.5),
        // Grazing from outside.
        (glass(0.3, 1.5), 0.1),
        // Part metal: its reflection draws and the glass's share the reflected side.
        (
            MetallicRoughness {
                metallic: 0.3,
                ..tinted(0.4, 1.5)
            },
            0.5,
        ),
    ] {
        let v = view(mu);
        let (r, t) = reflected_and_transmitted(&s, mu);
        let side = 256;
        let n = side * side;
        let mut sum = 0.0f64;
        for i in 0..n {
            let (a, b) = (i / side, i % side);
            let u = ((Vec2::new(a as f32, b as f32) + 0.5) / side as f32)
                .extend((i as f64 * GOLDEN).fract() as f32);
            let Some(draw) = s.sample(Vec3::Z, v, u) else {
                continue;
            };
            let pdf = s.pdf(Vec3::Z, draw.direction, v);
            assert!(
                (pdf - draw.pdf).abs() <= 1e-4 * pdf,
                "{pdf} against {}",
                draw.pdf
            );
            sum += f64::from(draw.weight.x);
        }
        let estimate = sum / f64::from(n);
        let want = r + t;
        println!(
            "eta {}, roughness {}, n.v {mu}: draws {estimate:.4}, quadrature {want:.4}",
            s.dielectric.eta, s.roughness
        );
        assert!(
            (estimate - want).abs() < 0.01 * want,
            "{estimate} against {want}"
        );
    }
}
