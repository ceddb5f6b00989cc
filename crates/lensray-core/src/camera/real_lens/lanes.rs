//! A packet of camera rays through the lens at once, laid out by lane (one array per
//! coordinate), so that each surface's square roots, division and ~50 flops run as vector
//! instructions across the lanes. The arithmetic is `Interface::intersect`, `Interface::pass`
//! and `refract` operation for operation, in the same order (glam's `Vec3` is scalar: `dot` is
//! `(x x + y y) + z z`, `a + t d` per coordinate), with branches turned into selects and a
//! blocked lane's mask cleared; so every lane that passes carries `trace_to_scene`'s ray bit
//! for bit (`RealLens::generate_rays` is tested against `generate_ray`). The scalar tracer
//! stays the definition the GLSL mirrors.

#![expect(
    clippy::needless_range_loop,
    reason = "lane loops index several arrays by lane: the layout the vectorizer wants"
)]
#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(a > b)` as the scalar tracer tests it: a NaN does not block there either"
)]

use glam::{Vec2, Vec3};

use super::{RealLens, PUPIL_BINS};
use crate::optics::trace::narrow::{Elements, Interface, LensRay};
use crate::optics::trace::Toward;

/// N rays by coordinate, and which of them are still in the lens.
pub(super) struct Lanes<const N: usize> {
    pub ox: [f32; N],
    pub oy: [f32; N],
    pub oz: [f32; N],
    pub dx: [f32; N],
    pub dy: [f32; N],
    pub dz: [f32; N],
    pub alive: [bool; N],
    /// The stop's transmission where each ray crossed it.
    pub transmission: [f32; N],
    /// Each ray's dispersion offset (its wavelength; 0: the d line).
    pub offset: [f32; N],
}

impl<const N: usize> Lanes<N> {
    /// Every lane dead (`start` brings the samples' lanes to life).
    fn dead() -> Self {
        Lanes {
            ox: [0.0; N],
            oy: [0.0; N],
            oz: [0.0; N],
            dx: [0.0; N],
            dy: [0.0; N],
            dz: [1.0; N],
            alive: [false; N],
            transmission: [1.0; N],
            offset: [0.0; N],
        }
    }

    /// The rays from film points toward the pupil points of their lens samples, and the
    /// areas they were drawn from: `RealLens::start` (`ExitPupil::sample`, then the direction
    /// normalized as glam does) for every lane. The bins' regions are gathered lane by lane;
    /// the rest runs across the lanes.
    pub(super) fn start(lens: &RealLens, samples: &[(Vec3, Vec2, f32)]) -> (Self, [f32; N]) {
        let n = samples.len().min(N);
        let pupil = lens.pupil();
        let mut lanes = Lanes::dead();
        let (mut ux, mut uy) = ([0.0f32; N], [0.0f32; N]);
        for (l, &(film, u, k)) in samples.iter().enumerate().take(n) {
            lanes.offset[l] = k;
            lanes.ox[l] = film.x;
            lanes.oy[l] = film.y;
            lanes.oz[l] = film.z;
            ux[l] = u.x;
            uy[l] = u.y;
            lanes.alive[l] = true;
        }
        // ExitPupil::bin_at.
        let (mut r, mut f, mut bin) = ([0.0f32; N], [0.0f32; N], [0usize; N]);
        let bins = PUPIL_BINS as f32;
        for l in 0..N {
            r[l] = (lanes.ox[l] * lanes.ox[l] + lanes.oy[l] * lanes.oy[l]).sqrt();
            let t = r[l] / pupil.film_radius * bins;
            bin[l] = (t as usize).min(PUPIL_BINS - 1);
            f[l] = (t - bin[l] as f32).clamp(0.0, 1.0);
        }
        let mut regions = [[0.0f32; N]; 8];
        for l in 0..N {
            let b = &pupil.bins[bin[l]];
            let fields = [
                b.inner.centre.x,
                b.inner.centre.y,
                b.inner.half.x,
                b.inner.half.y,
                b.outer.centre.x,
                b.outer.centre.y,
                b.outer.half.x,
                b.outer.half.y,
            ];
            for (k, v) in fields.into_iter().enumerate() {
                regions[k][l] = v;
            }
        }
        let [icx, icy, ihx, ihy, ocx, ocy, ohx, ohy] = regions;
        let mut area = [0.0f32; N];
        for l in 0..N {
            // PupilBin::region, point and area.
            let (fl, film_x, film_y) = (f[l], lanes.ox[l], lanes.oy[l]);
            let (cx, cy) = (
                icx[l] + fl * (ocx[l] - icx[l]),
                icy[l] + fl * (ocy[l] - icy[l]),
            );
            let (hx, hy) = (
                ihx[l] + fl * (ohx[l] - ihx[l]),
                ihy[l] + fl * (ohy[l] - ihy[l]),
            );
            let qx = cx + hx * (2.0 * ux[l] - 1.0);
            let qy = cy + hy * (2.0 * uy[l] - 1.0);
            area[l] = 4.0 * hx.max(0.0) * hy.max(0.0);
            // Turned to the film point's angle.
            let on_axis = r[l] > 0.0;
            let cos = if on_axis { film_x / r[l] } else { 1.0 };
            let sin = if on_axis { film_y / r[l] } else { 0.0 };
            let rear_x = cos * qx - sin * qy;
            let rear_y = sin * qx + cos * qy;
            // (rear - film).normalize().
            let (x, y, z) = (rear_x - film_x, rear_y - film_y, pupil.rear_z - lanes.oz[l]);
            let recip = 1.0 / (x * x + y * y + z * z).sqrt();
            lanes.dx[l] = x * recip;
            lanes.dy[l] = y * recip;
            lanes.dz[l] = z * recip;
        }
        (lanes, area)
    }

    /// Rays from `film` toward the points `rear` of the rear vertex's plane (`rear_z`), at
    /// dispersion offset `k`: the exit-pupil search's grid (`Search::grid_of`), each direction
    /// normalized as the one-by-one search does. Lanes past `rear`'s length are dead.
    pub(super) fn toward(film: Vec3, rear: &[Vec2], rear_z: f32, k: f32) -> Self {
        let mut lanes = Lanes::dead();
        for (l, q) in rear.iter().enumerate().take(N) {
            let direction = (q.extend(rear_z) - film).normalize();
            (lanes.ox[l], lanes.oy[l], lanes.oz[l]) = film.into();
            (lanes.dx[l], lanes.dy[l], lanes.dz[l]) = direction.into();
            lanes.offset[l] = k;
            lanes.alive[l] = true;
        }
        lanes
    }

    pub(super) fn ray(&self, l: usize) -> LensRay {
        LensRay {
            origin: Vec3::new(self.ox[l], self.oy[l], self.oz[l]),
            direction: Vec3::new(self.dx[l], self.dy[l], self.dz[l]),
        }
    }

    /// Every lane from the film through every surface to the scene, as
    /// `RealLens::trace_to_scene` takes one ray.
    pub(super) fn trace_to_scene(&mut self, lens: &RealLens) {
        let (stop, stop_radius, aperture) = lens.stop();
        let interfaces = &lens.elements().interfaces;
        for i in (0..interfaces.len()).rev() {
            if i == stop {
                let t = self.meet_stop(&interfaces[i]);
                // The shape's transmission, lane by lane (one surface of many).
                for l in 0..N {
                    if self.alive[l] {
                        let p = Vec2::new(
                            self.ox[l] + t[l] * self.dx[l],
                            self.oy[l] + t[l] * self.dy[l],
                        );
                        self.transmission[l] = aperture.transmission(p / stop_radius);
                        self.alive[l] = self.transmission[l] > 0.0;
                    }
                }
            } else if interfaces[i].asphere {
                self.pass_one_by_one(&interfaces[i]);
            } else {
                self.refract_at(&interfaces[i]);
            }
            if !self.alive.iter().any(|&a| a) {
                return;
            }
        }
    }

    /// Every lane from the film through the lens's surfaces to the scene, as
    /// `Elements::trace_at` toward the scene takes one ray: the stop is its row's round
    /// opening (the aperture's shape plays no part), which `alive` then tells.
    pub(super) fn trace_elements(&mut self, elements: &Elements) {
        for surface in elements.interfaces.iter().rev() {
            if surface.radius == 0.0 {
                self.pass_opening(surface);
            } else if surface.asphere {
                self.pass_one_by_one(surface);
            } else {
                self.refract_at(surface);
            }
            if !self.alive.iter().any(|&a| a) {
                return;
            }
        }
    }

    /// `Interface::pass_at` through a flat opening: lanes that miss its plane or pass
    /// outside its radius die; the others go on from where they were, unrefracted.
    #[inline(always)]
    fn pass_opening(&mut self, opening: &Interface) {
        let t = self.meet_stop(opening);
        let aperture2 = opening.aperture_radius * opening.aperture_radius;
        for l in 0..N {
            let px = self.ox[l] + t[l] * self.dx[l];
            let py = self.oy[l] + t[l] * self.dy[l];
            self.alive[l] &= !(px * px + py * py > aperture2);
        }
    }

    /// `Interface::intersect` of the flat stop: the distance to its plane (the rays go on
    /// unrefracted from where they were); lanes that do not reach it die.
    #[inline(always)]
    fn meet_stop(&mut self, stop: &Interface) -> [f32; N] {
        let mut t = [0.0; N];
        for l in 0..N {
            t[l] = (stop.z - self.oz[l]) / self.dz[l];
            self.alive[l] &= t[l] > 0.0 && t[l].is_finite();
        }
        t
    }

    /// `Interface::pass_at` toward the scene through an asphere, lane by lane (Newton's
    /// iteration branches per ray; few lenses have aspheres, and those few surfaces).
    fn pass_one_by_one(&mut self, surface: &Interface) {
        for l in 0..N {
            if !self.alive[l] {
                continue;
            }
            match surface.pass_at(self.ray(l), Toward::Scene, self.offset[l]) {
                Some(ray) => {
                    (self.ox[l], self.oy[l], self.oz[l]) = ray.origin.into();
                    (self.dx[l], self.dy[l], self.dz[l]) = ray.direction.into();
                }
                None => self.alive[l] = false,
            }
        }
    }

    /// Each lane's ratio of indices (after / before: toward the scene) at its wavelength, as
    /// `Interface::pass_at` forms it.
    #[inline(always)]
    fn etas(&self, surface: &Interface) -> [f32; N] {
        if surface.dispersion_before == 0.0 && surface.dispersion_after == 0.0 {
            return [surface.index_after / surface.index_before; N];
        }
        let mut eta = [0.0; N];
        for l in 0..N {
            let k = self.offset[l];
            let before = surface.index_before + surface.dispersion_before * k;
            let after = surface.index_after + surface.dispersion_after * k;
            eta[l] = after / before;
        }
        eta
    }

    /// `Interface::pass_at` toward the scene through a spherical surface, every lane.
    #[inline(always)]
    fn refract_at(&mut self, surface: &Interface) {
        let radius = surface.radius;
        let centre_z = surface.z + surface.radius;
        let radius2 = surface.radius * surface.radius;
        let abs_radius = surface.radius.abs();
        let aperture2 = surface.aperture_radius * surface.aperture_radius;
        let etas = self.etas(surface);
        for l in 0..N {
            let eta = etas[l];
            let eta2 = eta * eta;
            let (dx, dy, dz) = (self.dx[l], self.dy[l], self.dz[l]);
            // intersect: o = origin - centre (the centre is on the axis).
            let (ox, oy, oz) = (self.ox[l] - 0.0, self.oy[l] - 0.0, self.oz[l] - centre_z);
            let b = ox * dx + oy * dy + oz * dz;
            let c = (ox * ox + oy * oy + oz * oz) - radius2;
            let discriminant = b * b - c;
            let mut alive = self.alive[l] & (discriminant >= 0.0);
            let root = discriminant.sqrt();
            let (near, far) = (-b - root, -b + root);
            let near_on_cap = near > 0.0 && (oz + near * dz) * -radius > 0.0;
            let far_on_cap = far > 0.0 && (oz + far * dz) * -radius > 0.0;
            alive &= near_on_cap | far_on_cap;
            let t = if near_on_cap { near } else { far };
            let mut nx = (ox + t * dx) / abs_radius;
            let mut ny = (oy + t * dy) / abs_radius;
            let mut nz = (oz + t * dz) / abs_radius;
            if nx * dx + ny * dy + nz * dz > 0.0 {
                (nx, ny, nz) = (-nx, -ny, -nz);
            }
            // pass: the point and the clear aperture.
            let px = self.ox[l] + t * dx;
            let py = self.oy[l] + t * dy;
            let pz = self.oz[l] + t * dz;
            alive &= !(px * px + py * py > aperture2);
            // refract.
            let cos_i = -(nx * dx + ny * dy + nz * dz);
            let sin2_t = eta2 * (1.0 - cos_i * cos_i);
            alive &= !(sin2_t > 1.0);
            let cos_t = (1.0 - sin2_t).sqrt();
            let k = eta * cos_i - cos_t;
            self.dx[l] = eta * dx + k * nx;
            self.dy[l] = eta * dy + k * ny;
            self.dz[l] = eta * dz + k * nz;
            self.ox[l] = px;
            self.oy[l] = py;
            self.oz[l] = pz;
            self.alive[l] = alive;
        }
    }
}
