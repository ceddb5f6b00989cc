//! The rig's camera with every value explicit, and how it writes itself into the settings.

use glam::DVec3;

use lensray_core::camera::Movements;
use lensray_core::settings::{ProjectionKind, Settings, Switch};

use super::lens::RigLens;

/// Everything that describes the camera, explicit.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct RigCamera {
    pub(super) eye: DVec3,
    pub(super) target: DVec3,
    /// The world up: orbit yaws about it.
    pub(super) up: DVec3,
    pub(super) projection: ProjectionKind,
    /// Kept while orthographic, so switching back restores it.
    pub(super) vfov_degrees: f64,
    /// Meaningful while orthographic.
    pub(super) ortho_height: f64,
    pub(super) focus_distance: f64,
    pub(super) lens: RigLens,
    /// Shift and tilt (`camera::movements`).
    pub(super) movements: Movements,
}

/// The camera frame in f64, built as `CameraFrame::look_at` builds it.
pub(super) struct RigFrame {
    pub(super) forward: DVec3,
    pub(super) right: DVec3,
    pub(super) true_up: DVec3,
}

impl RigCamera {
    pub(super) fn distance(&self) -> f64 {
        (self.target - self.eye).length()
    }

    pub(super) fn frame(&self) -> RigFrame {
        let forward = (self.target - self.eye).normalize_or_zero();
        let right = forward.cross(self.up).normalize_or_zero();
        RigFrame {
            forward,
            right,
            true_up: right.cross(forward),
        }
    }

    /// The vertical field of view the camera has: the lens's with physical units (a real
    /// lens's to first order).
    pub(super) fn vfov_radians(&self) -> f64 {
        match &self.lens {
            RigLens::Physical(lens) => lens
                .tilted_film_distance_mm(
                    self.focus_distance,
                    self.movements.tilt_degrees.to_radians(),
                )
                .map_or(self.vfov_degrees.to_radians(), |film| {
                    2.0 * (lens.sensor_height_mm / (2.0 * film)).atan()
                }),
            RigLens::Real(real) => real.vfov(self.focus_distance),
            RigLens::Aperture { .. } => self.vfov_degrees.to_radians(),
        }
    }

    /// Height in world units of what the view shows at the target's distance.
    pub(super) fn view_height_at_target(&self) -> f64 {
        match self.projection {
            ProjectionKind::Perspective => {
                2.0 * (0.5 * self.vfov_radians()).tan() * self.distance()
            }
            ProjectionKind::Orthographic => self.ortho_height,
        }
    }

    pub(super) fn aperture_radius(&self) -> f64 {
        match &self.lens {
            RigLens::Aperture { radius } => *radius,
            RigLens::Physical(lens) => lens.aperture_radius(),
            RigLens::Real(real) => real.entrance_pupil_radius(),
        }
    }

    /// Writes this camera into `settings` (near and far untouched).
    pub(super) fn store(&self, settings: &mut Settings) {
        let c = &mut settings.camera;
        let orthographic = self.projection == ProjectionKind::Orthographic;
        c.projection = Some(self.projection);
        c.eye = Some(self.eye.to_array());
        c.target = Some(self.target.to_array());
        c.up = Some(self.up.to_array());
        c.vfov_degrees = Some(self.vfov_degrees);
        c.ortho_height = orthographic.then_some(self.ortho_height);
        c.focus_distance = Some(self.focus_distance);
        let m = &self.movements;
        c.shift = (m.shift != [0.0, 0.0]).then_some(m.shift);
        c.tilt = (m.tilt_degrees != 0.0).then_some(m.tilt_degrees);
        c.tilt_direction = (m.tilt_degrees != 0.0).then_some(m.tilt_direction_degrees);
        c.focus_plane = None;
        c.lens.prescription = None;
        match &self.lens {
            RigLens::Aperture { radius } => {
                c.aperture_radius = Some(*radius);
                c.focal_length_mm = None;
                // With a shutter time the f-number stays: the exposure's (settings::exposure).
                if c.exposure.shutter.is_none() {
                    c.f_number = None;
                }
                c.sensor_height_mm = None;
            }
            RigLens::Physical(lens) => {
                c.aperture_radius = None;
                c.focal_length_mm = Some(lens.focal_length_mm);
                c.f_number = Some(lens.f_number);
                c.sensor_height_mm = Some(lens.sensor_height_mm);
            }
            RigLens::Real(real) => {
                c.aperture_radius = None;
                c.focal_length_mm = None;
                c.f_number = Some(real.f_number);
                c.sensor_height_mm = Some(real.sensor_height_mm);
                c.lens.prescription = Some(real.prescription.clone());
                c.lens.dispersion = (!real.dispersion).then_some(Switch::Off);
            }
        }
    }
}
