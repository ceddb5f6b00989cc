//! Camera -> screen: the course's projective matrices ("Linear Models").
//!
//! Both map the view volume between `near` and `far` to depth [0, 1] and leave x, y for the
//! screen window to scale (see `film`).

use glam::{Mat4, Vec4};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Vertical field of view, radians.
    Perspective { vfov: f32 },
    /// Height of the view in world units.
    Orthographic { height: f32 },
}

impl Projection {
    /// Half the height of the screen window: tan(vfov / 2) on the z = 1 plane, or height / 2.
    pub fn screen_half_height(&self) -> f32 {
        match *self {
            Projection::Perspective { vfov } => (0.5 * vfov).tan(),
            Projection::Orthographic { height } => 0.5 * height,
        }
    }

    pub fn screen_from_camera(&self, near: f32, far: f32) -> Mat4 {
        match self {
            Projection::Perspective { .. } => perspective(near, far),
            Projection::Orthographic { .. } => orthographic(near, far),
        }
    }

    pub fn camera_from_screen(&self, near: f32, far: f32) -> Mat4 {
        match self {
            Projection::Perspective { .. } => perspective_inverse(near, far),
            Projection::Orthographic { .. } => orthographic_inverse(near, far),
        }
    }
}

/// Slide "Orthographic": (x, y, z) -> (x, y, (z - near) / (far - near)).
///
/// ```text
/// P = | 1 0 0            0                     |
///     | 0 1 0            0                     |
///     | 0 0 1/(f-n)      -n/(f-n)              |
///     | 0 0 0            1                     |
/// ```
pub fn orthographic(near: f32, far: f32) -> Mat4 {
    let range = far - near;
    // glam is column-major: each Vec4 below is a column of P.
    Mat4::from_cols(
        Vec4::X,
        Vec4::Y,
        Vec4::new(0.0, 0.0, 1.0 / range, 0.0),
        Vec4::new(0.0, 0.0, -near / range, 1.0),
    )
}

/// Inverse of [`orthographic`]: z = near + z_screen (far - near).
pub fn orthographic_inverse(near: f32, far: f32) -> Mat4 {
    let range = far - near;
    Mat4::from_cols(
        Vec4::X,
        Vec4::Y,
        Vec4::new(0.0, 0.0, range, 0.0),
        Vec4::new(0.0, 0.0, near, 1.0),
    )
}

/// Slide "Perspective": (x, y, z) -> (x/z, y/z, far (z - near) / (z (far - near))).
///
/// ```text
/// P = | 1 0 0          0              |
///     | 0 1 0          0              |
///     | 0 0 f/(f-n)    -f n/(f-n)     |
///     | 0 0 1          0              |
/// ```
pub fn perspective(near: f32, far: f32) -> Mat4 {
    let range = far - near;
    Mat4::from_cols(
        Vec4::X,
        Vec4::Y,
        Vec4::new(0.0, 0.0, far / range, 1.0),
        Vec4::new(0.0, 0.0, -far * near / range, 0.0),
    )
}

/// Inverse of [`perspective`] in closed form: the inverse of its lower-right 2x2 block
/// `[[f/(f-n), -f n/(f-n)], [1, 0]]` is `[[0, 1], [-(f-n)/(f n), 1/n]]`. Homogeneous: divide by w.
pub fn perspective_inverse(near: f32, far: f32) -> Mat4 {
    let range = far - near;
    Mat4::from_cols(
        Vec4::X,
        Vec4::Y,
        Vec4::new(0.0, 0.0, 0.0, -range / (far * near)),
        Vec4::new(0.0, 0.0, 1.0, 1.0 / near),
    )
}
