//! Moving the camera: orbit, pan, dolly and fly, the mouse's and the held keys' motions.

use glam::{DQuat, DVec3};

use lensray_core::settings::ProjectionKind;

use super::{
    CameraRig, DOLLY_FACTOR_PER_STEP, MAX_ELEVATION_DEGREES, MIN_DISTANCE_PER_RADIUS,
    ORBIT_DEGREES_PER_PIXEL,
};

impl CameraRig {
    /// Left drag: turns the eye about the target, grabbing the scene. Dragging right moves the eye
    /// to its left (yaw about the world up); dragging down raises it (pitch about the camera
    /// right), stopping short of the poles so the view never flips. The distance is kept.
    pub fn orbit(&mut self, dx_px: f64, dy_px: f64) {
        let cam = &mut self.camera;
        let up = cam.up.normalize_or_zero();
        let offset = cam.eye - cam.target;
        let distance = offset.length();
        if up == DVec3::ZERO || distance == 0.0 {
            return;
        }
        let direction = offset / distance;
        let elevation = direction.dot(up).clamp(-1.0, 1.0).asin();
        let horizontal = (direction - direction.dot(up) * up).normalize_or_zero();
        if horizontal == DVec3::ZERO {
            return; // Looking along the up axis: no camera resolves there anyway.
        }
        let yaw = -(dx_px * ORBIT_DEGREES_PER_PIXEL).to_radians();
        let horizontal = DQuat::from_axis_angle(up, yaw) * horizontal;
        // A camera that starts beyond the limit may come back, never go further.
        let limit = MAX_ELEVATION_DEGREES.to_radians();
        let new_elevation = (elevation + (dy_px * ORBIT_DEGREES_PER_PIXEL).to_radians())
            .clamp((-limit).min(elevation), limit.max(elevation));
        let (sin, cos) = new_elevation.sin_cos();
        cam.eye = cam.target + distance * (cos * horizontal + sin * up);
        self.commit();
    }

    /// World units that one pixel spans at the target's distance.
    fn world_per_pixel(&self) -> f64 {
        self.camera.view_height_at_target() / self.image_height()
    }

    /// Right or middle drag: moves eye and target together along the camera's right and up so the
    /// point at the target's distance stays under the cursor (pixels, y down).
    pub fn pan(&mut self, dx_px: f64, dy_px: f64) {
        let scale = self.world_per_pixel();
        let frame = self.camera.frame();
        let shift = scale * (-dx_px * frame.right + dy_px * frame.true_up);
        self.camera.eye += shift;
        self.camera.target += shift;
        self.commit();
    }

    /// Mouse wheel (positive = in): perspective moves the eye towards the target, leaving
    /// 0.9^steps of the distance (never reaching it); orthographic scales the view height by it.
    pub fn dolly(&mut self, steps: f64) {
        let factor = DOLLY_FACTOR_PER_STEP.powf(steps);
        let min_distance = MIN_DISTANCE_PER_RADIUS * self.scene_radius;
        let cam = &mut self.camera;
        match cam.projection {
            ProjectionKind::Perspective => {
                let distance = (cam.distance() * factor).max(min_distance);
                cam.eye = cam.target - distance * cam.frame().forward;
            }
            ProjectionKind::Orthographic => {
                cam.ortho_height = (cam.ortho_height * factor).max(min_distance);
            }
        }
        self.commit();
    }

    /// Held keys: moves eye and target together along `direction` in camera axes (x right, y up,
    /// z forward) at one scene radius per second; diagonals are no faster.
    pub fn fly(&mut self, direction: glam::Vec3, seconds: f64) {
        let d = direction.as_dvec3();
        let d = if d.length() > 1.0 { d.normalize() } else { d };
        let frame = self.camera.frame();
        let shift = self.scene_radius
            * seconds
            * (d.x * frame.right + d.y * frame.true_up + d.z * frame.forward);
        self.camera.eye += shift;
        self.camera.target += shift;
        self.commit();
    }
}
