//! The film behind a real lens, and the lens's tilt against it.
//!
//! A tilted lens turns as a whole about its entrance pupil's centre (camera space's origin):
//! by the tilt toward the hinge direction h (`Movements`), so that its axis runs along
//! a = (sin(tilt) h, cos(tilt)) in camera space, as the thin lens of `movements` turns about
//! its centre. The film stays square to the view axis. Lens space is then camera space turned
//! by `camera_from_lens` (and flipped along the axis, see the parent module), and the film is a
//! plane of lens space that faces the lens's axis only when the lens does not tilt.
//!
//! Where the film sits comes from the optics: it is the plane square to the view axis where
//! the real rays from the subject on the view axis (the focus distance in front of the
//! entrance pupil), through a grid over the entrance pupil, gather most tightly (least spread
//! about their centroid). Untilted, `focus::film_z` finds the same plane from meridional rays
//! of the axial point. Where the plane of focus then lands is the optics' answer too: the
//! renderer traces it, and `tests/reference/tilted_lens.rs` compares it with the thin lens's
//! hinge rule.

use glam::{DMat3, DQuat, DVec3, Mat3, Vec2, Vec3};

use super::RealLensError;
use crate::camera::physical::MM_PER_WORLD_UNIT;
use crate::camera::Movements;
use crate::optics::paraxial::FirstOrder;
use crate::optics::trace::wide::{Elements, LensRay};
use crate::optics::trace::Toward;
use crate::optics::Prescription;

/// Rings and spokes of the entrance-pupil grid a tilted lens is focused with.
const RINGS: u32 = 16;
const SPOKES: u32 = 32;

/// The film in lens space (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmFrame {
    /// The film point on the view axis (where `RealLens::raster_centre` lands).
    pub origin: Vec3,
    /// Lens-space directions of the image's +x and +y (camera space's x and y). The image is
    /// inverted: a film point u mm right and v mm up in the image lies at
    /// origin - u right - v up.
    pub right: Vec3,
    pub up: Vec3,
    /// The film's unit normal, facing away from the lens ((0, 0, 1) untilted).
    pub normal: Vec3,
    /// Lens-space z where the film crosses the lens's axis.
    pub axis_z: f32,
}

impl FilmFrame {
    /// The film square to the lens's axis at lens-space z `film_z`.
    pub fn square(film_z: f32) -> Self {
        FilmFrame {
            origin: Vec3::new(0.0, 0.0, film_z),
            right: Vec3::X,
            up: Vec3::Y,
            normal: Vec3::Z,
            axis_z: film_z,
        }
    }

    /// The film point `(u, v)` mm right and up of the origin in the image, inverted. Written
    /// out so that the GLSL mirror rounds as this does (and the square film's points are
    /// exactly (-u, -v, film_z)).
    #[inline(always)]
    pub fn point(&self, u: f32, v: f32) -> Vec3 {
        let (o, r, p) = (self.origin, self.right, self.up);
        Vec3::new(
            (o.x + r.x * -u) + p.x * -v,
            (o.y + r.y * -u) + p.y * -v,
            (o.z + r.z * -u) + p.z * -v,
        )
    }

    /// The corners (lens space) of a film of half sides `half` (mm) shifted by `shift` (mm, in
    /// the image).
    pub fn corners(&self, half: Vec2, shift: Vec2) -> [Vec3; 4] {
        [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
            .map(|(sx, sy)| self.point(sx * half.x + shift.x, sy * half.y + shift.y))
    }

    /// How far the film's points lie from the lens's axis (mm): the farthest of `corners`.
    pub fn reach(corners: &[Vec3; 4]) -> f32 {
        corners
            .iter()
            .map(|p| Vec2::new(p.x, p.y).length())
            .fold(0.0, f32::max)
    }

    /// tan(tilt): across a circle of radius r about the lens's axis, the film's lens-space z
    /// runs over axis_z +- r tan(tilt).
    pub fn slope(&self) -> f32 {
        Vec2::new(self.normal.x, self.normal.y).length() / self.normal.z
    }
}

/// A lens tilted as `movements` says: the turn from lens to camera space, about the entrance
/// pupil.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tilt {
    /// Camera space from lens space unflipped (x, y, entrance_pupil_z - z): the identity
    /// untilted.
    pub turn: DMat3,
    pub radians: f64,
}

impl Tilt {
    pub fn of(movements: &Movements) -> Self {
        let radians = movements.tilt_degrees.to_radians();
        if radians == 0.0 {
            return Tilt {
                turn: DMat3::IDENTITY,
                radians,
            };
        }
        let h = movements.hinge_direction();
        let (sin, cos) = radians.sin_cos();
        let axis = DVec3::new(sin * h.x, sin * h.y, cos);
        Tilt {
            turn: DMat3::from_quat(DQuat::from_rotation_arc(DVec3::Z, axis)),
            radians,
        }
    }

    pub fn is_square(&self) -> bool {
        self.radians == 0.0
    }

    /// `turn` in f32: what camera rays are turned by.
    pub fn camera_from_lens(&self) -> Mat3 {
        self.turn.as_mat3()
    }

    /// Lens space of a camera-space point (mm) of a lens whose entrance pupil is at lens-space
    /// z `entrance_pupil_z`.
    fn lens_point(&self, camera: DVec3, entrance_pupil_z: f64) -> DVec3 {
        let v = self.turn.transpose() * camera;
        DVec3::new(v.x, v.y, entrance_pupil_z - v.z)
    }

    /// Lens space of a camera-space direction.
    fn lens_direction(&self, camera: DVec3) -> DVec3 {
        let v = self.turn.transpose() * camera;
        DVec3::new(v.x, v.y, -v.z)
    }

    /// The film `distance` mm behind the entrance pupil along the view axis.
    pub fn film(&self, distance: f64, entrance_pupil_z: f64) -> FilmFrame {
        let origin = self.lens_point(DVec3::new(0.0, 0.0, -distance), entrance_pupil_z);
        let normal = self.lens_direction(-DVec3::Z);
        FilmFrame {
            origin: origin.as_vec3(),
            right: self.lens_direction(DVec3::X).as_vec3(),
            up: self.lens_direction(DVec3::Y).as_vec3(),
            normal: normal.as_vec3(),
            // Where origin + s (normal's plane) meets the axis: normal . (p - origin) = 0.
            axis_z: (origin.z + (normal.x * origin.x + normal.y * origin.y) / normal.z) as f32,
        }
    }

    /// The distance (mm) behind the entrance pupil, along the view axis, of the film where
    /// the real rays from the subject `focus_distance` world units along the view axis
    /// gather most tightly: for rays p_i(c) = a_i + b_i c meeting the plane at c, the spread
    /// sum |p_i - mean|^2 is least at c = -sum (a_i - a) . (b_i - b) / sum |b_i - b|^2.
    pub fn film_distance(
        &self,
        lens: &Prescription,
        first_order: &FirstOrder,
        focus_distance: f64,
    ) -> Result<f64, RealLensError> {
        // The subject lies focus_distance cos(tilt) along the lens's axis: the same bounds.
        super::focus::film_z(lens, first_order, focus_distance * self.radians.cos())?;
        let entrance_pupil_z = first_order.entrance_pupil.position_mm;
        let subject = self.lens_point(
            DVec3::new(0.0, 0.0, focus_distance * MM_PER_WORLD_UNIT),
            entrance_pupil_z,
        );
        let w = self.lens_direction(DVec3::Z);
        let pupil_centre = DVec3::new(0.0, 0.0, entrance_pupil_z);
        let elements = Elements::new(lens);
        let mut rays = Vec::new();
        for ring in 0..RINGS {
            let rho = 0.5
                * first_order.entrance_pupil.diameter_mm
                * ((f64::from(ring) + 0.5) / f64::from(RINGS)).sqrt();
            for spoke in 0..SPOKES {
                let phi = std::f64::consts::TAU * (f64::from(spoke) + 0.5) / f64::from(SPOKES);
                let aim = pupil_centre + rho * DVec3::new(phi.cos(), phi.sin(), 0.0);
                let ray = LensRay {
                    origin: subject,
                    direction: (aim - subject).normalize(),
                };
                if let Some(out) = elements.trace(ray, Toward::Film) {
                    let across = w.dot(out.direction);
                    let a =
                        out.origin - out.direction * (w.dot(out.origin - pupil_centre) / across);
                    rays.push((a, -out.direction / across));
                }
            }
        }
        let n = rays.len() as f64;
        let (a_mean, b_mean) = rays.iter().fold((DVec3::ZERO, DVec3::ZERO), |(a, b), r| {
            (a + r.0 / n, b + r.1 / n)
        });
        let (mut ab, mut bb) = (0.0, 0.0);
        for (a, b) in &rays {
            ab += (*a - a_mean).dot(*b - b_mean);
            bb += (*b - b_mean).length_squared();
        }
        if rays.len() < 3 || bb <= 0.0 {
            return Err(RealLensError::NoLight {
                lens: lens.name.clone(),
                f_number: first_order.f_number,
            });
        }
        Ok(-ab / bb)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Untilted, the least spread over the whole entrance pupil puts the film where
    /// `focus::film_z`'s meridional rays do: measured 1e-5 mm apart for double-gauss-50 at
    /// f/8, 3 m (bound 1e-3 mm, a thousandth of the depth of focus there).
    #[test]
    fn a_square_film_lands_where_focus_puts_it() {
        let lens = crate::optics::builtin::lens("double-gauss-50").expect("built in");
        let stopped = lens.with_stop_diameter(lens.surfaces()[lens.stop()].diameter / 4.0);
        let first_order = FirstOrder::of(&stopped);
        let film_z = super::super::focus::film_z(&stopped, &first_order, 3.0).expect("focuses");
        let square = Tilt::of(&Movements::NONE);
        let distance = square
            .film_distance(&stopped, &first_order, 3.0)
            .expect("focuses");
        let z = first_order.entrance_pupil.position_mm + distance;
        let apart = (z - f64::from(film_z)).abs();
        assert!(apart < 1e-3, "film at {z} mm, focus::film_z {film_z} mm");
    }
}
