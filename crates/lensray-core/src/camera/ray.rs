//! A ray: origin and unit direction, in whatever space the caller says.

use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    /// Unit length.
    pub direction: Vec3,
}

impl Ray {
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.direction * t
    }

    /// The ray in the space `a_from_b` maps to, from the space it maps from (a rigid
    /// transform keeps the direction unit length): `world_from_camera` takes a camera ray to
    /// world space.
    pub fn transformed(&self, a_from_b: &Mat4) -> Ray {
        Ray {
            origin: a_from_b.transform_point3(self.origin),
            direction: a_from_b.transform_vector3(self.direction),
        }
    }
}
