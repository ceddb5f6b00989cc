//! Settings (file overridden by command line) + scene -> a validated camera and render settings.
//! What neither gives gets a default; a scene without a camera position is framed automatically
//! (`super::framing`), focused at its centre.

use glam::{DVec3, Vec3};
use thiserror::Error;

use std::sync::Arc;

use crate::camera::look_at::CameraFrame;
use crate::camera::movements::TiltModel;
use crate::camera::physical::{PhysicalLens, MM_PER_WORLD_UNIT};
use crate::camera::{
    Aperture, ApertureShape, Camera, CameraError, CameraParams, LensParams, Movements,
    ProjectionParams, RealLensParams,
};
use crate::interface::MAX_BOUNCES;
use crate::optics::Prescription;
use crate::scene::{Bounds, Scene};
use crate::settings::{ApertureSettings, CameraSettings, ProjectionKind, Settings, Switch};
use crate::settings::{EnvironmentSetting, RenderSettings, Shading};

use super::framing::{framing_vfov_degrees, view, View};

pub const DEFAULT_WIDTH: u32 = 640;
pub const DEFAULT_HEIGHT: u32 = 480;
pub const DEFAULT_SPP: u32 = 16;
pub const DEFAULT_VFOV_DEGREES: f64 = 40.0;
pub const DEFAULT_F_NUMBER: f64 = 2.8;
/// Full-frame sensor height.
pub const DEFAULT_SENSOR_HEIGHT_MM: f64 = 24.0;
const DEFAULT_BACKGROUND: [f64; 3] = [0.1, 0.1, 0.1];

#[derive(Debug, Error, PartialEq)]
pub enum SettingsError {
    #[error(transparent)]
    Camera(#[from] CameraError),
    #[error("{0} must be finite and not negative, got {1:?}")]
    BadColour(&'static str, [f64; 3]),
    #[error("{0} must be finite, got {1:?}")]
    NotFinite(&'static str, [f64; 3]),
    #[error("spp must be at least 1")]
    ZeroSpp,
    #[error("{0}")]
    Conflict(&'static str),
    #[error("the scene has no triangles to frame")]
    EmptyScene,
    #[error(transparent)]
    ApertureImage(#[from] super::aperture_image::ApertureImageFileError),
    #[error("{0}")]
    Lens(String),
    #[error("{0}")]
    Light(String),
    #[error("{err}; {chosen_by} chose it (does --scene-units match the scene's units?)")]
    Focus {
        chosen_by: FocusChoice,
        err: CameraError,
    },
    #[error("{0}")]
    Exposure(String),
    #[error("{0}")]
    Environment(String),
    #[error("noise_threshold must be a positive finite number (say 0.01), got {0}")]
    NoiseThreshold(f64),
    #[error("fps must be a positive number up to 1000, got {0}")]
    Fps(f64),
    #[error("{0} must be a finite number, got {1}")]
    NotANumber(String, f64),
    #[error("{0}")]
    Shutter(String),
}

/// What chose a shot's focus distance, for an error that no image forms there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FocusChoice {
    /// The settings' focus distance: `--focus-distance`, or the scene file's.
    Setting,
    /// The depth of the target the camera looks at: the file's camera's, or `--eye`/`--target`.
    Target,
    /// The automatic framing: the depth of the scene's centre.
    Framing,
}

impl FocusChoice {
    fn of(c: &CameraSettings) -> Self {
        match (c.focus_distance, c.eye) {
            (Some(_), _) => Self::Setting,
            (None, Some(_)) => Self::Target,
            (None, None) => Self::Framing,
        }
    }
}

impl std::fmt::Display for FocusChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Setting => "the focus distance setting (--focus-distance or the scene file's)",
            Self::Target => {
                "the depth of the camera's target (the file's camera, or --eye and --target)"
            }
            Self::Framing => "the automatic framing (the depth of the scene's centre)",
        })
    }
}

impl From<crate::camera::RealLensError> for SettingsError {
    fn from(e: crate::camera::RealLensError) -> Self {
        SettingsError::Camera(e.into())
    }
}

/// What a user's settings resolve to: the camera and the render settings of one image.
#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    pub camera: Camera,
    pub render: RenderSettings,
}

fn vec3(v: [f64; 3]) -> Vec3 {
    DVec3::from_array(v).as_vec3()
}

pub(super) fn colour(name: &'static str, v: [f64; 3]) -> Result<Vec3, SettingsError> {
    if v.iter().all(|c| c.is_finite() && *c >= 0.0) {
        Ok(vec3(v))
    } else {
        Err(SettingsError::BadColour(name, v))
    }
}

pub(super) fn point(name: &'static str, v: [f64; 3]) -> Result<Vec3, SettingsError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(vec3(v))
    } else {
        Err(SettingsError::NotFinite(name, v))
    }
}

/// The aperture of `a` (round where it names no blades), each value checked.
fn aperture(a: &ApertureSettings) -> Result<Aperture, SettingsError> {
    if a.blades.is_some() && a.image.is_some() {
        return Err(SettingsError::Conflict(
            "give either aperture blades or an aperture image, not both",
        ));
    }
    let image = a
        .image
        .as_deref()
        .map(super::aperture_image::load)
        .transpose()?;
    Ok(ApertureShape {
        blades: a.blades,
        rotation_degrees: a.rotation.unwrap_or(0.0) as f32,
        roundness: a.roundness.unwrap_or(0.0) as f32,
        aspect: a.aspect.unwrap_or(1.0) as f32,
        image,
    }
    .build()?)
}

/// The real lens the settings name, if any (a built-in name or a prescription file).
fn prescription(c: &CameraSettings) -> Result<Option<Prescription>, SettingsError> {
    let Some(name) = &c.lens.prescription else {
        return Ok(None);
    };
    if c.aperture_radius.is_some() || c.focal_length_mm.is_some() {
        return Err(SettingsError::Conflict(
            "give either a real lens (--lens) or a thin lens (aperture radius or focal length), not both",
        ));
    }
    if c.projection == Some(ProjectionKind::Orthographic) {
        return Err(SettingsError::Conflict(
            "a real lens (--lens) needs the perspective projection",
        ));
    }
    crate::optics::builtin::resolve(name)
        .map(Some)
        .map_err(SettingsError::Lens)
}

/// The shot of `settings` and `scene`: fills in defaults and validates everything.
pub fn shot(settings: &Settings, scene: &Scene) -> Result<Shot, SettingsError> {
    let bounds = scene.bounds().ok_or(SettingsError::EmptyScene)?;
    // A still does not use the rate or the shutter, but a bad one is still a mistake to name.
    super::keyframe::fps(settings)?;
    if let Some((key, value)) = super::finite::first_not_finite(settings) {
        return Err(SettingsError::NotANumber(key, value));
    }
    super::shutter::shutter(settings)?;
    let c = &settings.camera;
    let real_lens = prescription(c)?;
    let vfov_degrees = framing_vfov_degrees(c, real_lens.as_ref());
    let view = view(settings, scene, &bounds, real_lens.as_ref())?;
    let projection = projection(c, &view, vfov_degrees);
    let (near, far) = clip_planes(c, &bounds, &view);
    let axis_distance = (view.target - view.eye).length() as f64;
    let chosen_by = FocusChoice::of(c);
    let lens = lens(c, real_lens, axis_distance)?;

    let camera = CameraParams {
        eye: view.eye,
        target: view.target,
        up: view.up,
        projection,
        lens,
        near,
        far,
        width: settings.image.width.unwrap_or(DEFAULT_WIDTH),
        height: settings.image.height.unwrap_or(DEFAULT_HEIGHT),
        movements: movements(c)?,
    }
    .build_with_aperture(aperture(&c.aperture)?)
    .map_err(|err| match err {
        CameraError::FocusWithinFocalLength { .. } => SettingsError::Focus { chosen_by, err },
        err => err.into(),
    })?;

    let render = render_settings(settings, scene)?;
    Ok(Shot { camera, render })
}

/// The camera's frame (eye and axes) that `settings` give on `scene`: the pose of
/// [`shot`]'s camera, without building its lens.
pub fn camera_frame(settings: &Settings, scene: &Scene) -> Result<CameraFrame, SettingsError> {
    let bounds = scene.bounds().ok_or(SettingsError::EmptyScene)?;
    let real_lens = prescription(&settings.camera)?;
    let view = view(settings, scene, &bounds, real_lens.as_ref())?;
    CameraFrame::look_at(view.eye, view.target, view.up).ok_or_else(|| {
        SettingsError::Shutter(format!(
            "the camera at eye {} looking at {} with up {} has no frame",
            view.eye, view.target, view.up
        ))
    })
}

/// Where the default lights go (`lights::settings_lights`): the eye, the camera's up, the
/// target and the radius of the scene's bounding sphere.
pub(super) struct Framing {
    pub eye: Vec3,
    pub true_up: Vec3,
    pub target: Vec3,
    pub radius: f64,
}

/// The framing of the shot `settings` give `scene`.
pub(super) fn framing(settings: &Settings, scene: &Scene) -> Result<Framing, SettingsError> {
    let camera = shot(settings, scene)?.camera;
    let bounds = scene.bounds().ok_or(SettingsError::EmptyScene)?;
    let radius = (0.5 * bounds.diagonal().length()).max(1e-3) as f64;
    let view = view(
        settings,
        scene,
        &bounds,
        prescription(&settings.camera)?.as_ref(),
    )?;
    Ok(Framing {
        eye: view.eye,
        true_up: camera.frame.true_up,
        target: view.target,
        radius,
    })
}

/// The projection the settings name (default: perspective).
fn projection(c: &CameraSettings, view: &View, vfov_degrees: f64) -> ProjectionParams {
    match c.projection.unwrap_or(ProjectionKind::Perspective) {
        ProjectionKind::Perspective => ProjectionParams::Perspective { vfov_degrees },
        // By default the orthographic view frames what the perspective one shows at the target.
        ProjectionKind::Orthographic => ProjectionParams::Orthographic {
            height: c.ortho_height.unwrap_or(
                2.0 * (vfov_degrees.clamp(1.0, 179.0) * 0.5).to_radians().tan()
                    * (view.target - view.eye).length() as f64,
            ),
        },
    }
}

/// Near and far: by default, from the depth of the scene along the view axis.
fn clip_planes(c: &CameraSettings, bounds: &Bounds, view: &View) -> (f64, f64) {
    let forward = (view.target - view.eye).normalize_or_zero();
    let deepest = bounds
        .corners()
        .iter()
        .map(|&p| (p - view.eye).dot(forward))
        .fold(f32::MIN, f32::max) as f64;
    let far = c.far.unwrap_or((deepest * 1.05).max(1e-2));
    let near = c.near.unwrap_or(far * 1e-4);
    (near, far)
}

/// The lens the settings describe: a real lens, a thin lens in world units or in photographic
/// ones, or a pinhole; by default focused at `axis_distance`, the target's.
fn lens(
    c: &CameraSettings,
    real_lens: Option<Prescription>,
    axis_distance: f64,
) -> Result<LensParams, SettingsError> {
    // Without a focal length, an f-number is allowed with a shutter time: it sets the exposure
    // alone (settings::exposure).
    let exposure_f_number = c.f_number.is_some() && c.exposure.shutter.is_some();
    if c.focal_length_mm.is_none()
        && real_lens.is_none()
        && ((c.f_number.is_some() && !exposure_f_number) || c.sensor_height_mm.is_some())
    {
        return Err(SettingsError::Conflict(
            "f-number and sensor height need a focal length (--focal-length-mm) or a lens (--lens)",
        ));
    }
    Ok(match (c.aperture_radius, c.focal_length_mm) {
        _ if real_lens.is_some() => LensParams::Real(RealLensParams {
            prescription: Arc::new(real_lens.expect("checked")),
            f_number: c.f_number,
            focus_distance: c.focus_distance.unwrap_or(axis_distance),
            sensor_height_mm: c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM),
            dispersion: c.lens.dispersion != Some(Switch::Off),
            movements: crate::camera::Movements::NONE,
        }),
        (Some(_), Some(_)) => {
            return Err(SettingsError::Conflict(
                "give either an aperture radius or a focal length (physical units), not both",
            ))
        }
        (Some(aperture_radius), None) => LensParams::ThinLens {
            aperture_radius,
            focus_distance: c.focus_distance.unwrap_or(axis_distance),
        },
        (None, Some(focal_length_mm)) => LensParams::Physical {
            lens: PhysicalLens {
                focal_length_mm,
                f_number: c.f_number.unwrap_or(DEFAULT_F_NUMBER),
                sensor_height_mm: c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM),
            },
            focus_distance: c.focus_distance.unwrap_or(axis_distance),
        },
        (None, None) => match c.focus_distance {
            Some(focus_distance) => LensParams::ThinLens {
                aperture_radius: 0.0,
                focus_distance,
            },
            None => LensParams::Pinhole,
        },
    })
}

/// Shift and tilt. A plane of focus through three pixels (`focus_plane`) is the app's to
/// solve before the shot (it needs the surfaces under them): here it must be gone, or given
/// alone.
fn movements(c: &CameraSettings) -> Result<Movements, SettingsError> {
    if c.focus_plane.is_some() && (c.tilt.is_some() || c.tilt_direction.is_some()) {
        return Err(SettingsError::Conflict(
            "give either a focus plane (three points) or a tilt and tilt direction, not both",
        ));
    }
    Ok(Movements {
        shift: c.shift.unwrap_or([0.0, 0.0]),
        tilt_degrees: c.tilt.unwrap_or(0.0),
        tilt_direction_degrees: c.tilt_direction.unwrap_or(0.0),
    })
}

/// How the settings' lens, built as `camera`, tilts (`camera::movements`): by the hinge rule
/// for a perspective lens with a focal length (a real lens's: its efl), by the plane's own
/// angle otherwise.
pub fn tilt_model(c: &CameraSettings, camera: &crate::camera::Camera) -> TiltModel {
    if let Some(real) = camera.lens.real() {
        return TiltModel::FocalLength(real.first_order.efl / MM_PER_WORLD_UNIT);
    }
    let perspective = c.projection != Some(ProjectionKind::Orthographic);
    match c.focal_length_mm {
        Some(f) if perspective && c.aperture_radius.is_none() => {
            TiltModel::FocalLength(f / MM_PER_WORLD_UNIT)
        }
        _ => TiltModel::PlaneAngle,
    }
}

/// Adaptive sampling's threshold, checked: positive and finite (in f32 too).
fn noise_threshold(settings: &Settings) -> Result<Option<f32>, SettingsError> {
    match settings.render.noise_threshold {
        None => Ok(None),
        Some(t) if t.is_finite() && t > 0.0 && (t as f32) > 0.0 && (t as f32).is_finite() => {
            Ok(Some(t as f32))
        }
        Some(t) => Err(SettingsError::NoiseThreshold(t)),
    }
}

/// The surfaces a lit path shades where the settings name none: enough for a path through a
/// glass volume to meet what is behind it and that surface's light (in, out, the surface)
/// where the scene transmits light, else 1 (direct light).
pub const GLASS_BOUNCES: u32 = 4;

/// Samples, seed, sampler, shading, background and environment, each checked.
fn render_settings(settings: &Settings, scene: &Scene) -> Result<RenderSettings, SettingsError> {
    let spp = settings.image.spp.unwrap_or(DEFAULT_SPP);
    if spp == 0 {
        return Err(SettingsError::ZeroSpp);
    }
    let environment = super::environment::sky_radiance(settings)?;
    let map = matches!(
        settings.render.environment,
        Some(EnvironmentSetting::Map(_))
    );
    let transmits = scene.materials.iter().any(|m| m.transmission > 0.0);
    let bounces = settings
        .render
        .bounces
        .unwrap_or(if transmits { GLASS_BOUNCES } else { 1 });
    if !(1..=MAX_BOUNCES).contains(&bounces) {
        return Err(SettingsError::Environment(format!(
            "bounces must be 1 to {MAX_BOUNCES}, got {bounces}"
        )));
    }
    Ok(RenderSettings {
        spp,
        seed: settings.image.seed.unwrap_or(0),
        sampler: settings.image.sampler.unwrap_or_default(),
        shading: settings.render.shading.unwrap_or(Shading::Lit),
        // The sky the environment lights with is what a ray that leaves the scene sees.
        background: match (settings.render.background, environment) {
            (Some(b), _) => colour("background", b)?,
            (None, Some(e)) => e,
            (None, None) => colour("background", DEFAULT_BACKGROUND)?,
        },
        environment: environment.unwrap_or(Vec3::ZERO),
        environment_seen: map && settings.render.background.is_none(),
        bounces,
        shared_samples: false,
        noise_threshold: noise_threshold(settings)?,
    })
}
