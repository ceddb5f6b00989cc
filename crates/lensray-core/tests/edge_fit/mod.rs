//! The analytic image of a straight edge seen through a thin lens, and its least-squares fit.
//!
//! A plane parallel to the film, off the focal plane, is blurred by a uniform disk of radius R
//! pixels (the circle of confusion) centred on the pinhole projection: a film point at screen
//! position s sees s + l (1/z - 1/F) for lens points l uniform on the aperture disk. A vertical
//! dark-to-bright step at raster x = e therefore becomes, at signed distance d = x - e, the
//! fraction of the disk on the bright side ([`disk_step`]), and a pixel, whose film samples are
//! uniform over its width, shows that averaged over the pixel ([`pixel_value`]).
#![allow(
    dead_code,
    reason = "the reference tests and the app's autofocus test each use part of it"
)]

use std::f64::consts::PI;

/// The disk-blurred unit step at signed distance `d` from the edge, disk radius `r`:
/// 0 for d <= -r, 1 for d >= r, else 1/2 + (d sqrt(r^2 - d^2) + r^2 asin(d / r)) / (pi r^2).
pub fn disk_step(d: f64, r: f64) -> f64 {
    if d <= -r {
        0.0
    } else if d >= r {
        1.0
    } else {
        0.5 + (d * (r * r - d * d).sqrt() + r * r * (d / r).asin()) / (PI * r * r)
    }
}

/// The integral of [`disk_step`] from -infinity to `d`: 0 for d <= -r, d for d >= r, else
/// d / 2 + (r^2 (d asin(d / r) + sqrt(r^2 - d^2)) - (r^2 - d^2)^(3/2) / 3) / (pi r^2).
fn disk_step_integral(d: f64, r: f64) -> f64 {
    if d <= -r {
        0.0
    } else if d >= r {
        d
    } else {
        let q = (r * r - d * d).max(0.0);
        let u = (d / r).clamp(-1.0, 1.0);
        0.5 * d + (r * r * (d * u.asin() + q.sqrt()) - q * q.sqrt() / 3.0) / (PI * r * r)
    }
}

/// The value of pixel column `column` (covering raster x in [column, column + 1)) for an edge
/// at raster x = `edge` blurred by a disk of radius `r`: [`disk_step`] box-filtered over the pixel.
pub fn pixel_value(column: usize, edge: f64, r: f64) -> f64 {
    let x = column as f64 - edge;
    disk_step_integral(x + 1.0, r) - disk_step_integral(x, r)
}

#[derive(Clone, Copy, Debug)]
pub struct EdgeFit {
    /// Raster x of the edge.
    pub edge: f64,
    /// Radius of the blur disk, pixels.
    pub radius: f64,
    /// Root-mean-square difference between the profile and the fitted model, over the columns
    /// the blur reaches (those strictly inside (edge - radius - 1, edge + radius + 1)).
    pub rms_residual: f64,
}

fn sum_of_squares(profile: &[f64], edge: f64, r: f64) -> f64 {
    profile
        .iter()
        .enumerate()
        .map(|(c, &v)| (v - pixel_value(c, edge, r)).powi(2))
        .sum()
}

/// Minimum of a function that is unimodal on [a, b], to about 1e-9 of the interval.
fn golden_section(mut a: f64, mut b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let k = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (b - k * (b - a), a + k * (b - a));
    let (mut f1, mut f2) = (f(x1), f(x2));
    while b - a > 1e-9 * (1.0 + b.abs()) {
        if f1 < f2 {
            (b, x2, f2) = (x2, x1, f1);
            x1 = b - k * (b - a);
            f1 = f(x1);
        } else {
            (a, x1, f1) = (x1, x2, f2);
            x2 = a + k * (b - a);
            f2 = f(x2);
        }
    }
    0.5 * (a + b)
}

/// Least-squares fit of (edge, radius) to a row profile averaged over rows, normalised so the
/// dark side is 0 and the bright side (larger x) is 1. The blur must lie inside the profile.
///
/// The edge is first placed by the area under the profile (the blurred step minus the sharp one
/// is odd about the edge, so the sum of the values is `len - edge`), then for each radius the
/// edge is refined within a pixel of that; the radius is scanned in steps of 1/8 pixel and
/// refined by golden section between the neighbours of the best step.
pub fn fit(profile: &[f64]) -> EdgeFit {
    let n = profile.len() as f64;
    let area_edge = n - profile.iter().sum::<f64>();
    let best_edge = |r: f64| {
        golden_section(area_edge - 1.0, area_edge + 1.0, |e| {
            sum_of_squares(profile, e, r)
        })
    };
    let cost = |r: f64| sum_of_squares(profile, best_edge(r), r);
    let step = 0.125;
    let steps = (n / 2.0 / step) as usize;
    let best_step = (0..=steps)
        .map(|i| (i, cost(i as f64 * step)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
        .unwrap();
    let lo = (best_step as f64 - 1.0).max(0.0) * step;
    let radius = golden_section(lo, (best_step + 1) as f64 * step, cost);
    let edge = best_edge(radius);
    let reached: Vec<f64> = profile
        .iter()
        .enumerate()
        .filter(|&(c, _)| (c as f64 + 1.0 - (edge - radius)) > 0.0 && (c as f64) < edge + radius)
        .map(|(c, &v)| v - pixel_value(c, edge, radius))
        .collect();
    let rms_residual =
        (reached.iter().map(|d| d * d).sum::<f64>() / reached.len().max(1) as f64).sqrt();
    EdgeFit {
        edge,
        radius,
        rms_residual,
    }
}

/// Self-checks of the model: the closed-form pixel integral against a numerical one, and the
/// fit recovering a known profile. A radius smaller than the edge's distance to the nearest pixel
/// boundary does not change any pixel (the blur is odd about the edge and stays inside one
/// pixel), so below half a pixel only "less than half a pixel" is checked.
pub fn self_check() {
    for (edge, r) in [(10.3, 0.0), (10.3, 0.4), (10.7, 3.3), (12.0, 7.9)] {
        for c in 0..24 {
            let k = 20_000;
            let numeric = (0..k)
                .map(|i| disk_step(c as f64 + (i as f64 + 0.5) / k as f64 - edge, r))
                .sum::<f64>()
                / k as f64;
            let closed = pixel_value(c, edge, r);
            assert!(
                (numeric - closed).abs() < 1e-6,
                "pixel {c}, edge {edge}, radius {r}: closed form {closed}, numerical {numeric}"
            );
        }
    }
    for (edge, r) in [
        (31.37, 0.0),
        (31.37, 0.3),
        (31.9, 0.7),
        (32.9, 6.61),
        (30.2, 17.3),
    ] {
        let profile: Vec<f64> = (0..64).map(|c| pixel_value(c, edge, r)).collect();
        let f = fit(&profile);
        let radius_ok = if r > 0.5 {
            (f.radius - r).abs() < 1e-5
        } else {
            f.radius < 0.5
        };
        assert!(
            (f.edge - edge).abs() < 1e-6 && radius_ok && f.rms_residual < 1e-7,
            "fit of an exact profile (edge {edge}, radius {r}) gave {f:?}"
        );
    }
}
