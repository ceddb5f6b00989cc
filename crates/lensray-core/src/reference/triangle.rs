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
        let inv_z = 1.0 / direction[kz];
        Self {
            origin: origin.into(),
            kx,
            ky,
            kz,
            shear: Vec3::new(direction[kx] * inv_z, direction[ky] * inv_z, inv_z),
        }
    }

    /// The axis permutation (kx, ky, kz) this ray uses: one of six.
    pub fn axes(&self) -> (usize, usize, usize) {
        (self.kx, self.ky, self.kz)
    }

    /// Distance and barycentrics (weights of v1 and v2) of a hit with t in (t_min, t_max);
    /// both faces count. Dispatches on the permutation; hot loops call [`Self::intersect_axes`]
    /// with the permutation fixed at compile time instead (see `with_axes!`).
    #[inline]
    pub fn intersect(&self, v: &[Vec3A; 3], t_min: f32, t_max: f32) -> Option<(f32, Vec2)> {
        crate::with_axes!(self.axes(), |KX, KY, KZ| self
            .intersect_axes::<KX, KY, KZ>(v, t_min, t_max))
    }

    /// [`Self::intersect`] with the permutation as constants: component access compiles to plain
    /// lane reads instead of run-time indexing.
    #[inline(always)]
    pub fn intersect_axes<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        v: &[Vec3A; 3],
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec2)> {
        debug_assert_eq!((KX, KY, KZ), self.axes());
        let a = v[0] - self.origin;
        let b = v[1] - self.origin;
        let c = v[2] - self.origin;
        let s = self.shear;
        let ax = a[KX] - s.x * a[KZ];
        let ay = a[KY] - s.y * a[KZ];
        let bx = b[KX] - s.x * b[KZ];
        let by = b[KY] - s.y * b[KZ];
        let cx = c[KX] - s.x * c[KZ];
        let cy = c[KY] - s.y * c[KZ];
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
        let t_scaled = u * (s.z * a[KZ]) + v_ * (s.z * b[KZ]) + w * (s.z * c[KZ]);
        // Range test on the scaled distance, so the division happens only for hits.
        let (t_abs, det_abs) = if det < 0.0 {
            (-t_scaled, -det)
        } else {
            (t_scaled, det)
        };
        if !(t_abs > t_min * det_abs && t_abs < t_max * det_abs) {
            return None;
        }
        let inv_det = 1.0 / det;
        Some((t_scaled * inv_det, Vec2::new(v_ * inv_det, w * inv_det)))
    }
}

/// Runs `$body` with `KX, KY, KZ` bound as const generics to the permutation `$axes`
/// (one of the six a [`WatertightRay`] can pick).
#[macro_export]
macro_rules! with_axes {
    ($axes:expr, |$kx:ident, $ky:ident, $kz:ident| $body:expr) => {{
        match $axes {
            (1, 2, 0) => {
                const $kx: usize = 1;
                const $ky: usize = 2;
                const $kz: usize = 0;
                $body
            }
            (2, 1, 0) => {
                const $kx: usize = 2;
                const $ky: usize = 1;
                const $kz: usize = 0;
                $body
            }
            (2, 0, 1) => {
                const $kx: usize = 2;
                const $ky: usize = 0;
                const $kz: usize = 1;
                $body
            }
            (0, 2, 1) => {
                const $kx: usize = 0;
                const $ky: usize = 2;
                const $kz: usize = 1;
                $body
            }
            (0, 1, 2) => {
                const $kx: usize = 0;
                const $ky: usize = 1;
                const $kz: usize = 2;
                $body
            }
            _ => {
                const $kx: usize = 1;
                const $ky: usize = 0;
                const $kz: usize = 2;
                $body
            }
        }
    }};
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
                // Away from the square's outer edges, which no other triangle shares.
                (1e-4..=1.0 - 1e-4).contains(&p.x) && (1e-4..=1.0 - 1e-4).contains(&p.y)
            };
            if inside && !hit {
                misses += 1;
                eprintln!("ray at x = {x} slipped through");
            }
        }
        assert_eq!(misses, 0, "rays slipped through the shared edge");
    }
}
