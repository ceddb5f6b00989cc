//! The interactive camera of `lensray preview`: mouse and keyboard motions applied to the camera
//! part of [`Settings`], so the window resolves its camera exactly as `lensray render` would and
//! any frame can be reproduced headless.
//!
//! At construction the camera is resolved once and pinned: eye, target, up, projection, field of
//! view or orthographic height, focus distance and lens become explicit values, so later motions
//! never depend on defaults that follow the eye. Near and far stay as the user gave them (when not
//! given, `resolve` derives them for the current eye, which is what a moving camera needs).
//!
//! The lens is a thin lens (world units or photographic ones) or a real lens (issue 21: a
//! built-in prescription or a file, `--lens`), picked in the panel: a real lens keeps its
//! f-number between its widest and f/22, and its focus beyond the nearest it reaches, so every
//! motion leaves a camera that `lensray render` accepts.

use std::sync::Arc;

use glam::{DQuat, DVec3};

use lensray_core::camera::physical::{PhysicalLens, MM_PER_WORLD_UNIT};
use lensray_core::camera::Projection;
use lensray_core::optics::paraxial::FirstOrder;
use lensray_core::optics::Prescription;
use lensray_core::scene::Scene;
use lensray_core::settings::{
    shot, SettingsError, Shot, DEFAULT_F_NUMBER, DEFAULT_SENSOR_HEIGHT_MM, DEFAULT_VFOV_DEGREES,
};
use lensray_core::settings::{ApertureSettings, ProjectionKind, Settings};

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

/// The lens, in the units the user chose.
#[derive(Clone, Debug, PartialEq)]
enum Lens {
    /// World units; 0 is a pinhole.
    Aperture { radius: f64 },
    /// Photographic units; the field of view follows the lens (see `camera::physical`).
    Physical(PhysicalLens),
    /// A lens prescription traced surface by surface (`camera::real_lens`).
    Real(RealRigLens),
}

/// A real lens as the rig holds it: what the settings name, and its first-order data for the
/// limits (widest f-number, nearest focus) and the framing.
#[derive(Clone, Debug, PartialEq)]
struct RealRigLens {
    /// As the settings give it: a built-in name or a prescription file.
    prescription: String,
    lens: Arc<Prescription>,
    first_order: FirstOrder,
    f_number: f64,
    sensor_height_mm: f64,
}

impl RealRigLens {
    fn new(prescription: String, lens: Prescription, f_number: Option<f64>, sensor: f64) -> Self {
        let first_order = FirstOrder::of(&lens);
        RealRigLens {
            prescription,
            lens: Arc::new(lens),
            f_number: f_number.unwrap_or(first_order.f_number),
            first_order,
            sensor_height_mm: sensor,
        }
    }

    /// The f-numbers the steps and the panel allow: the lens's widest to f/22 (a value given
    /// outside stays until changed: `RealLens` accepts a marked f-number a little wider).
    fn f_number_range(&self) -> (f64, f64) {
        let widest = self.first_order.f_number;
        (widest, REAL_F_NUMBER_MAX.max(widest))
    }

    /// Nearest focus distance from the entrance pupil, world units (see
    /// `REAL_MAX_MAGNIFICATION`; never at or inside the front focal point, nor behind the
    /// first vertex).
    fn nearest_focus(&self) -> f64 {
        let fo = &self.first_order;
        let entrance_pupil_z = fo.entrance_pupil.position_mm;
        // Newton: magnification m = -f / x, x the subject's distance before the front focal
        // point (lens-space z, negative toward the scene).
        let subject_z = fo.ffl - fo.efl.abs() / REAL_MAX_MAGNIFICATION;
        let limit = 1.001 * (entrance_pupil_z - fo.ffl.min(0.0));
        (entrance_pupil_z - subject_z).max(limit) / MM_PER_WORLD_UNIT
    }

    /// The vertical field of view focused at `focus_distance`, to first order (the film
    /// where Newton's equation puts it; `RealLens::pinhole_vfov` refines the film by tracing).
    fn vfov(&self, focus_distance: f64) -> f64 {
        let fo = &self.first_order;
        let subject_z = fo.entrance_pupil.position_mm - focus_distance * MM_PER_WORLD_UNIT;
        let x = (subject_z - fo.ffl).min(-1e-9);
        let film_z = self.lens.length() + fo.bfl - fo.efl * fo.efl / x;
        let exit_pupil_z = self.lens.length() + fo.exit_pupil.position_mm;
        let slope = 0.5 * self.sensor_height_mm / (film_z - exit_pupil_z)
            * fo.exit_pupil.diameter_mm
            / fo.entrance_pupil.diameter_mm;
        2.0 * slope.abs().atan()
    }

    /// Radius of the entrance pupil at the f-number, world units.
    fn entrance_pupil_radius(&self) -> f64 {
        let widest = self.first_order.f_number;
        0.5 * self.first_order.entrance_pupil.diameter_mm * widest
            / self.f_number.max(widest)
            / MM_PER_WORLD_UNIT
    }
}

/// `n` clamped to `range`, except that a value already outside it (given by the user) may
/// stay where it is or move toward the range.
fn clamp_toward(n: f64, range: (f64, f64), current: f64) -> f64 {
    n.clamp(range.0.min(current), range.1.max(current))
}

/// Everything that describes the camera, explicit.
#[derive(Clone, Debug, PartialEq)]
struct RigCamera {
    eye: DVec3,
    target: DVec3,
    /// The world up: orbit yaws about it.
    up: DVec3,
    projection: ProjectionKind,
    /// Kept while orthographic, so switching back restores it.
    vfov_degrees: f64,
    /// Meaningful while orthographic.
    ortho_height: f64,
    focus_distance: f64,
    lens: Lens,
}

/// The camera frame in f64, built as `CameraFrame::look_at` builds it.
struct Frame {
    forward: DVec3,
    right: DVec3,
    true_up: DVec3,
}

impl RigCamera {
    fn distance(&self) -> f64 {
        (self.target - self.eye).length()
    }

    fn frame(&self) -> Frame {
        let forward = (self.target - self.eye).normalize_or_zero();
        let right = forward.cross(self.up).normalize_or_zero();
        Frame {
            forward,
            right,
            true_up: right.cross(forward),
        }
    }

    /// The vertical field of view the camera has: the lens's with physical units (a real
    /// lens's to first order).
    fn vfov_radians(&self) -> f64 {
        match &self.lens {
            Lens::Physical(lens) => lens
                .vfov(self.focus_distance)
                .unwrap_or(self.vfov_degrees.to_radians()),
            Lens::Real(real) => real.vfov(self.focus_distance),
            Lens::Aperture { .. } => self.vfov_degrees.to_radians(),
        }
    }

    /// Height in world units of what the view shows at the target's distance.
    fn view_height_at_target(&self) -> f64 {
        match self.projection {
            ProjectionKind::Perspective => {
                2.0 * (0.5 * self.vfov_radians()).tan() * self.distance()
            }
            ProjectionKind::Orthographic => self.ortho_height,
        }
    }

    fn aperture_radius(&self) -> f64 {
        match &self.lens {
            Lens::Aperture { radius } => *radius,
            Lens::Physical(lens) => lens.aperture_radius(),
            Lens::Real(real) => real.entrance_pupil_radius(),
        }
    }

    /// Writes this camera into `settings` (near and far untouched).
    fn store(&self, settings: &mut Settings) {
        let c = &mut settings.camera;
        let orthographic = self.projection == ProjectionKind::Orthographic;
        c.projection = Some(self.projection);
        c.eye = Some(self.eye.to_array());
        c.target = Some(self.target.to_array());
        c.up = Some(self.up.to_array());
        c.vfov_degrees = Some(self.vfov_degrees);
        c.ortho_height = orthographic.then_some(self.ortho_height);
        c.focus_distance = Some(self.focus_distance);
        c.lens.prescription = None;
        match &self.lens {
            Lens::Aperture { radius } => {
                c.aperture_radius = Some(*radius);
                c.focal_length_mm = None;
                c.f_number = None;
                c.sensor_height_mm = None;
            }
            Lens::Physical(lens) => {
                c.aperture_radius = None;
                c.focal_length_mm = Some(lens.focal_length_mm);
                c.f_number = Some(lens.f_number);
                c.sensor_height_mm = Some(lens.sensor_height_mm);
            }
            Lens::Real(real) => {
                c.aperture_radius = None;
                c.focal_length_mm = None;
                c.f_number = Some(real.f_number);
                c.sensor_height_mm = Some(real.sensor_height_mm);
                c.lens.prescription = Some(real.prescription.clone());
            }
        }
    }
}

/// What a lens panel shows of a real lens.
#[derive(Clone, Debug, PartialEq)]
pub struct RealLensReadout {
    /// As the settings name it (the panel's picker): a built-in name or a file.
    pub prescription: String,
    /// The prescription's own name.
    pub name: String,
    /// The f-numbers it stops down through: its widest to f/22.
    pub f_number_range: (f64, f64),
    /// World units from the entrance pupil.
    pub nearest_focus: f64,
    pub focal_length_mm: f64,
}

/// What a lens panel shows.
#[derive(Clone, Debug, PartialEq)]
pub struct LensReadout {
    pub projection: ProjectionKind,
    /// Physical units only.
    pub focal_length_mm: Option<f64>,
    /// Physical units only.
    pub f_number: Option<f64>,
    /// Physical units only.
    pub sensor_height_mm: Option<f64>,
    /// World units (with physical units, f / 2N); 0 is a pinhole.
    pub aperture_radius: f64,
    /// Along the view axis, world units.
    pub focus_distance: f64,
    /// Perspective only: the field of view the camera has (the lens's with physical units).
    pub vfov_degrees: Option<f64>,
    /// Orthographic only.
    pub ortho_height: Option<f64>,
    /// Eye to target.
    pub target_distance: f64,
    /// A real lens's limits (its f-number and sensor height are `f_number` and
    /// `sensor_height_mm`).
    pub real: Option<RealLensReadout>,
}

/// What the lens picker offers: the thin lens or a real one by its name in the settings.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LensChoice {
    Thin,
    Real(String),
}

impl LensChoice {
    pub fn label(&self) -> String {
        match self {
            LensChoice::Thin => "thin lens".to_owned(),
            LensChoice::Real(name) => {
                if lensray_core::optics::builtin::lens(name).is_some() {
                    name.clone()
                } else {
                    // A file: its name, the folder on hover.
                    let path = std::path::Path::new(name);
                    path.file_name()
                        .map_or(name.clone(), |f| f.to_string_lossy().into_owned())
                }
            }
        }
    }
}

/// The preview's camera: [`Settings`] whose camera part the user moves.
#[derive(Clone, Debug)]
pub struct CameraRig {
    /// Always holds `camera` (written by `commit`).
    settings: Settings,
    camera: RigCamera,
    /// The camera the preview started with, for `reset`.
    start: RigCamera,
    /// Bounding-sphere radius: the scale of flying speed and of the smallest aperture.
    scene_radius: f64,
    /// The thin lens last used (picking "thin lens" again restores it).
    thin: Lens,
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
        // In f32, as `resolve` measures it.
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
                Lens::Real(RealRigLens::new(
                    name.clone(),
                    lens,
                    c.f_number,
                    c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM),
                ))
            }
            (None, Some(focal_length_mm)) => Lens::Physical(PhysicalLens {
                focal_length_mm,
                f_number: c.f_number.unwrap_or(DEFAULT_F_NUMBER),
                sensor_height_mm: c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM),
            }),
            (None, None) => Lens::Aperture {
                radius: c.aperture_radius.unwrap_or(0.0),
            },
        };
        // The thin lens "thin lens" picks: the one given, or for a real lens the thin lens of
        // its focal length, f-number and sensor.
        let thin = match &lens {
            Lens::Real(real) => Lens::Physical(PhysicalLens {
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
            // A pinhole gets the distance resolve would focus a lens at, for the focus controls.
            focus_distance: c.focus_distance.unwrap_or(axis_distance),
            lens,
        };
        let mut rig = Self {
            settings,
            camera: pinned.clone(),
            start: pinned,
            scene_radius: (0.5 * bounds.diagonal().length()).max(1e-3) as f64,
            thin,
            files,
        };
        rig.settings.image.width = Some(camera.width);
        rig.settings.image.height = Some(camera.height);
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

    /// Nearest focus the lens allows: beyond the focal length with physical units (no image forms
    /// inside it), a real lens's nearest (`REAL_MAX_MAGNIFICATION`), and never 0.
    fn min_focus_distance(&self) -> f64 {
        let floor = MIN_DISTANCE_PER_RADIUS * self.scene_radius;
        match &self.camera.lens {
            Lens::Physical(lens) => floor.max(1.001 * lens.focal_length_mm / MM_PER_WORLD_UNIT),
            Lens::Real(real) => floor.max(real.nearest_focus()),
            Lens::Aperture { .. } => floor,
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
            Lens::Physical(lens) => {
                lens.f_number =
                    (lens.f_number * f_factor).clamp(F_NUMBER_RANGE.0, F_NUMBER_RANGE.1);
            }
            Lens::Real(real) => {
                let range = real.f_number_range();
                real.f_number = clamp_toward(real.f_number * f_factor, range, real.f_number);
            }
            Lens::Aperture { radius } => {
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
        self.camera.lens = Lens::Physical(match &self.camera.lens {
            Lens::Physical(lens) => PhysicalLens {
                focal_length_mm,
                ..*lens
            },
            Lens::Real(real) => PhysicalLens {
                focal_length_mm,
                f_number: real.f_number,
                sensor_height_mm: real.sensor_height_mm,
            },
            Lens::Aperture { .. } => PhysicalLens {
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
            Lens::Physical(lens) => {
                lens.f_number = f_number.clamp(F_NUMBER_RANGE.0, F_NUMBER_RANGE.1);
            }
            Lens::Real(real) => {
                real.f_number = clamp_toward(f_number, real.f_number_range(), real.f_number);
            }
            Lens::Aperture { .. } => return,
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
            Lens::Physical(lens) => lens.sensor_height_mm = height_mm.clamp(lo, hi),
            Lens::Real(real) => real.sensor_height_mm = height_mm.clamp(lo, hi),
            Lens::Aperture { .. } => return,
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
            Lens::Real(real) => LensChoice::Real(real.prescription.clone()),
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
                let (f_number, sensor) = match &self.camera.lens {
                    Lens::Physical(l) => (Some(l.f_number), l.sensor_height_mm),
                    Lens::Real(r) => (Some(r.f_number), r.sensor_height_mm),
                    Lens::Aperture { .. } => (None, DEFAULT_SENSOR_HEIGHT_MM),
                };
                let mut real = RealRigLens::new(name.clone(), prescription, None, sensor);
                if let Some(n) = f_number {
                    let (lo, hi) = real.f_number_range();
                    real.f_number = n.clamp(lo, hi);
                }
                self.set_projection(ProjectionKind::Perspective);
                Lens::Real(real)
            }
        };
        if !matches!(self.camera.lens, Lens::Real(_)) {
            self.thin = self.camera.lens.clone();
        }
        self.camera.lens = lens;
        self.camera.focus_distance = self.camera.focus_distance.max(self.min_focus_distance());
        self.commit();
    }

    /// Sets the aperture radius in world units (0 = pinhole), switching from physical units to
    /// world units with the field of view the lens had, so the framing stays.
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

    pub fn set_aperture_radius(&mut self, radius: f64) {
        if !(radius.is_finite() && radius >= 0.0) {
            return;
        }
        self.camera.vfov_degrees = self.camera.vfov_radians().to_degrees();
        self.camera.lens = Lens::Aperture { radius };
        self.commit();
    }

    /// Switches projection keeping the framing at the target: orthographic shows the height the
    /// perspective view shows at the target's distance (as `resolve` does by default); back in
    /// perspective, the eye moves along the view axis to where that height fills the view (the
    /// field of view is the lens's, so it stays). A real lens stays perspective.
    pub fn set_projection(&mut self, projection: ProjectionKind) {
        let cam = &mut self.camera;
        if cam.projection == projection || matches!(cam.lens, Lens::Real(_)) {
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

    /// Back to the camera the preview started with (the image keeps the window's size).
    pub fn reset(&mut self) {
        if !matches!(self.camera.lens, Lens::Real(_)) {
            self.thin = self.camera.lens.clone();
        }
        self.camera = self.start.clone();
        self.commit();
    }

    pub fn readout(&self) -> LensReadout {
        let cam = &self.camera;
        let physical = match cam.lens {
            Lens::Physical(lens) => Some(lens),
            _ => None,
        };
        let real = match &cam.lens {
            Lens::Real(real) => Some(real),
            _ => None,
        };
        let perspective = cam.projection == ProjectionKind::Perspective;
        LensReadout {
            projection: cam.projection,
            focal_length_mm: physical.map(|l| l.focal_length_mm),
            f_number: physical.map(|l| l.f_number).or(real.map(|r| r.f_number)),
            sensor_height_mm: physical
                .map(|l| l.sensor_height_mm)
                .or(real.map(|r| r.sensor_height_mm)),
            aperture_radius: cam.aperture_radius(),
            focus_distance: cam.focus_distance,
            vfov_degrees: perspective.then(|| cam.vfov_radians().to_degrees()),
            ortho_height: (!perspective).then_some(cam.ortho_height),
            target_distance: cam.distance(),
            real: real.map(|r| RealLensReadout {
                prescription: r.prescription.clone(),
                name: r.lens.name.clone(),
                f_number_range: r.f_number_range(),
                nearest_focus: self.min_focus_distance(),
                focal_length_mm: r.first_order.efl,
            }),
        }
    }
}

#[cfg(test)]
mod tests;
