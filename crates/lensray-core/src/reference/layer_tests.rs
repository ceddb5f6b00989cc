//! What the layered BRDF's tests (clearcoat_tests.rs, sheen_tests.rs) share: an opaque base,
//! and the check that
//! its draws estimate the albedo a quadrature of f cos finds, each draw carrying the density
//! `pdf` gives its direction.

use glam::{DVec3, Vec3};

use super::brdf::{Dielectric, MetallicRoughness};
use super::clearcoat::LayeredBrdf;

/// An opaque base of colour `colour`.
pub(super) fn base(
    colour: Vec3,
    metallic: f32,
    roughness: f32,
    specular: f32,
) -> MetallicRoughness {
    MetallicRoughness {
        base_colour: colour,
        metallic,
        roughness,
        specular,
        dielectric: Dielectric::OPAQUE,
    }
}

/// The golden ratio's fraction: the step of a rank-1 lattice that spreads a third coordinate
/// evenly over a grid's points.
const GOLDEN: f64 = 0.618_033_988_749_895;

/// Asserts that the mean weight of 512^2 stratified draws of `s` at normal +Z seen from `v`
/// is within 0.5 % of `quadrature` per channel, and that each draw carries the density `pdf`
/// gives its direction; prints both after `what`.
pub(super) fn assert_draws_estimate(s: &LayeredBrdf, v: Vec3, quadrature: DVec3, what: &str) {
    let (n, steps) = (Vec3::Z, 512);
    let mut drawn = DVec3::ZERO;
    for k in 0..steps * steps {
        // The third coordinate (a glass base's choice) on a rank-1 lattice across the grid.
        let u = Vec3::new(
            ((k / steps) as f32 + 0.5) / steps as f32,
            ((k % steps) as f32 + 0.5) / steps as f32,
            (k as f64 * GOLDEN).fract() as f32,
        );
        if let Some(d) = s.sample(n, v, u) {
            let pdf = s.pdf(n, d.direction, v);
            assert!((pdf - d.pdf).abs() <= 1e-5 * pdf, "{pdf} against {}", d.pdf);
            drawn += d.weight.as_dvec3();
        }
    }
    let drawn = drawn / (steps * steps) as f64;
    let error = ((drawn - quadrature).abs() / quadrature).max_element();
    println!("{what}: drawn {drawn:.4}, quadrature {quadrature:.4}, relative error {error:.2e}");
    assert!(error < 5e-3, "{what}: {drawn} against {quadrature}");
}
