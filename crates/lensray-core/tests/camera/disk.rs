//! 7. The concentric square -> disk map.

use glam::Vec2;
use lensray_core::camera::thin_lens::concentric_sample_disk;

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
    assert_eq!(
        concentric_sample_disk(Vec2::splat(0.5)),
        Vec2::ZERO,
        "centre"
    );
}

/// Uniform density: with 10^5 stratified samples, the fraction inside radius r is r^2 (0.25 for
/// r = 0.5) within 0.005; finer, each of 64 equal-area polar cells (4 rings of radii
/// sqrt(k / 4), 16 sectors of 22.5 degrees, so not aligned with the map's 45-degree wedges only)
/// holds 1/64, and half-planes at odd angles hold the disk-segment area.
#[test]
fn concentric_map_preserves_area() {
    let (nx, ny) = (400usize, 250usize); // 10^5 strata
    let mut rng = Rng::new(40);
    let points: Vec<Vec2> = (0..nx)
        .flat_map(|a| (0..ny).map(move |b| (a, b)))
        .map(|(a, b)| {
            // Jittered (stratified) sample of stratum (a, b).
            let u = Vec2::new(
                (a as f32 + rng.f32()) / nx as f32,
                (b as f32 + rng.f32()) / ny as f32,
            );
            concentric_sample_disk(u)
        })
        .collect();
    let total = points.len() as f64;
    let fraction = |inside: &dyn Fn(Vec2) -> bool| {
        points.iter().filter(|&&p| inside(p)).count() as f64 / total
    };

    assert_close(
        "fraction of stratified samples within radius 0.5",
        fraction(&|p| p.length() < 0.5),
        0.25,
        0.005,
    );
    for limit in [0.1f32, 0.3, 0.7, 0.9, 0.99] {
        assert_close(
            &format!("fraction of stratified samples within radius {limit}"),
            fraction(&|p| p.length() < limit),
            (limit as f64).powi(2),
            0.002,
        );
    }

    let mut cells = [[0usize; 16]; 4];
    for p in &points {
        let ring = ((p.length_squared() * 4.0) as usize).min(3);
        let angle = p.y.atan2(p.x).rem_euclid(std::f32::consts::TAU);
        let sector = ((angle / std::f32::consts::TAU * 16.0) as usize).min(15);
        cells[ring][sector] += 1;
    }
    for (ring, row) in cells.iter().enumerate() {
        for (sector, &count) in row.iter().enumerate() {
            assert_close(
                &format!(
                    "fraction of samples in polar cell ring {ring} (r^2 in [{}, {})), sector \
                     {sector} ({} to {} degrees)",
                    ring as f64 / 4.0,
                    (ring + 1) as f64 / 4.0,
                    sector as f64 * 22.5,
                    (sector + 1) as f64 * 22.5
                ),
                count as f64 / total,
                1.0 / 64.0,
                5e-4,
            );
        }
    }

    // Half-planes {p . n > a}: the disk segment's area fraction (acos a - a sqrt(1 - a^2)) / pi.
    for (degrees, a) in [
        (10.0f64, 0.3f64),
        (37.0, -0.2),
        (67.5, 0.6),
        (200.0, 0.45),
        (301.0, 0.0),
    ] {
        let n = Vec2::new(
            degrees.to_radians().cos() as f32,
            degrees.to_radians().sin() as f32,
        );
        let expected = (a.acos() - a * (1.0 - a * a).sqrt()) / std::f64::consts::PI;
        assert_close(
            &format!("fraction of samples in the half-plane p . {n:?} > {a}"),
            fraction(&|p| p.dot(n) > a as f32),
            expected,
            1e-3,
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

#[test]
fn quarter_sine_and_cosine_are_within_two_ulps() {
    use lensray_core::camera::thin_lens::sin_cos_quarter;
    let quarter = std::f64::consts::FRAC_PI_4;
    let mut worst = (0.0f64, 0.0f64);
    for i in -100_000..=100_000 {
        let x = (quarter * f64::from(i) / 100_000.0) as f32;
        let (sin, cos) = sin_cos_quarter(x);
        let (want_sin, want_cos) = f64::from(x).sin_cos();
        // An ulp of the true value (f32 spacing at its magnitude).
        let ulp = |v: f64| f64::from(f32::EPSILON) * v.abs().max(f64::from(f32::MIN_POSITIVE));
        let ulps_sin = (f64::from(sin) - want_sin).abs() / ulp(want_sin).max(1e-45);
        let ulps_cos = (f64::from(cos) - want_cos).abs() / ulp(want_cos);
        worst = (worst.0.max(ulps_sin), worst.1.max(ulps_cos));
    }
    assert!(
        worst.0 <= 2.0 && worst.1 <= 2.0,
        "sin {:.2} ulps, cos {:.2} ulps at worst",
        worst.0,
        worst.1
    );
}

#[test]
fn concentric_map_matches_the_trigonometric_definition() {
    // Shirley and Chiu's map with f64 trigonometry.
    let reference = |u: Vec2| {
        let (x, y) = (2.0 * f64::from(u.x) - 1.0, 2.0 * f64::from(u.y) - 1.0);
        if x == 0.0 && y == 0.0 {
            return (0.0, 0.0);
        }
        let quarter = std::f64::consts::FRAC_PI_4;
        let (r, theta) = if x.abs() > y.abs() {
            (x, quarter * (y / x))
        } else {
            (y, 2.0 * quarter - quarter * (x / y))
        };
        (r * theta.cos(), r * theta.sin())
    };
    let mut worst = 0.0f64;
    for i in 0..=256 {
        for j in 0..=256 {
            let u = Vec2::new(i as f32 / 256.0, j as f32 / 256.0);
            let p = concentric_sample_disk(u);
            let (x, y) = reference(u);
            worst = worst.max((f64::from(p.x) - x).abs().max((f64::from(p.y) - y).abs()));
        }
    }
    assert!(
        worst < 5e-7,
        "largest difference from the f64 map: {worst:e}"
    );
}
