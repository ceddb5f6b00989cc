//! Bladed irises: the shape as a fan of equal-area triangles around the lens centre, and the
//! area-preserving map of the square onto it (see the parent module's "Sampling").

use glam::{DVec2, Vec2};

use super::MAX_FAN;

/// Uniform [0, 1)^2 -> uniform over the fan `fan` (equal-area triangles around the origin):
/// concentric ring r in [0, 1], fraction `a` of the way around it, then the point at `a` of
/// the fan's outer boundary (triangle floor(a n), a linear position on its outer edge) scaled
/// by r. Scaled copies of the fan have area proportional to r^2, as the square's rings do, and
/// each triangle holds 1/n of every ring: the map preserves area.
pub fn sample_fan(fan: &[Vec2], u: Vec2) -> Vec2 {
    let offset = 2.0 * u - Vec2::ONE;
    if offset.x == 0.0 && offset.y == 0.0 {
        return Vec2::ZERO;
    }
    // The concentric map's ring and angle (in turns: its theta / 2 pi).
    let (mut r, mut a) = if offset.x.abs() > offset.y.abs() {
        (offset.x, 0.125 * (offset.y / offset.x))
    } else {
        (offset.y, 0.25 - 0.125 * (offset.x / offset.y))
    };
    if r < 0.0 {
        r = -r;
        a += 0.5;
    }
    if a < 0.0 {
        a += 1.0;
    }
    let n = fan.len() as u32;
    let s = a * n as f32;
    let i = (s as u32).min(n - 1);
    let t = s - i as f32;
    let (p0, p1) = (fan[i as usize], fan[((i + 1) % n) as usize]);
    r * (p0 + t * (p1 - p0))
}

/// The fan of an iris of `blades` blades of roundness `roundness`, vertex 0 at angle
/// `rotation` (radians): per blade, the blade's first vertex and points on its arc chosen so
/// that every triangle of the fan has the same area.
pub(super) fn blade_fan(blades: u32, rotation: f64, roundness: f64) -> Vec<DVec2> {
    let per_blade = if roundness > 0.0 {
        MAX_FAN / blades as usize
    } else {
        1
    };
    let half = std::f64::consts::PI / f64::from(blades);
    let mut fan = Vec::with_capacity(per_blade * blades as usize);
    // One blade along +x (vertices at -half and +half), then turned into place.
    let arc = BladeArc::new(half, roundness);
    let steps = arc.equal_area_steps(per_blade);
    for k in 0..blades {
        let turn = rotation + half + 2.0 * half * f64::from(k);
        let (sin, cos) = turn.sin_cos();
        for &p in &steps {
            fan.push(DVec2::new(cos * p.x - sin * p.y, sin * p.x + cos * p.y));
        }
    }
    fan
}

/// One blade's arc through (cos half, -+sin half): a circle of radius `radius` centred on the
/// x axis at `centre_x`, from angle -`span` to +`span` about that centre; straight (no arc)
/// when `radius` is infinite.
struct BladeArc {
    half: f64,
    centre_x: f64,
    radius: f64,
    span: f64,
}

impl BladeArc {
    fn new(half: f64, roundness: f64) -> Self {
        let (chord_half, chord_x) = (half.sin(), half.cos());
        let sagitta = roundness * (1.0 - chord_x);
        if sagitta <= 0.0 {
            return BladeArc {
                half,
                centre_x: 0.0,
                radius: f64::INFINITY,
                span: 0.0,
            };
        }
        let radius = (chord_half * chord_half + sagitta * sagitta) / (2.0 * sagitta);
        BladeArc {
            half,
            centre_x: chord_x + sagitta - radius,
            radius,
            span: (chord_half / radius).asin(),
        }
    }

    /// The point at parameter `t` in [0, 1] from the first vertex to the second.
    fn point(&self, t: f64) -> DVec2 {
        if self.radius.is_infinite() {
            let y = (2.0 * t - 1.0) * self.half.sin();
            return DVec2::new(self.half.cos(), y);
        }
        let angle = (2.0 * t - 1.0) * self.span;
        DVec2::new(
            self.centre_x + self.radius * angle.cos(),
            self.radius * angle.sin(),
        )
    }

    /// `n` points from the first vertex (included) towards the second (excluded) such that
    /// the n triangles (origin, point i, point i + 1), the last ending at the second vertex,
    /// have equal areas: the area per triangle is found by bisection so that the n-th step
    /// lands on the second vertex.
    fn equal_area_steps(&self, n: usize) -> Vec<DVec2> {
        let area = |a: DVec2, b: DVec2| 0.5 * a.perp_dot(b);
        // The parameter after `from` whose triangle has `target` area (area grows with it).
        let step = |from: f64, target: f64| -> f64 {
            let (mut lo, mut hi) = (from, 1.0 + 1.0);
            let a = self.point(from);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if area(a, self.point(mid.min(1.0))) + (mid - 1.0).max(0.0) < target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        };
        let whole = area(self.point(0.0), self.point(1.0));
        let (mut lo, mut hi) = (0.0, whole);
        for _ in 0..100 {
            let target = 0.5 * (lo + hi);
            let mut t = 0.0;
            for _ in 0..n {
                t = step(t, target);
            }
            if t < 1.0 {
                lo = target;
            } else {
                hi = target;
            }
        }
        let target = 0.5 * (lo + hi);
        let mut t = 0.0;
        let mut points = Vec::with_capacity(n);
        for _ in 0..n {
            points.push(self.point(t));
            t = step(t, target).min(1.0);
        }
        points
    }
}
