//! Shift and tilt in the preview: the panel's values, and the plane of focus through three
//! surface points (Shift+click).

use glam::DVec3;

use lensray_core::camera::movements::MAX_TILT_DEGREES;
use lensray_core::camera::{Camera, FocusPlane, Movements};
use lensray_core::settings::tilt_model;

use super::CameraRig;

/// The largest tilt the panel sets, degrees (the settings take any below 90).
pub const PANEL_MAX_TILT_DEGREES: f64 = MAX_TILT_DEGREES - 1.0;

impl CameraRig {
    /// Shift and tilt as the camera has them.
    pub fn movements(&self) -> Movements {
        self.camera.movements
    }

    /// Shifts the film window (mm with a focal length or a real lens, else image heights).
    pub fn set_shift(&mut self, shift: [f64; 2]) {
        if shift.iter().all(|x| x.is_finite()) {
            self.camera.movements.shift = shift;
            self.commit();
        }
    }

    /// Tilts the lens by `tilt` degrees (clamped to [0, 89]) toward `direction` (degrees
    /// counter-clockwise from the image's bottom, kept in [0, 360)).
    pub fn set_tilt(&mut self, tilt: f64, direction: f64) {
        if !(tilt.is_finite() && direction.is_finite()) {
            return;
        }
        let m = &mut self.camera.movements;
        m.tilt_degrees = tilt.clamp(0.0, PANEL_MAX_TILT_DEGREES);
        m.tilt_direction_degrees = direction.rem_euclid(360.0);
        self.commit();
    }

    /// Lays the plane of focus through `points` (world space) seen by `camera` (the current
    /// view's): sets focus distance, tilt and tilt direction, and returns the plane.
    pub fn lay_focus_plane(
        &mut self,
        points: &[DVec3; 3],
        camera: &Camera,
    ) -> Result<FocusPlane, String> {
        let camera_from_world = camera.camera_from_world.as_dmat4();
        let in_camera = points.map(|p| camera_from_world.transform_point3(p));
        let plane = FocusPlane::through(in_camera, tilt_model(&self.settings.camera, camera))
            .map_err(|e| e.to_string())?;
        self.camera.focus_distance = plane.focus_distance;
        self.camera.movements.tilt_degrees = plane.tilt_degrees;
        self.camera.movements.tilt_direction_degrees = plane.tilt_direction_degrees;
        self.commit();
        Ok(plane)
    }
}
