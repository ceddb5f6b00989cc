//! Light from an environment: an equirectangular high-dynamic-range image (Radiance `.hdr` or
//! OpenEXR `.exr`) at infinity around the scene, turned about the vertical axis and scaled.
//!
//! The mapping (`map_from_world`): +Y is up; the image's top row looks up, its bottom row down;
//! its centre column looks along -Z (where a glTF camera with no rotation looks), and u grows
//! towards +X. `rotation_degrees` turns the environment counter-clockwise seen from above.
//! A texel's radiance is constant over it (nearest lookup), so that sampling the texels by
//! their power (`sampling`) has a density exactly proportional to what it lights with.

mod load;
pub mod sampling;
pub mod studio;
#[cfg(test)]
mod tests;

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

pub use load::{EnvironmentError, Mended};
pub use sampling::{EnvironmentSample, EnvironmentSampler};

/// An equirectangular radiance map, its turn about +Y and its scale.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    pub width: u32,
    pub height: u32,
    /// Linear radiance, row-major from the top row (looking up).
    pub texels: Vec<Vec3>,
    /// Counter-clockwise seen from above, degrees.
    pub rotation_degrees: f32,
    /// Multiplies every texel.
    pub intensity: f32,
}

impl EnvironmentMap {
    /// A map of `width` x `height` texels (row-major from the top); `None` when the sizes and
    /// the texels do not agree or a size is 0.
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Option<Self> {
        let count = (width as usize).checked_mul(height as usize)?;
        (count > 0 && texels.len() == count).then_some(Self {
            width,
            height,
            texels,
            rotation_degrees: 0.0,
            intensity: 1.0,
        })
    }

    /// The same map turned by `degrees` and scaled by `intensity`.
    pub fn turned(self, degrees: f32, intensity: f32) -> Self {
        Self {
            rotation_degrees: degrees,
            intensity,
            ..self
        }
    }

    /// (cos, sin) of the turn: computed once a lookup in the same order as the GLSL mirror.
    fn turn(&self) -> (f32, f32) {
        let radians = self.rotation_degrees.to_radians();
        (radians.cos(), radians.sin())
    }

    /// The image coordinates ([0, 1)^2, u across, v down) a world direction `d` (unit) sees.
    pub fn uv_from_world(&self, d: Vec3) -> Vec2 {
        let (c, s) = self.turn();
        // Undo the turn: a counter-clockwise turn seen from above takes +X towards -Z.
        let x = c * d.x - s * d.z;
        let z = s * d.x + c * d.z;
        let u = 0.5 + x.atan2(-z) / TAU;
        let v = d.y.clamp(-1.0, 1.0).acos() / PI;
        Vec2::new(u.rem_euclid(1.0), v)
    }

    /// The world direction (unit) at image coordinates `uv`.
    pub fn world_from_uv(&self, uv: Vec2) -> Vec3 {
        let d = map_direction(uv);
        let (c, s) = self.turn();
        Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
    }

    /// The texel (column, row) image coordinates `uv` fall in.
    pub fn texel_at(&self, uv: Vec2) -> (u32, u32) {
        let column = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let row = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        (column, row)
    }

    /// Radiance arriving from direction `d` (unit, pointing away from the scene).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (column, row) = self.texel_at(self.uv_from_world(d));
        self.texel(column, row)
    }

    /// The scaled radiance of one texel.
    pub fn texel(&self, column: u32, row: u32) -> Vec3 {
        self.texels[(row * self.width + column) as usize] * self.intensity
    }
}

/// The direction (unit) image coordinates `uv` look along before the map is turned.
pub fn map_direction(uv: Vec2) -> Vec3 {
    let phi = (uv.x - 0.5) * TAU;
    let theta = uv.y * PI;
    let (sin_theta, cos_theta) = theta.sin_cos();
    Vec3::new(sin_theta * phi.sin(), cos_theta, -sin_theta * phi.cos())
}

/// An environment map that lights a scene: the map and the tables that draw its directions
/// by power (`None` when nothing in it emits: it is then only seen and reflected).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentLight {
    pub map: EnvironmentMap,
    pub sampler: Option<EnvironmentSampler>,
}

impl EnvironmentLight {
    pub fn new(map: EnvironmentMap) -> Self {
        let sampler = EnvironmentSampler::new(&map);
        Self { map, sampler }
    }
}

/// Rec. 709 luminance of linear RGB: what a texel's share of the samples follows.
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
