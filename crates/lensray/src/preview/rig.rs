//! The interactive camera of `lensray preview`: mouse and keyboard motions applied to the camera
//! part of [`Settings`], so the window resolves its camera exactly as `lensray render` would and
//! any frame can be reproduced headless.
//!
//! At construction the camera is resolved once and pinned: eye, target, up, projection, field of
//! view or orthographic height, focus distance and lens become explicit values, so later motions
//! never depend on defaults that follow the eye. Near and far stay as the user gave them (when not
//! given, `settings::shot` derives them for the current eye, which is what a moving camera
//! needs).
//!
//! The lens is a thin lens (world units or photographic ones) or a real lens (a built-in
//! prescription or a file, `--lens`), picked in the panel: a real lens keeps its
//! f-number between its widest and f/22, and its focus beyond the nearest it reaches, so every
//! motion leaves a camera that `lensray render` accepts.

use std::sync::Arc;

use glam::DVec3;

use lensray_core::camera::physical::PhysicalLens;
use lensray_core::camera::{Camera, Movements, Projection};
use lensray_core::film::tonemap::ToneMap;
use lensray_core::optics::Prescription;
use lensray_core::scene::Scene;
use lensray_core::settings::{exposure, Exposure, ExposureSettings};
use lensray_core::settings::{pinned_lights, ProjectionKind, Settings, Switch};
use lensray_core::settings::{
    shot, SettingsError, Shot, DEFAULT_F_NUMBER, DEFAULT_SENSOR_HEIGHT_MM, DEFAULT_VFOV_DEGREES,
};

/// Orbit rate of a left drag.
pub const ORBIT_DEGREES_PER_PIXEL: f64 = 0.3;
/// Orbiting stops this far from the poles of the world up, so the view never flips.
pub const MAX_ELEVATION_DEGREES: f64 = 89.0;
/// One wheel step brings the eye this fraction of the way (0.9 of the distance remains).
pub const DOLLY_FACTOR_PER_STEP: f64 = 0.9;
/// Focus steps per doubling of the focus distance.
pub const FOCUS_STEPS_PER_OCTAVE: f64 = 8.0;
/// Stops per aperture step with physical units: third stops (N times 2^(1/6) per step).
pub const F_STOPS_PER_STEP: f64 = 1.0 / 3.0;
/// The f-numbers the aperture steps and the panel allow.
pub const F_NUMBER_RANGE: (f64, f64) = (0.5, 64.0);
/// A real lens stops down from its widest f-number to this one.
pub const REAL_F_NUMBER_MAX: f64 = 22.0;
/// A real lens focuses no nearer than where it images at this magnification (1:1, a macro
/// lens's limit; nearer, the film runs off toward infinity as the subject nears the front
/// focal point, where the lens cannot focus at all).
pub const REAL_MAX_MAGNIFICATION: f64 = 1.0;
/// The sensor heights the panel allows, mm.
pub const SENSOR_HEIGHT_RANGE_MM: (f64, f64) = (1.0, 200.0);
/// Aperture-radius steps per doubling (world-unit lens).
pub const APERTURE_STEPS_PER_OCTAVE: f64 = 3.0;
/// The first aperture above a pinhole, relative to the scene's bounding-sphere radius.
pub const SMALLEST_APERTURE_PER_RADIUS: f64 = 0.002;
/// Closest the eye may come to the target, relative to the scene radius (eye = target is no
/// camera at all).
const MIN_DISTANCE_PER_RADIUS: f64 = 1e-4;

mod camera;
mod lens;
mod lens_controls;
mod movements;
mod navigation;
mod readout;

pub use lens::LensChoice;
pub use movements::PANEL_MAX_TILT_DEGREES;
pub use readout::{LensReadout, RealLensReadout};

use camera::RigCamera;
use lens::{RealRigLens, RigLens};

/// The preview's camera: [`Settings`] whose camera part the user moves.
#[derive(Clone, Debug)]
pub struct CameraRig {
    /// Always holds `camera` (written by `commit`).
    settings: Settings,
    camera: RigCamera,
    /// The camera the preview started with, for `reset`.
    start: RigCamera,
    /// The last camera that resolved (`accept`), which `revert` goes back to.
    accepted: RigCamera,
    /// Bounding-sphere radius: the scale of flying speed and of the smallest aperture.
    scene_radius: f64,
    /// The thin lens last used (picking "thin lens" again restores it).
    thin: RigLens,
    /// Real lenses the picker offers beyond the built-in ones: the file the preview started
    /// with.
    files: Vec<(String, Arc<Prescription>)>,
}

impl CameraRig {
    /// Pins the camera that `settings` resolve to for `scene`.
    pub fn new(settings: Settings, scene: &Scene) -> Result<Self, SettingsError> {
        let Shot { camera, render: _ } = shot(&settings, scene)?;
        let bounds = scene.bounds().ok_or(SettingsError::EmptyScene)?;
        let c = &settings.camera;
        // Given values are kept as given (f64); derived ones come from the resolved camera, whose
        // f32 values convert back exactly, so the pinned settings resolve to the same camera.
        let eye = c.eye.map_or(camera.frame.eye.as_dvec3(), DVec3::from_array);
        let target = c
            .target
            .map_or(bounds.center().as_dvec3(), DVec3::from_array);
        // In f32, as `settings::shot` measures it.
        let axis_distance = (target.as_vec3() - camera.frame.eye).length() as f64;
        let mut files = Vec::new();
        let lens = match (&c.lens.prescription, c.focal_length_mm) {
            (Some(name), _) => {
                // `shot` read it already.
                let lens =
                    lensray_core::optics::builtin::resolve(name).map_err(SettingsError::Lens)?;
                if lensray_core::optics::builtin::lens(name).is_none() {
                    files.push((name.clone(), Arc::new(lens.clone())));
                }
                let mut real = RealRigLens::new(
                    name.clone(),
                    lens,
                    c.f_number,
                    c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM),
                );
                real.dispersion = c.lens.dispersion != Some(Switch::Off);
                RigLens::Real(real)
            }
            (None, Some(focal_length_mm)) => RigLens::Physical(PhysicalLens {
                focal_length_mm,
                f_number: c.f_number.unwrap_or(DEFAULT_F_NUMBER),
                sensor_height_mm: c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM),
            }),
            (None, None) => RigLens::Aperture {
                radius: c.aperture_radius.unwrap_or(0.0),
            },
        };
        // The thin lens "thin lens" picks: the one given, or for a real lens the thin lens of
        // its focal length, f-number and sensor.
        let thin = match &lens {
            RigLens::Real(real) => RigLens::Physical(PhysicalLens {
                focal_length_mm: real.first_order.efl,
                f_number: real.f_number,
                sensor_height_mm: real.sensor_height_mm,
            }),
            thin => thin.clone(),
        };
        let pinned = RigCamera {
            eye,
            target,
            up: c.up.map_or(DVec3::Y, DVec3::from_array),
            projection: c.projection.unwrap_or(ProjectionKind::Perspective),
            vfov_degrees: c.vfov_degrees.unwrap_or(DEFAULT_VFOV_DEGREES),
            ortho_height: match camera.projection {
                Projection::Orthographic { height } => c.ortho_height.unwrap_or(height as f64),
                Projection::Perspective { .. } => 0.0,
            },
            // A pinhole gets the distance `settings::shot` would focus a lens at, for the focus
            // controls.
            focus_distance: c.focus_distance.unwrap_or(axis_distance),
            lens,
            movements: Movements {
                shift: c.shift.unwrap_or([0.0, 0.0]),
                tilt_degrees: c.tilt.unwrap_or(0.0),
                tilt_direction_degrees: c.tilt_direction.unwrap_or(0.0),
            },
        };
        let mut rig = Self {
            settings,
            camera: pinned.clone(),
            accepted: pinned.clone(),
            start: pinned,
            scene_radius: (0.5 * bounds.diagonal().length()).max(1e-3) as f64,
            thin,
            files,
        };
        rig.settings.image.width = Some(camera.width);
        rig.settings.image.height = Some(camera.height);
        // The lights stay where the first view put them while the camera moves.
        rig.settings.light = pinned_lights(&rig.settings, scene)?;
        rig.commit();
        // The pinned camera must resolve too: a pinhole's new focus distance must lie beyond an
        // orthographic near plane the user gave.
        rig.shot(scene)?;
        Ok(rig)
    }

    /// The settings the current view resolves from: the scene file's and the command line's,
    /// with the camera part explicit.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The camera and render settings of the current view, exactly as `lensray render` would
    /// resolve [`CameraRig::settings`].
    pub fn shot(&self, scene: &Scene) -> Result<Shot, SettingsError> {
        shot(&self.settings, scene)
    }

    /// The exposure and tone map of the current view (`settings::exposure`): what the final
    /// view and a PNG screenshot show.
    pub fn exposure(&self, camera: &Camera) -> Result<Exposure, SettingsError> {
        exposure(&self.settings, camera)
    }

    /// Exposure and tone map as set (`[camera.exposure]`): the panel edits `ev` and `tonemap`.
    pub fn exposure_settings(&self) -> &ExposureSettings {
        &self.settings.camera.exposure
    }

    /// The lens's own light the final view adds once converged (`--flare`, `--starburst`).
    pub fn set_flare(&mut self, switches: lensray_core::camera::flare::FlareSwitches) {
        let switch = |on: bool| Some(if on { Switch::On } else { Switch::Off });
        self.settings.camera.lens.flare = switch(switches.ghosts);
        self.settings.camera.lens.starburst = switch(switches.starburst);
    }

    /// Stops on top of the physical exposure, or alone (0: none).
    pub fn set_exposure_ev(&mut self, ev: f64) {
        self.settings.camera.exposure.ev = (ev != 0.0).then_some(ev);
    }

    pub fn set_tonemap(&mut self, tonemap: ToneMap) {
        self.settings.camera.exposure.tonemap = Some(tonemap);
    }

    /// Whether motion blur is on (`--motion-blur`, the B key).
    pub fn motion_blur(&self) -> bool {
        self.settings.camera.shutter.motion_blur == Some(Switch::On)
    }

    /// Turns motion blur on where it was off and off where it was on; whether it is on now.
    pub fn toggle_motion_blur(&mut self) -> bool {
        let shutter = &mut self.settings.camera.shutter;
        let on = shutter.motion_blur != Some(Switch::On);
        shutter.motion_blur = Some(if on { Switch::On } else { Switch::Off });
        on
    }

    /// Bounding-sphere radius of the scene.
    pub fn scene_radius(&self) -> f64 {
        self.scene_radius
    }

    /// The window size drives the image size; a minimised window (0) keeps at least one pixel.
    pub fn set_image_size(&mut self, width: u32, height: u32) {
        self.settings.image.width = Some(width.max(1));
        self.settings.image.height = Some(height.max(1));
    }

    fn image_height(&self) -> f64 {
        self.settings.image.height.unwrap_or(1).max(1) as f64
    }

    fn commit(&mut self) {
        self.camera.store(&mut self.settings);
    }

    /// The current camera resolved: later changes that do not resolve go back to it.
    pub fn accept(&mut self) {
        self.accepted = self.camera.clone();
    }

    /// Back to the last camera that resolved ([`Self::accept`]): a change the settings refuse
    /// (a tilt whose plane of focus reaches the lens) is undone.
    pub fn revert(&mut self) {
        self.camera = self.accepted.clone();
        self.commit();
    }

    /// Back to the camera the preview started with (the image keeps the window's size).
    pub fn reset(&mut self) {
        if !matches!(self.camera.lens, RigLens::Real(_)) {
            self.thin = self.camera.lens.clone();
        }
        self.camera = self.start.clone();
        self.commit();
    }
}

#[cfg(test)]
mod tests;
