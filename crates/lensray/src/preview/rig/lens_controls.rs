//! The lens panel's controls: focus, aperture, focal length, f-number, sensor, the lens
//! picker and the projection.

use lensray_core::camera::physical::{PhysicalLens, MM_PER_WORLD_UNIT};
use lensray_core::optics::Prescription;
use lensray_core::settings::{
    ApertureSettings, ProjectionKind, DEFAULT_F_NUMBER, DEFAULT_SENSOR_HEIGHT_MM,
};

use super::lens::{clamp_toward, LensChoice, RealRigLens, RigLens};
use super::{
    CameraRig, APERTURE_STEPS_PER_OCTAVE, FOCUS_STEPS_PER_OCTAVE, F_NUMBER_RANGE, F_STOPS_PER_STEP,
    MIN_DISTANCE_PER_RADIUS, SENSOR_HEIGHT_RANGE_MM, SMALLEST_APERTURE_PER_RADIUS,
};

impl CameraRig {
    /// Nearest focus the lens allows: beyond the focal length with physical units (no image forms
    /// inside it), a real lens's nearest (`REAL_MAX_MAGNIFICATION`), and never 0.
    pub(super) fn min_focus_distance(&self) -> f64 {
        let floor = MIN_DISTANCE_PER_RADIUS * self.scene_radius;
        match &self.camera.lens {
            RigLens::Physical(lens) => floor.max(1.001 * lens.focal_length_mm / MM_PER_WORLD_UNIT),
            RigLens::Real(real) => floor.max(real.nearest_focus()),
            RigLens::Aperture { .. } => floor,
        }
    }

    /// Focuses at `distance` along the view axis (e.g. the G-buffer depth under the cursor;
    /// with a real lens, from its entrance pupil, the camera's origin), no nearer than the
    /// lens focuses. Returns the focus set; a miss (0, infinite or NaN) leaves the focus as it
    /// is and returns `None`.
    pub fn set_focus_distance(&mut self, distance: f64) -> Option<f64> {
        if distance.is_finite() && distance > 0.0 {
            self.camera.focus_distance = distance.max(self.min_focus_distance());
            self.commit();
            Some(self.camera.focus_distance)
        } else {
            None
        }
    }

    /// Each step moves the focus 2^(1/8) times farther (negative: nearer).
    pub fn step_focus(&mut self, steps: f64) {
        let factor = 2f64.powf(steps / FOCUS_STEPS_PER_OCTAVE);
        let _ = self.set_focus_distance(self.camera.focus_distance * factor);
    }

    /// Positive steps open the aperture. Physical units: third f-stops (N divided by 2^(1/6) per
    /// step, within [0.5, 64]); a real lens: the same, within its widest and f/22. World units:
    /// the radius times 2^(1/3) per step; from a pinhole the first step opens to a small radius
    /// for the scene, and closing below it gives a pinhole.
    pub fn step_aperture(&mut self, steps: i32) {
        let smallest = SMALLEST_APERTURE_PER_RADIUS * self.scene_radius;
        // N grows by sqrt 2 per stop (the aperture area halves).
        let f_factor = 2f64.powf(-(steps as f64) * F_STOPS_PER_STEP * 0.5);
        match &mut self.camera.lens {
            RigLens::Physical(lens) => {
                lens.f_number =
                    (lens.f_number * f_factor).clamp(F_NUMBER_RANGE.0, F_NUMBER_RANGE.1);
            }
            RigLens::Real(real) => {
                let range = real.f_number_range();
                real.f_number = clamp_toward(real.f_number * f_factor, range, real.f_number);
            }
            RigLens::Aperture { radius } => {
                let factor = 2f64.powf(1.0 / APERTURE_STEPS_PER_OCTAVE);
                for _ in 0..steps.unsigned_abs() {
                    *radius = if steps > 0 {
                        if *radius == 0.0 {
                            smallest
                        } else {
                            *radius * factor
                        }
                    } else if *radius / factor < smallest * (1.0 - 1e-9) {
                        // The tolerance keeps rounding from closing the smallest radius times one
                        // step straight to a pinhole.
                        0.0
                    } else {
                        *radius / factor
                    };
                }
            }
        }
        self.commit();
    }

    /// Sets the focal length, switching to physical units (keeping the f-number and sensor when
    /// already physical, else f/2.8 on a full-frame sensor). The focus stays beyond the lens's
    /// focal length.
    pub fn set_focal_length_mm(&mut self, focal_length_mm: f64) {
        if !(focal_length_mm.is_finite() && focal_length_mm > 0.0) {
            return;
        }
        self.camera.lens = RigLens::Physical(match &self.camera.lens {
            RigLens::Physical(lens) => PhysicalLens {
                focal_length_mm,
                ..*lens
            },
            RigLens::Real(real) => PhysicalLens {
                focal_length_mm,
                f_number: real.f_number,
                sensor_height_mm: real.sensor_height_mm,
            },
            RigLens::Aperture { .. } => PhysicalLens {
                focal_length_mm,
                f_number: DEFAULT_F_NUMBER,
                sensor_height_mm: DEFAULT_SENSOR_HEIGHT_MM,
            },
        });
        let focus = self.camera.focus_distance;
        self.camera.focus_distance = focus.max(self.min_focus_distance());
        self.commit();
    }

    /// Sets the f-number (clamped to [0.5, 64], a real lens's to its widest and f/22); only
    /// physical units and real lenses have one, so with a world-unit lens nothing changes.
    pub fn set_f_number(&mut self, f_number: f64) {
        if !f_number.is_finite() {
            return;
        }
        match &mut self.camera.lens {
            RigLens::Physical(lens) => {
                lens.f_number = f_number.clamp(F_NUMBER_RANGE.0, F_NUMBER_RANGE.1);
            }
            RigLens::Real(real) => {
                real.f_number = clamp_toward(f_number, real.f_number_range(), real.f_number);
            }
            RigLens::Aperture { .. } => return,
        }
        self.commit();
    }

    /// Sets the sensor (film) height in mm, within 1 to 200 mm; only physical units and real
    /// lenses have one.
    pub fn set_sensor_height_mm(&mut self, height_mm: f64) {
        if !height_mm.is_finite() {
            return;
        }
        let (lo, hi) = SENSOR_HEIGHT_RANGE_MM;
        match &mut self.camera.lens {
            RigLens::Physical(lens) => lens.sensor_height_mm = height_mm.clamp(lo, hi),
            RigLens::Real(real) => real.sensor_height_mm = height_mm.clamp(lo, hi),
            RigLens::Aperture { .. } => return,
        }
        self.commit();
    }

    /// Turns a real lens's dispersion on or off (the others have none).
    pub fn set_dispersion(&mut self, on: bool) {
        match &mut self.camera.lens {
            RigLens::Real(real) if real.dispersion != on => real.dispersion = on,
            _ => return,
        }
        self.commit();
    }

    /// What the lens picker offers: the thin lens, each built-in lens, and the file the
    /// preview started with.
    pub fn lens_choices(&self) -> Vec<LensChoice> {
        let mut choices = vec![LensChoice::Thin];
        choices.extend(
            lensray_core::optics::builtin::names()
                .into_iter()
                .map(|n| LensChoice::Real(n.to_owned())),
        );
        choices.extend(self.files.iter().map(|(n, _)| LensChoice::Real(n.clone())));
        choices
    }

    /// The lens in use, as the picker names it.
    pub fn lens_choice(&self) -> LensChoice {
        match &self.camera.lens {
            RigLens::Real(real) => LensChoice::Real(real.prescription.clone()),
            _ => LensChoice::Thin,
        }
    }

    /// Picks the lens: the thin lens last used, or a real lens by its name in the settings (a
    /// built-in name or the file the preview started with; another name changes nothing).
    /// A real lens needs the perspective projection (the view switches to it, framing kept);
    /// it keeps the f-number and sensor of the lens before where it can (clamped to its
    /// range; a world-unit lens gives it its widest f-number), and the focus, no nearer than
    /// it reaches.
    pub fn set_lens(&mut self, choice: &LensChoice) {
        if *choice == self.lens_choice() {
            return;
        }
        let lens = match choice {
            LensChoice::Thin => self.thin.clone(),
            LensChoice::Real(name) => {
                let prescription = match lensray_core::optics::builtin::lens(name) {
                    Some(lens) => lens,
                    None => match self.files.iter().find(|(n, _)| n == name) {
                        Some((_, lens)) => Prescription::clone(lens),
                        None => return,
                    },
                };
                let (f_number, sensor, dispersion) = match &self.camera.lens {
                    RigLens::Physical(l) => (Some(l.f_number), l.sensor_height_mm, true),
                    RigLens::Real(r) => (Some(r.f_number), r.sensor_height_mm, r.dispersion),
                    RigLens::Aperture { .. } => (None, DEFAULT_SENSOR_HEIGHT_MM, true),
                };
                let mut real = RealRigLens::new(name.clone(), prescription, None, sensor);
                real.dispersion = dispersion;
                if let Some(n) = f_number {
                    let (lo, hi) = real.f_number_range();
                    real.f_number = n.clamp(lo, hi);
                }
                self.set_projection(ProjectionKind::Perspective);
                RigLens::Real(real)
            }
        };
        if !matches!(self.camera.lens, RigLens::Real(_)) {
            self.thin = self.camera.lens.clone();
        }
        self.camera.lens = lens;
        self.camera.focus_distance = self.camera.focus_distance.max(self.min_focus_distance());
        self.commit();
    }

    /// The aperture's shape as the settings give it.
    pub fn aperture(&self) -> ApertureSettings {
        self.settings.camera.aperture.clone()
    }

    /// Sets the aperture's shape; a value `lensray render` would refuse leaves it unchanged.
    pub fn set_aperture(&mut self, aperture: ApertureSettings) {
        let blades_ok = aperture
            .blades
            .is_none_or(|n| (3..=lensray_core::camera::aperture::MAX_BLADES).contains(&n));
        let roundness_ok = aperture.roundness.is_none_or(|r| (0.0..=1.0).contains(&r));
        let aspect_ok = aperture.aspect.is_none_or(|a| a.is_finite() && a > 0.0);
        let rotation_ok = aperture.rotation.is_none_or(f64::is_finite);
        if blades_ok && roundness_ok && aspect_ok && rotation_ok {
            self.settings.camera.aperture = aperture;
        }
    }

    /// Sets the aperture radius in world units (0 = pinhole), switching from physical units to
    /// world units with the field of view the lens had, so the framing stays.
    pub fn set_aperture_radius(&mut self, radius: f64) {
        if !(radius.is_finite() && radius >= 0.0) {
            return;
        }
        self.camera.vfov_degrees = self.camera.vfov_radians().to_degrees();
        self.camera.lens = RigLens::Aperture { radius };
        self.commit();
    }

    /// Switches projection keeping the framing at the target: orthographic shows the height the
    /// perspective view shows at the target's distance (as `settings::shot` does by default);
    /// back in perspective, the eye moves along the view axis to where that height fills the
    /// view (the field of view is the lens's, so it stays). A real lens stays perspective.
    pub fn set_projection(&mut self, projection: ProjectionKind) {
        let cam = &mut self.camera;
        if cam.projection == projection || matches!(cam.lens, RigLens::Real(_)) {
            return;
        }
        match projection {
            ProjectionKind::Orthographic => cam.ortho_height = cam.view_height_at_target(),
            ProjectionKind::Perspective => {
                let distance = cam.ortho_height / (2.0 * (0.5 * cam.vfov_radians()).tan());
                cam.eye = cam.target - distance * cam.frame().forward;
            }
        }
        cam.projection = projection;
        self.commit();
    }

    pub fn toggle_projection(&mut self) {
        self.set_projection(match self.camera.projection {
            ProjectionKind::Perspective => ProjectionKind::Orthographic,
            ProjectionKind::Orthographic => ProjectionKind::Perspective,
        });
    }
}
