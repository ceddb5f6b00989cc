//! The emissive triangles of a scene as lights: the distribution that draws one by its power,
//! the luminance of its material's emissive factor times its area. An emissive texture is not
//! counted in the power (a triangle with a dark texture is drawn as often as a bright one); the
//! shading reads the textured emission where the drawn point lands, so the estimate stays
//! unbiased wherever the factor is not zero. The CPU reference draws from it
//! (`reference::emitters`) and the GPU reads the same arrays (shaders/include/emitters.glsl).

use glam::{Vec2, Vec3};

use super::environment::luminance;

/// The emissive triangles, by index in the renderers' triangle order, and the distribution that
/// draws them by power.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EmitterDistribution {
    /// The emissive triangles, in the renderers' triangle order.
    pub triangles: Vec<u32>,
    /// `cdf[i]`: the share of the power of `triangles[..=i]`; the last is 1.
    pub cdf: Vec<f32>,
    /// Per triangle: the density per unit area of a drawn point on it (its share of the power
    /// over its area); 0 where it does not emit; empty when no triangle emits.
    pub area_pdf: Vec<f32>,
}

/// The area of a triangle and its front face's unit normal (counter-clockwise).
pub fn area_normal(v: &[Vec3; 3]) -> (f32, Vec3) {
    let cross = (v[1] - v[0]).cross(v[2] - v[0]);
    let length = cross.length();
    (0.5 * length, cross / length.max(f32::MIN_POSITIVE))
}

/// The index of the first `cdf` entry above `u` (the triangle `u` draws), and `u` rescaled to
/// [0, 1) within that entry's share.
fn pick(cdf: &[f32], u: f32) -> (usize, f32) {
    let i = cdf.partition_point(|&c| c <= u).min(cdf.len() - 1);
    let low = if i == 0 { 0.0 } else { cdf[i - 1] };
    let width = cdf[i] - low;
    let rescaled = if width > 0.0 { (u - low) / width } else { 0.0 };
    (i, rescaled.clamp(0.0, 1.0 - f32::EPSILON))
}

/// A point uniform on a triangle from a point of [0, 1)^2: barycentrics (b1, b2).
pub fn uniform_barycentric(u: Vec2) -> Vec2 {
    let s = u.x.sqrt();
    Vec2::new(1.0 - s, u.y * s)
}

/// The point `u` draws uniformly on triangle `v`: its barycentrics (b1, b2) and position.
pub fn uniform_point(v: &[Vec3; 3], u: Vec2) -> (Vec2, Vec3) {
    let b = uniform_barycentric(u);
    (b, (1.0 - b.x - b.y) * v[0] + b.x * v[1] + b.y * v[2])
}

impl EmitterDistribution {
    /// The distribution over `triangles` (vertices), each emitting its material's emissive
    /// factor `emission(index)`.
    pub fn new(triangles: &[[Vec3; 3]], emission: impl Fn(usize) -> Vec3) -> Self {
        let mut emitters = Vec::new();
        let mut powers = Vec::new();
        for (t, v) in triangles.iter().enumerate() {
            let power = luminance(emission(t)) * area_normal(v).0;
            if power > 0.0 && power.is_finite() {
                emitters.push(t as u32);
                powers.push(power);
            }
        }
        let total: f32 = powers.iter().sum();
        let mut area_pdf = vec![
            0.0;
            if emitters.is_empty() {
                0
            } else {
                triangles.len()
            }
        ];
        let mut cdf = Vec::with_capacity(powers.len());
        let mut sum = 0.0;
        for (&t, &power) in emitters.iter().zip(&powers) {
            sum += power;
            cdf.push(sum / total);
            area_pdf[t as usize] = power / total / area_normal(&triangles[t as usize]).0;
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Self {
            triangles: emitters,
            cdf,
            area_pdf,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The triangle `u.x` draws and `u` with its x rescaled for the point on it.
    pub fn pick(&self, u: Vec2) -> (u32, Vec2) {
        let (i, x) = pick(&self.cdf, u.x);
        (self.triangles[i], Vec2::new(x, u.y))
    }

    /// The density per solid angle, seen from a point at `distance` along unit direction `d`,
    /// of drawing the point of `triangle` (front normal `normal`) the direction meets.
    pub fn pdf(&self, triangle: u32, normal: Vec3, d: Vec3, distance: f32) -> f32 {
        let area_pdf = self.area_pdf.get(triangle as usize).copied().unwrap_or(0.0);
        let cosine = normal.dot(d).abs();
        if area_pdf == 0.0 || cosine == 0.0 {
            return 0.0;
        }
        area_pdf * distance * distance / cosine
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_is_luminance_times_area() {
        let small = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let large = small.map(|v| 2.0 * v);
        let dark = small.map(|v| v + Vec3::Z);
        let emission = [Vec3::ONE, Vec3::ONE, Vec3::ZERO];
        let d = EmitterDistribution::new(&[small, large, dark], |t| emission[t]);
        assert_eq!(d.triangles, [0, 1]);
        // Areas 0.5 and 2: a fifth and four fifths of the power.
        assert!(
            (d.cdf[0] - 0.2).abs() < 1e-6 && d.cdf[1] == 1.0,
            "{:?}",
            d.cdf
        );
        // Each triangle's share over its area: 0.2 / 0.5 and 0.8 / 2.
        assert!((d.area_pdf[0] - 0.4).abs() < 1e-6 && (d.area_pdf[1] - 0.4).abs() < 1e-6);
        assert_eq!(d.area_pdf[2], 0.0);
        // Seen at distance 2 along the normal: 0.4 * 4 / 1.
        assert!((d.pdf(0, Vec3::Z, -Vec3::Z, 2.0) - 1.6).abs() < 1e-6);
        assert!(EmitterDistribution::new(&[dark], |_| Vec3::ZERO).is_empty());
    }

    #[test]
    fn pick_follows_the_cdf_and_rescales() {
        let cdf = [0.25, 0.25, 1.0];
        assert_eq!(pick(&cdf, 0.0), (0, 0.0));
        assert_eq!(pick(&cdf, 0.125), (0, 0.5));
        // The empty middle entry is never drawn.
        assert_eq!(pick(&cdf, 0.25), (2, 0.0));
        assert_eq!(pick(&cdf, 0.625), (2, 0.5));
        assert!(pick(&cdf, 0.999_999_9).0 == 2);
    }

    #[test]
    fn uniform_barycentrics_cover_the_triangle_evenly() {
        // The mean of a uniform point is the centroid (1/3, 1/3).
        let n = 64;
        let mut mean = Vec2::ZERO;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let b = uniform_barycentric(u);
                assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0);
                mean += b;
            }
        }
        mean /= (n * n) as f32;
        assert!(
            (mean - Vec2::splat(1.0 / 3.0)).abs().max_element() < 1e-3,
            "{mean}"
        );
    }
}
