use std::f32::consts::PI;

use glam::{DVec3, Vec3};

use super::*;
use crate::reference::layer_tests::{assert_draws_estimate, base};

fn coated(base: MetallicRoughness, weight: f32, roughness: f32) -> LayeredBrdf {
    LayeredBrdf {
        base,
        clearcoat: Clearcoat {
            weight,
            roughness,
            normal: Vec3::Z,
        },
        sheen: crate::reference::sheen::Sheen::default(),
    }
}

/// The directional albedo of `s` at n.v = `mu` (base normal +Z): the integral of what it
/// reflects (f cos, `reflected`) over the sphere (nothing below the base but what a tilted coat
/// reflects), a midpoint rule in polar coordinates (psi, phi) about the mirror direction with
/// psi = pi s^2, whose steps are finest where a smooth lobe's peak is (alpha 0.01 at grazing
/// views is 0.6 degrees wide).
fn albedo(s: &LayeredBrdf, mu: f32) -> DVec3 {
    let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let mirror = Vec3::new(-v.x, 0.0, v.z);
    let (e1, e2) = crate::scene::light::orthonormal_frame(mirror);
    let (qs, qp) = (2000, 720);
    let (ds, dp) = (1.0 / qs as f64, std::f64::consts::TAU / qp as f64);
    let mut sum = DVec3::ZERO;
    for i in 0..qs {
        let t = (i as f64 + 0.5) * ds;
        let psi = std::f64::consts::PI * t * t;
        // d(solid angle) = sin psi dpsi dphi, dpsi = 2 pi s ds.
        let jacobian = psi.sin() * 2.0 * std::f64::consts::PI * t;
        let (sin, cos) = (psi.sin() as f32, psi.cos() as f32);
        for j in 0..qp {
            let phi = ((j as f64 + 0.5) * dp) as f32;
            let l = mirror * cos + (e1 * phi.cos() + e2 * phi.sin()) * sin;
            sum += s.reflected(Vec3::Z, l, v).as_dvec3() * jacobian;
        }
    }
    sum * ds * dp
}

/// n = l = v: Fc = f0 = 0.04, the coat's D = 1 / (pi alpha^2) and V = 1/4.
#[test]
fn the_layers_mix_as_the_specification_says() {
    let n = Vec3::Z;
    let grey = base(Vec3::splat(0.5), 0.0, 1.0, 1.0);
    // The base alone: 0.49 / pi (brdf.rs's test); the coat at roughness 0.5 (alpha 0.25):
    // D V = 1 / (4 pi 0.0625) = 1.273240.
    let f = coated(grey, 1.0, 0.5).reflected(n, n, n).x;
    let want = 0.49 / PI * 0.96 + 0.04 * 1.273_24;
    println!("coated grey at normal incidence: {f} against {want}");
    assert!((f - want).abs() < 1e-5 * want, "{f} against {want}");
    // Half a coat blends half as much; none leaves the base exactly.
    let f = coated(grey, 0.5, 0.5).reflected(n, n, n).x;
    let want = 0.49 / PI * 0.98 + 0.02 * 1.273_24;
    assert!((f - want).abs() < 1e-5 * want, "{f} against {want}");
    let l = Vec3::new(0.6, 0.0, 0.8);
    let v = Vec3::new(-0.3, 0.4, 0.866).normalize();
    assert_eq!(
        coated(grey, 0.0, 0.2).reflected(n, l, v),
        grey.evaluate(n, l, v) * n.dot(l)
    );
    // At 80 degrees from the normal the coat takes Fc = 0.04 + 0.96 (1 - cos 80)^5 = 0.409910
    // of the light from the base.
    let mu = 80f32.to_radians().cos();
    assert!((coated(grey, 1.0, 0.5).clearcoat.blend(mu) - 0.409_910).abs() < 1e-5);
}

/// Draws estimate the albedo the quadrature finds, and each carries the density `pdf` gives
/// its direction.
#[test]
fn draws_estimate_the_albedo_and_carry_their_density() {
    for (weight, roughness, metallic) in [(1.0, 0.1, 0.0), (1.0, 0.6, 0.0), (0.5, 0.3, 1.0)] {
        let s = coated(
            base(Vec3::new(0.9, 0.6, 0.3), metallic, 0.5, 1.0),
            weight,
            roughness,
        );
        for mu in [0.3f32, 0.8, 1.0] {
            let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let what = format!(
                "clearcoat {weight} at roughness {roughness} over metallic {metallic}, n.v {mu}"
            );
            assert_draws_estimate(&s, v, albedo(&s, mu), &what);
        }
    }
}

/// The white furnace of a coat over white Lambert (albedo 1): what it loses is the light its
/// GGX lobe loses (no multiple scattering between microfacets), weighed by its Fresnel, so a
/// smooth coat keeps nearly everything and a rough one loses most at grazing views. The
/// bounds are docs/materials.md's.
#[test]
fn a_coat_over_white_loses_what_its_lobe_loses() {
    let white = base(Vec3::ONE, 0.0, 1.0, 0.0);
    // (coat roughness, n.v, most lost)
    let cases = [
        (0.1, 1.0, 0.001),
        (0.1, 0.5, 0.001),
        (0.1, 0.2, 0.002),
        (0.5, 1.0, 0.005),
        (0.5, 0.5, 0.012),
        (0.5, 0.2, 0.06),
        (1.0, 1.0, 0.03),
        (1.0, 0.5, 0.045),
        (1.0, 0.2, 0.15),
    ];
    for (roughness, mu, most) in cases {
        let a = albedo(&coated(white, 1.0, roughness), mu).x;
        println!(
            "coat roughness {roughness}, n.v {mu}: albedo {a:.5}, lost {:.5}",
            1.0 - a
        );
        assert!(
            a <= 1.0 + 1e-3,
            "roughness {roughness}, n.v {mu}: reflects {a}"
        );
        assert!(
            1.0 - a <= most,
            "roughness {roughness}, n.v {mu}: loses {}",
            1.0 - a
        );
    }
}

/// A coat whose normal is tilted by `degrees` about +y from the base's +Z (towards -x for
/// negative angles), over `base`.
fn tilted(base: MetallicRoughness, roughness: f32, degrees: f32) -> LayeredBrdf {
    let (sin, cos) = degrees.to_radians().sin_cos();
    let mut s = coated(base, 1.0, roughness);
    s.clearcoat.normal = Vec3::new(sin, 0.0, cos);
    s
}

/// The coat reflects about its own normal nc and the base about its own n, each at its own
/// cosine: f cos = f_base |n.l| (1 - Fc(nc.v)) + Fc(nc.v) D(nc.h) V(nc.l, nc.v) nc.l, with
/// GGX's D and the height-correlated V written out here. Light below the base's normal but
/// above the coat's is the coat's alone; below a transmitting base it is transmitted light,
/// which the coat does not reflect.
#[test]
fn each_layer_reflects_about_its_own_normal() {
    let grey = base(Vec3::splat(0.5), 0.0, 1.0, 1.0);
    let (roughness, degrees) = (0.4f32, -20.0f32);
    let s = tilted(grey, roughness, degrees);
    let nc = s.clearcoat.normal;
    let n = Vec3::Z;
    let a2 = roughness.powi(4);
    let d = |c: f32| a2 / (PI * (c * c * (a2 - 1.0) + 1.0).powi(2));
    let v_term = |nl: f32, nv: f32| {
        0.5 / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt())
    };
    let fresnel = |c: f32| 0.04 + 0.96 * (1.0 - c).powi(5);
    let v = Vec3::new(0.8, 0.0, 0.6);
    for l in [
        Vec3::new(-0.5, 0.1, 0.86).normalize(),
        Vec3::new(-0.9, 0.0, 0.3).normalize(),
        Vec3::new(-0.98, 0.0, -0.1).normalize(),
    ] {
        let h = (l + v).normalize();
        let (nl, nv) = (nc.dot(l), nc.dot(v));
        let coat = fresnel(nv) * d(nc.dot(h)) * v_term(nl, nv) * nl;
        let beneath = grey.evaluate(n, l, v) * n.dot(l).max(0.0) * (1.0 - fresnel(nv));
        let want = beneath.x + coat;
        let got = s.reflected(n, l, v).x;
        println!("l {l}: {got} against {want} (coat {coat})");
        assert!(
            (got - want).abs() <= 1e-5 * want.max(1e-3),
            "l {l}: {got} against {want}"
        );
        assert!(s.coat_reflects(n, l), "{l}");
    }
    let mut glass = s;
    glass.base.dielectric = crate::reference::brdf::Dielectric {
        ior: 1.5,
        transmission: 1.0,
        eta: 1.5,
    };
    let below = Vec3::new(-0.98, 0.0, -0.1).normalize();
    assert!(!glass.coat_reflects(n, below));
}

/// A coat tilted from the base, both ways, over an opaque and a metallic base: draws estimate
/// the albedo the quadrature finds (coat light below the base's normal included), and a coat
/// over white Lambert reflects no more than it receives.
#[test]
fn draws_of_a_tilted_coat_estimate_its_albedo() {
    for (degrees, metallic) in [(-20.0, 0.0), (15.0, 1.0)] {
        for mu in [0.5f32, 0.9] {
            let s = tilted(
                base(Vec3::new(0.9, 0.6, 0.3), metallic, 0.5, 1.0),
                0.3,
                degrees,
            );
            let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let what = format!("coat tilted {degrees} degrees over metallic {metallic}, n.v {mu}");
            assert_draws_estimate(&s, v, albedo(&s, mu), &what);
            let white = tilted(base(Vec3::ONE, 0.0, 1.0, 0.0), 0.3, degrees);
            let a = albedo(&white, mu).x;
            println!("white under a coat tilted {degrees} degrees, n.v {mu}: albedo {a:.5}");
            assert!(a <= 1.0 + 1e-3, "{degrees} degrees, n.v {mu}: reflects {a}");
        }
    }
}
