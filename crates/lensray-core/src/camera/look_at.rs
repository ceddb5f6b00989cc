//! World -> camera: the camera frame from eye, target and up.

use glam::{Mat4, Vec3, Vec4};

/// The orthonormal frame of a camera in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraFrame {
    pub eye: Vec3,
    pub right: Vec3,
    pub true_up: Vec3,
    pub forward: Vec3,
}

impl CameraFrame {
    /// `None` when the frame is degenerate: eye = target, or up parallel to the view direction.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Option<Self> {
        let forward = (target - eye).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        // Reject near-parallel up vectors too: the frame would be dominated by rounding.
        if forward.cross(up.normalize_or_zero()).length() < 1e-6 {
            return None;
        }
        let true_up = right.cross(forward);
        Some(Self {
            eye,
            right,
            true_up,
            forward,
        })
    }

    /// Rows are right, true_up, forward: camera x right, y up, z forward (left-handed, as the
    /// course and pbrt), so the determinant is -1: the mirror from the right-handed world.
    pub fn camera_from_world(&self) -> Mat4 {
        let rotation = Mat4::from_cols(
            Vec4::new(self.right.x, self.true_up.x, self.forward.x, 0.0),
            Vec4::new(self.right.y, self.true_up.y, self.forward.y, 0.0),
            Vec4::new(self.right.z, self.true_up.z, self.forward.z, 0.0),
            Vec4::W,
        );
        rotation * Mat4::from_translation(-self.eye)
    }

    /// The exact inverse, built directly (columns right, true_up, forward, eye).
    pub fn world_from_camera(&self) -> Mat4 {
        Mat4::from_cols(
            self.right.extend(0.0),
            self.true_up.extend(0.0),
            self.forward.extend(0.0),
            self.eye.extend(1.0),
        )
    }
}
