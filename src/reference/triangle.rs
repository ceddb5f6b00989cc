//! Watertight ray-triangle intersection (Woop, Benthin and Wald, JCGT 2013): no ray slips through
//! the shared edge of two triangles, which matters for the pixel-exact CPU/GPU comparison.

use glam::{Vec2, Vec3, Vec3A};

/// The per-ray part of the test, computed once per ray: axis permutation and shear that turn the
/// ray into the +z axis.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3A,
    kx: usize,
    ky: usize,
    kz: usize,
    shear: Vec3,
}

impl WatertightRay {
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        let abs = direction.abs();
        let kz = if abs.x > abs.y {
            if abs.x > abs.z {
                0
            } else {
                2
            }
        } else if abs.y > abs.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Keep the winding of the projected triangle independent of the ray's direction sign.
        if direction[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Self {
            origin: origin.into(),
            kx,
            ky,
            kz,
            shear: Vec3::new(
                direction[kx] / direction[kz],
                direction[ky] / direction[kz],
                1.0 / direction[kz],
            ),
        }
    }

    /// Distance and barycentrics (weights of v1 and v2) of a hit with t in (t_min, t_max);
    /// both faces count.
    #[inline]
    pub fn intersect(&self, v: &[Vec3A; 3], t_min: f32, t_max: f32) -> Option<(f32, Vec2)> {
        let a = v[0] - self.origin;
        let b = v[1] - self.origin;
        let c = v[2] - self.origin;
        let (kx, ky, kz, s) = (self.kx, self.ky, self.kz, self.shear);
        let ax = a[kx] - s.x * a[kz];
        let ay = a[ky] - s.y * a[kz];
        let bx = b[kx] - s.x * b[kz];
        let by = b[ky] - s.y * b[kz];
        let cx = c[kx] - s.x * c[kz];
        let cy = c[ky] - s.y * c[kz];
        let mut u = cx * by - cy * bx;
        let mut v_ = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        // On an edge in single precision: redo the edge functions in double, as the paper does.
        if u == 0.0 || v_ == 0.0 || w == 0.0 {
            let (ax, ay, bx, by, cx, cy) = (
                ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64,
            );
            u = (cx * by - cy * bx) as f32;
            v_ = (ax * cy - ay * cx) as f32;
            w = (bx * ay - by * ax) as f32;
        }
        if (u < 0.0 || v_ < 0.0 || w < 0.0) && (u > 0.0 || v_ > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v_ + w;
        if det == 0.0 {
            return None;
        }
        let t_scaled = u * (s.z * a[kz]) + v_ * (s.z * b[kz]) + w * (s.z * c[kz]);
        let t = t_scaled / det;
        if !(t > t_min && t < t_max) {
            return None;
        }
        Some((t, Vec2::new(v_ / det, w / det)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3a;

    fn tri() -> [Vec3A; 3] {
        [
            vec3a(0.0, 0.0, 0.0),
            vec3a(1.0, 0.0, 0.0),
            vec3a(0.0, 1.0, 0.0),
        ]
    }

    #[test]
    fn hits_inside_with_barycentrics() {
        let ray = WatertightRay::new(Vec3::new(0.25, 0.5, -2.0), Vec3::Z);
        let (t, b) = ray.intersect(&tri(), 0.0, f32::INFINITY).expect("hit");
        assert!((t - 2.0).abs() < 1e-6, "t = {t}");
        assert!(
            (b - Vec2::new(0.25, 0.5)).length() < 1e-6,
            "barycentrics {b}"
        );
    }

    #[test]
    fn both_faces_and_range() {
        let ray = WatertightRay::new(Vec3::new(0.25, 0.25, 2.0), -Vec3::Z);
        assert!(ray.intersect(&tri(), 0.0, f32::INFINITY).is_some());
        assert!(ray.intersect(&tri(), 0.0, 1.5).is_none(), "t_max respected");
        let away = WatertightRay::new(Vec3::new(0.25, 0.25, 2.0), Vec3::Z);
        assert!(away.intersect(&tri(), 0.0, f32::INFINITY).is_none());
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of a unit square: every ray through the diagonal hits
        // at least one of them.
        let t0 = [
            vec3a(0.0, 0.0, 0.0),
            vec3a(1.0, 0.0, 0.0),
            vec3a(1.0, 1.0, 0.0),
        ];
        let t1 = [
            vec3a(0.0, 0.0, 0.0),
            vec3a(1.0, 1.0, 0.0),
            vec3a(0.0, 1.0, 0.0),
        ];
        let mut misses = 0;
        for i in 0..10_000 {
            let x = i as f32 / 10_000.0;
            let ray = WatertightRay::new(Vec3::new(x, x, -1.0), Vec3::new(0.001, -0.0007, 1.0));
            let hit = ray.intersect(&t0, 0.0, f32::INFINITY).is_some()
                || ray.intersect(&t1, 0.0, f32::INFINITY).is_some();
            let inside = {
                let p = Vec3::new(x, x, -1.0) + Vec3::new(0.001, -0.0007, 1.0);
                (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y)
            };
            if inside && !hit {
                misses += 1;
            }
        }
        assert_eq!(misses, 0, "rays slipped through the shared edge");
    }
}
