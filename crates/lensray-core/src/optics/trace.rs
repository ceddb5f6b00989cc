//! Exact ray tracing through a prescription's surfaces: at each surface, the intersection
//! with its sphere (the root on the cap around the vertex) or its asphere (Newton's iteration
//! on the sag, started from the vertex sphere), the clear aperture (or the stop's opening),
//! then Snell's law in vector form with each medium's index at the ray's wavelength. A ray
//! that misses a surface, leaves a clear aperture, is totally internally reflected or whose
//! Newton iteration does not converge is blocked (`None`), never NaN.
//!
//! The wavelength enters as the dispersion offset k = lambda^-2 - lambda_d^-2
//! (`glass::dispersion_offset`): a medium's index is n_d + B k, so k = 0 traces the d line
//! exactly as a lens without dispersion.
//!
//! Newton's iteration on an asphere stops when a step is at most `NEWTON_TOLERANCE` (1e-12 in
//! f64, 1e-6 in f32) times (1 + t) mm, t the distance along the ray, after at most
//! `NEWTON_ITERATIONS` steps (else the ray is blocked).
//!
//! Lens space: z along the axis from the first vertex, + toward the film; x, y across it. The
//! same code is built twice by one macro: in f64 (`wide`, the analysis of `lensray lens`) and
//! in f32 (`narrow`, what a render traces, and what the GLSL mirrors).

use super::prescription::Prescription;

/// Which way a ray crosses the lens.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Toward {
    /// From the scene to the film (+z): the first surface first.
    Film,
    /// From the film to the scene (-z): the last surface first.
    Scene,
}

/// Most Newton steps on an asphere's sag (shared with the GLSL mirror).
pub const NEWTON_ITERATIONS: u32 = crate::interface::LENS_NEWTON_ITERATIONS;

macro_rules! tracer {
    ($real:ty, $vec:ty, $tolerance:expr) => {
        use super::{Toward, NEWTON_ITERATIONS};
        use crate::optics::prescription::Prescription;

        /// Newton's iteration on an asphere's sag stops at a step this small, times (1 + t).
        pub const NEWTON_TOLERANCE: $real = $tolerance;

        /// A ray in lens space (mm); `direction` is a unit vector.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct LensRay {
            pub origin: $vec,
            pub direction: $vec,
        }

        /// One surface as the tracer reads it.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct Interface {
            /// The vertex's z.
            pub z: $real,
            /// 0: flat (the stop).
            pub radius: $real,
            /// Half the clear aperture (the stop's opening).
            pub aperture_radius: $real,
            /// Indices before (scene side) and after (film side), at the d line.
            pub index_before: $real,
            pub index_after: $real,
            /// Cauchy's B of the media before and after (µm^2): the index at dispersion
            /// offset k is n + B k (`glass.rs`).
            pub dispersion_before: $real,
            pub dispersion_after: $real,
            /// Whether the surface is an asphere, its conic constant and a2..a16.
            pub asphere: bool,
            pub conic: $real,
            pub coefficients: [$real; 8],
        }

        /// The surfaces of a prescription, ready to trace.
        #[derive(Clone, Debug, PartialEq)]
        pub struct Elements {
            pub interfaces: Vec<Interface>,
        }

        impl Elements {
            pub fn new(lens: &Prescription) -> Self {
                let vertices = lens.vertices();
                let interfaces = lens
                    .surfaces()
                    .iter()
                    .enumerate()
                    .map(|(i, s)| {
                        let asphere = s.asphere.unwrap_or_default();
                        Interface {
                            z: vertices[i] as $real,
                            radius: s.radius as $real,
                            aperture_radius: (0.5 * s.diameter) as $real,
                            index_before: lens.index_before(i) as $real,
                            index_after: s.index as $real,
                            dispersion_before: lens.glass_before(i).cauchy_b() as $real,
                            dispersion_after: s.glass().cauchy_b() as $real,
                            asphere: s.asphere.is_some(),
                            conic: asphere.conic as $real,
                            coefficients: asphere.coefficients.map(|a| a as $real),
                        }
                    })
                    .collect();
                Elements { interfaces }
            }

            /// `ray` through every surface in the order `toward` meets them, at the d line;
            /// `None` when it is blocked.
            pub fn trace(&self, ray: LensRay, toward: Toward) -> Option<LensRay> {
                self.trace_at(ray, toward, 0.0)
            }

            /// [`Self::trace`] at dispersion offset `k` (`glass::dispersion_offset`).
            pub fn trace_at(&self, ray: LensRay, toward: Toward, k: $real) -> Option<LensRay> {
                let mut ray = ray;
                let n = self.interfaces.len();
                for j in 0..n {
                    let i = match toward {
                        Toward::Film => j,
                        Toward::Scene => n - 1 - j,
                    };
                    ray = self.interfaces[i].pass_at(ray, toward, k)?;
                }
                Some(ray)
            }

            /// A ghost's path at dispersion offset `k`: `ray` (from the scene) reflected by
            /// surface `j`, back to surface `i` (`i < j`), reflected again, and on through
            /// every surface after `i` to the film; `None` where it is blocked on the way
            /// (the stop's opening and the clear apertures clip it) or `(i, j)` is no pair of
            /// refracting surfaces (the stop reflects nothing).
            pub fn trace_ghost_at(
                &self,
                ray: LensRay,
                (i, j): (usize, usize),
                k: $real,
            ) -> Option<LensRay> {
                let n = self.interfaces.len();
                if !(i < j && j < n) {
                    return None;
                }
                let mut ray = ray;
                for s in 0..j {
                    ray = self.interfaces[s].pass_at(ray, Toward::Film, k)?;
                }
                ray = self.interfaces[j].reflect(ray)?;
                for s in (i + 1..j).rev() {
                    ray = self.interfaces[s].pass_at(ray, Toward::Scene, k)?;
                }
                ray = self.interfaces[i].reflect(ray)?;
                for s in i + 1..n {
                    ray = self.interfaces[s].pass_at(ray, Toward::Film, k)?;
                }
                Some(ray)
            }
        }

        impl Interface {
            /// The ray after this surface at the d line, or `None` if it misses it, leaves the
            /// opening or is totally internally reflected.
            #[inline]
            pub fn pass(&self, ray: LensRay, toward: Toward) -> Option<LensRay> {
                self.pass_at(ray, toward, 0.0)
            }

            /// [`Self::pass`] at dispersion offset `k`.
            #[inline]
            pub fn pass_at(&self, ray: LensRay, toward: Toward, k: $real) -> Option<LensRay> {
                let (t, normal) = self.intersect(ray)?;
                let p = ray.origin + t * ray.direction;
                if p.x * p.x + p.y * p.y > self.aperture_radius * self.aperture_radius {
                    return None;
                }
                if self.radius == 0.0 {
                    // The stop: an opening in a plane, no refraction. The ray goes on from
                    // where it was (a stop at a lens vertex would otherwise start the next
                    // intersection on that surface).
                    return Some(ray);
                }
                let before = self.index_before + self.dispersion_before * k;
                let after = self.index_after + self.dispersion_after * k;
                let (from, to) = match toward {
                    Toward::Film => (before, after),
                    Toward::Scene => (after, before),
                };
                let direction = refract(ray.direction, normal, from / to)?;
                Some(LensRay {
                    origin: p,
                    direction,
                })
            }

            /// The ray reflected where it meets this surface (the law of reflection about the
            /// normal), or `None` if it misses it, leaves the clear aperture or this is the
            /// stop, which reflects nothing.
            #[inline]
            pub fn reflect(&self, ray: LensRay) -> Option<LensRay> {
                if self.radius == 0.0 {
                    return None;
                }
                let (t, normal) = self.intersect(ray)?;
                let p = ray.origin + t * ray.direction;
                if p.x * p.x + p.y * p.y > self.aperture_radius * self.aperture_radius {
                    return None;
                }
                let d = ray.direction;
                Some(LensRay {
                    origin: p,
                    direction: d - 2.0 * d.dot(normal) * normal,
                })
            }

            /// The distance along `ray` to this surface and the unit normal there (pointing
            /// against the ray).
            #[inline]
            pub fn intersect(&self, ray: LensRay) -> Option<($real, $vec)> {
                if self.radius == 0.0 {
                    let t = (self.z - ray.origin.z) / ray.direction.z;
                    if !(t > 0.0 && t.is_finite()) {
                        return None;
                    }
                    let normal = <$vec>::new(0.0, 0.0, -ray.direction.z.signum());
                    return Some((t, normal));
                }
                if self.asphere {
                    return self.newton(ray);
                }
                self.intersect_sphere(ray)
            }

            /// The vertex sphere's root on the cap around the vertex: the one whose point
            /// lies on the vertex's side of the centre.
            #[inline]
            pub fn intersect_sphere(&self, ray: LensRay) -> Option<($real, $vec)> {
                let centre = <$vec>::new(0.0, 0.0, self.z + self.radius);
                let o = ray.origin - centre;
                let b = o.dot(ray.direction);
                let c = o.dot(o) - self.radius * self.radius;
                let discriminant = b * b - c;
                if discriminant.is_nan() || discriminant < 0.0 {
                    return None;
                }
                let root = discriminant.sqrt();
                // Vertex side: (p.z - centre.z) has the sign of -radius.
                let on_cap = |t: $real| {
                    let z = o.z + t * ray.direction.z;
                    t > 0.0 && z * -self.radius > 0.0
                };
                let (near, far) = (-b - root, -b + root);
                let t = if on_cap(near) {
                    near
                } else if on_cap(far) {
                    far
                } else {
                    return None;
                };
                let mut normal = (o + t * ray.direction) / self.radius.abs();
                if normal.dot(ray.direction) > 0.0 {
                    normal = -normal;
                }
                Some((t, normal))
            }

            /// An asphere's sag (mm, + toward the film) and its derivative with respect to
            /// r^2, at squared distance `r2` from the axis; `None` where it is undefined.
            #[inline]
            pub fn sag(&self, r2: $real) -> Option<($real, $real)> {
                let c = 1.0 / self.radius;
                let q2 = 1.0 - (1.0 + self.conic) * c * c * r2;
                if q2.is_nan() || q2 < 0.0 {
                    return None;
                }
                let q = q2.sqrt();
                // Horner in r^2: poly = a2 + a4 r^2 + ..., and its derivative.
                let (mut poly, mut slope) = (0.0, 0.0);
                for (j, a) in self.coefficients.iter().enumerate().rev() {
                    slope = slope * r2 + (j + 1) as $real * a;
                    poly = poly * r2 + a;
                }
                let sag = c * r2 / (1.0 + q) + poly * r2;
                Some((sag, c / (2.0 * q) + slope))
            }

            /// Where `ray` meets the asphere: Newton's iteration on f(t) = z(t) - z_vertex -
            /// sag(r(t)^2), from the vertex sphere's root (or the vertex plane where the
            /// sphere is missed); the normal from the sag's gradient. `None` if the sag is
            /// undefined on the way, or the iteration does not converge in front of the ray.
            #[inline]
            pub fn newton(&self, ray: LensRay) -> Option<($real, $vec)> {
                let (o, d) = (ray.origin, ray.direction);
                let mut t = match self.intersect_sphere(ray) {
                    Some((t, _)) => t,
                    None => (self.z - o.z) / d.z,
                };
                for _ in 0..NEWTON_ITERATIONS {
                    let (x, y, z) = (o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
                    let (sag, slope) = self.sag(x * x + y * y)?;
                    let f = (z - self.z) - sag;
                    let df = d.z - 2.0 * slope * (x * d.x + y * d.y);
                    let step = f / df;
                    if !step.is_finite() {
                        return None;
                    }
                    t -= step;
                    if step.abs() <= NEWTON_TOLERANCE * (1.0 + t.abs()) {
                        if t.is_nan() || t <= 0.0 {
                            return None;
                        }
                        let (x, y) = (o.x + t * d.x, o.y + t * d.y);
                        let (_, slope) = self.sag(x * x + y * y)?;
                        let gradient = <$vec>::new(-2.0 * slope * x, -2.0 * slope * y, 1.0);
                        let mut normal = gradient.normalize();
                        if normal.dot(d) > 0.0 {
                            normal = -normal;
                        }
                        return Some((t, normal));
                    }
                }
                None
            }
        }

        /// Snell's law in vector form: unit `d` into a surface of unit normal `n` (against
        /// `d`), with `eta` = index before / index after; `None` at total internal
        /// reflection.
        pub fn refract(d: $vec, n: $vec, eta: $real) -> Option<$vec> {
            let cos_i = -n.dot(d);
            let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
            if sin2_t > 1.0 {
                return None;
            }
            let cos_t = (1.0 - sin2_t).sqrt();
            Some(eta * d + (eta * cos_i - cos_t) * n)
        }
    };
}

/// f64: the analysis (`lensray lens`, the tests against the optics).
pub mod wide {
    tracer!(f64, glam::DVec3, 1e-12);
}

/// f32: what renders trace (and the GLSL mirrors).
pub mod narrow {
    tracer!(f32, glam::Vec3, crate::interface::LENS_NEWTON_TOLERANCE);
}

/// The f64 elements of `lens`.
pub fn wide_elements(lens: &Prescription) -> wide::Elements {
    wide::Elements::new(lens)
}

#[cfg(test)]
mod tests {
    use super::wide::*;
    use super::*;
    use glam::DVec3;

    fn singlet() -> Prescription {
        Prescription::parse("s", "0 2 1 20\n60 8 1.6 30\n-40 0 1 30\n").unwrap()
    }

    /// Out and back: a ray traced to the film, reversed, comes back to where it started.
    #[test]
    fn tracing_is_reversible() {
        for lens in [
            singlet(),
            crate::optics::builtin::lens("double-gauss-50").unwrap(),
        ] {
            let elements = Elements::new(&lens);
            let start = LensRay {
                origin: DVec3::new(1.0, 2.0, -10.0),
                direction: DVec3::new(-0.05, -0.1, 1.0).normalize(),
            };
            let out = elements.trace(start, Toward::Film).expect("passes");
            // Reversed from a point past the last surface.
            let back = elements
                .trace(
                    LensRay {
                        origin: out.origin + 5.0 * out.direction,
                        direction: -out.direction,
                    },
                    Toward::Scene,
                )
                .expect("passes back");
            // Back at the first surface: continue to z = -10.
            let t = (-10.0 - back.origin.z) / back.direction.z;
            let p = back.origin + t * back.direction;
            assert!((p - start.origin).length() < 1e-9, "{}: {p}", lens.name);
            assert!((back.direction + start.direction).length() < 1e-12);
        }
    }

    /// Total internal reflection and clipped rays are blocked: `None`, never NaN.
    #[test]
    fn blocked_rays_are_none() {
        let elements = Elements::new(&singlet());
        // Outside the stop.
        let clipped = LensRay {
            origin: DVec3::new(0.0, 11.0, -1.0),
            direction: DVec3::Z,
        };
        assert!(elements.trace(clipped, Toward::Film).is_none());
        // From inside the glass at a grazing angle onto the rear surface: total internal
        // reflection (critical angle asin(1 / 1.6) = 38.7 degrees).
        let inside = Interface {
            z: 10.0,
            radius: 0.0,
            aperture_radius: 100.0,
            index_before: 1.6,
            index_after: 1.0,
            dispersion_before: 0.0,
            dispersion_after: 0.0,
            asphere: false,
            conic: 0.0,
            coefficients: [0.0; 8],
        };
        let d = DVec3::new(0.0, 60f64.to_radians().sin(), 60f64.to_radians().cos());
        assert!(refract(d, DVec3::new(0.0, 0.0, -1.0), 1.6).is_none());
        let glass = Interface {
            radius: -40.0,
            ..inside
        };
        let grazing = LensRay {
            origin: DVec3::new(0.0, 0.0, 5.0),
            direction: d,
        };
        assert!(glass.pass(grazing, Toward::Film).is_none());
        // A ray parallel to a flat surface misses it.
        assert!(inside
            .intersect(LensRay {
                origin: DVec3::ZERO,
                direction: DVec3::Y
            })
            .is_none());
    }

    /// An ellipsoid of conic constant -1/n^2 refracting from air into glass of index n images
    /// a point at infinity on the axis perfectly, at R n / (n - 1) behind its vertex (the
    /// Cartesian oval): every ray parallel to the axis crosses it there, in f64 to 1e-9 mm and
    /// in f32 to 1e-4 mm, and each hit lies on the sag.
    #[test]
    fn an_ellipsoid_focuses_parallel_rays_perfectly() {
        let (n, radius) = (1.5, 20.0);
        let lens = Prescription::parse(
            "ellipsoid",
            &format!(
                "0 1 1 20\n{radius} 60 {n} 20 k={}\n-1000 0 1 60\n",
                -1.0 / (n * n)
            ),
        )
        .unwrap();
        let focus = 1.0 + radius * n / (n - 1.0);
        let wide = Elements::new(&lens);
        let narrow = super::narrow::Elements::new(&lens);
        for h in [0.5, 2.0, 5.0, 8.0, 9.5] {
            let ray = LensRay {
                origin: DVec3::new(0.0, h, -5.0),
                direction: DVec3::Z,
            };
            let (t, _) = wide.interfaces[1]
                .intersect(ray)
                .expect("meets the asphere");
            let p = ray.origin + t * ray.direction;
            let (sag, _) = wide.interfaces[1].sag(p.y * p.y).unwrap();
            assert!((p.z - 1.0 - sag).abs() < 1e-12, "h {h}: off the sag");
            let out = wide.interfaces[1].pass(ray, Toward::Film).unwrap();
            let crossing = out.origin.z - out.origin.y * out.direction.z / out.direction.y;
            assert!(
                (crossing - focus).abs() < 1e-9,
                "h {h}: f64 crosses at {crossing}"
            );
            let ray32 = super::narrow::LensRay {
                origin: glam::Vec3::new(0.0, h as f32, -5.0),
                direction: glam::Vec3::Z,
            };
            let out = narrow.interfaces[1].pass(ray32, Toward::Film).unwrap();
            let crossing = out.origin.z - out.origin.y * out.direction.z / out.direction.y;
            assert!(
                (f64::from(crossing) - focus).abs() < 1e-4,
                "h {h}: f32 crosses at {crossing}"
            );
        }
    }
}
