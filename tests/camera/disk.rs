//! 7. The concentric square -> disk map.

use glam::Vec2;
use lensray::camera::thin_lens::concentric_sample_disk;

use crate::common::*;

/// Every output lies in the closed unit disk (a dense grid including the square's boundary).
#[test]
fn concentric_map_stays_in_unit_disk() {
    let n = 400;
    let mut worst = (0.0f32, Vec2::ZERO);
    for a in 0..=n {
        for b in 0..=n {
            let u = Vec2::new(a as f32 / n as f32, b as f32 / n as f32);
            let p = concentric_sample_disk(u);
            assert!(p.is_finite(), "concentric_sample_disk({u:?}) = {p:?}");
            if p.length() > worst.0 {
                worst = (p.length(), u);
            }
        }
    }
    assert!(
        worst.0 <= 1.0 + 1e-6,
        "concentric_sample_disk({:?}) has radius {} > 1 by {:.3e}",
        worst.1,
        worst.0,
        worst.0 - 1.0
    );
    assert_eq!(concentric_sample_disk(Vec2::splat(0.5)), Vec2::ZERO, "centre");
}

/// Uniform density: with 10^5 stratified samples, the fraction inside radius r is r^2 (0.25 for
/// r = 0.5) within 0.005, and each of 8 equal sectors holds 1/8.
#[test]
fn concentric_map_preserves_area() {
    let (nx, ny) = (400usize, 250usize); // 10^5 strata
    let mut rng = Rng::new(40);
    let radii = [0.3f32, 0.5, 0.7, 0.9];
    let mut inside = [0usize; 4];
    let mut sectors = [0usize; 8];
    for a in 0..nx {
        for b in 0..ny {
            // Jittered (stratified) sample of stratum (a, b).
            let u = Vec2::new(
                (a as f32 + rng.f32()) / nx as f32,
                (b as f32 + rng.f32()) / ny as f32,
            );
            let p = concentric_sample_disk(u);
            let r = p.length();
            for (k, &limit) in radii.iter().enumerate() {
                if r < limit {
                    inside[k] += 1;
                }
            }
            let angle = p.y.atan2(p.x).rem_euclid(std::f32::consts::TAU);
            let sector = ((angle / std::f32::consts::TAU * 8.0) as usize).min(7);
            sectors[sector] += 1;
        }
    }
    let total = (nx * ny) as f64;
    for (k, &limit) in radii.iter().enumerate() {
        let fraction = inside[k] as f64 / total;
        let expected = (limit as f64).powi(2);
        assert_close(
            &format!("fraction of stratified samples within radius {limit}"),
            fraction,
            expected,
            0.005,
        );
    }
    for (s, &count) in sectors.iter().enumerate() {
        assert_close(
            &format!("fraction of samples in angular sector {s} of 8"),
            count as f64 / total,
            0.125,
            0.005,
        );
    }
}

/// The square's boundary maps onto the unit circle, covering it without gaps.
#[test]
fn concentric_map_sends_square_boundary_to_circle() {
    let n = 1000;
    let mut angles = Vec::new();
    for k in 0..n {
        let t = k as f32 / n as f32;
        for u in [
            Vec2::new(t, 0.0),
            Vec2::new(1.0, t),
            Vec2::new(1.0 - t, 1.0),
            Vec2::new(0.0, 1.0 - t),
        ] {
            let p = concentric_sample_disk(u);
            assert_close(
                &format!("radius of concentric_sample_disk({u:?}) = {p:?}"),
                p.length() as f64,
                1.0,
                1e-6,
            );
            angles.push((p.y as f64).atan2(p.x as f64));
        }
    }
    angles.sort_by(f64::total_cmp);
    let mut largest_gap = angles[0] + std::f64::consts::TAU - angles[angles.len() - 1];
    for pair in angles.windows(2) {
        largest_gap = largest_gap.max(pair[1] - pair[0]);
    }
    // 4000 boundary points: an even cover leaves gaps of about 2 pi / 4000 = 1.6e-3.
    assert!(
        largest_gap < 4e-3,
        "the boundary's image leaves an angular gap of {largest_gap} rad on the circle"
    );
}
