//! Settings a user may give in a scene file or on the command line. Every field is optional:
//! the command line overrides the file, and what neither gives gets a default (see
//! `shot::shot`). Field names are the scene file's TOML keys.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::film::tonemap::ToneMap;
use crate::sampler::SamplerKind;
use crate::settings::{EnvironmentSetting, Lights, Shading};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ProjectionKind {
    Perspective,
    Orthographic,
}

impl ProjectionKind {
    pub const ALL: [ProjectionKind; 2] = [Self::Perspective, Self::Orthographic];

    /// The name `--projection` and `projection` take.
    pub fn name(self) -> &'static str {
        match self {
            Self::Perspective => "perspective",
            Self::Orthographic => "orthographic",
        }
    }
}

#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSettings {
    pub projection: Option<ProjectionKind>,
    pub eye: Option<[f64; 3]>,
    pub target: Option<[f64; 3]>,
    pub up: Option<[f64; 3]>,
    pub vfov_degrees: Option<f64>,
    pub ortho_height: Option<f64>,
    pub aperture_radius: Option<f64>,
    pub focus_distance: Option<f64>,
    pub focal_length_mm: Option<f64>,
    pub f_number: Option<f64>,
    pub sensor_height_mm: Option<f64>,
    pub near: Option<f64>,
    pub far: Option<f64>,
    /// The film window's shift off the axis `[x, y]` (`camera::movements`): mm on the film
    /// for a lens with a focal length, a fraction of the image height otherwise; +x right,
    /// +y up.
    pub shift: Option<[f64; 2]>,
    /// The lens's tilt against the film, degrees in [0, 90).
    pub tilt: Option<f64>,
    /// Where in the image the plane of focus comes nearer, degrees counter-clockwise from
    /// the image's bottom (0: like the ground).
    pub tilt_direction: Option<f64>,
    /// Three pixels `[[column, row], ...]` whose surfaces the plane of focus passes through;
    /// it sets focus distance, tilt and tilt direction (the app finds the surfaces and
    /// solves, `camera::FocusPlane`).
    pub focus_plane: Option<[[u32; 2]; 3]>,
    /// `[camera.aperture]`: the opening's shape (round when absent).
    #[serde(default, skip_serializing_if = "ApertureSettings::is_unset")]
    pub aperture: ApertureSettings,
    /// `[camera.lens]`: a real lens (a thin lens when absent).
    #[serde(default, skip_serializing_if = "LensSettings::is_unset")]
    pub lens: LensSettings,
    /// `[camera.exposure]`: exposure and tone map (as rendered, tone mapped by the default
    /// tone map, when absent).
    #[serde(default, skip_serializing_if = "ExposureSettings::is_unset")]
    pub exposure: ExposureSettings,
    /// `[camera.shutter]`: motion blur and rolling shutter (`settings::shutter`; neither when
    /// absent).
    #[serde(default, skip_serializing_if = "ShutterSettings::is_unset")]
    pub shutter: ShutterSettings,
}

/// What moves while the shutter is open (`settings::shutter` resolves it). Its time is the
/// exposure's shutter time when one is given, else the angle's share of a frame.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShutterSettings {
    /// Whether what moves during the exposure blurs (default off).
    pub motion_blur: Option<Switch>,
    /// The open share of a frame at the sequence's fps, degrees in (0, 360] (default 180);
    /// `camera.exposure.shutter`, when given, sets the time instead.
    pub angle: Option<f64>,
    /// Where the exposure lies about the frame's time (default centre).
    pub position: Option<ShutterPosition>,
    /// A rolling shutter's readout: seconds from the top row's opening to the bottom row's
    /// (default 0: every row at once).
    pub rolling: Option<f64>,
}

/// Where a frame's exposure lies about the frame's own time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ShutterPosition {
    /// Opens at the frame's time.
    Start,
    /// Centred on it (Cycles' default).
    #[serde(alias = "centre")]
    Center,
    /// Closes at it.
    End,
}

impl ShutterPosition {
    pub const ALL: [ShutterPosition; 3] = [Self::Start, Self::Center, Self::End];

    /// The name the command line and scene files take.
    pub fn name(self) -> &'static str {
        match self {
            Self::Start => "start",
            Self::Center => "center",
            Self::End => "end",
        }
    }
}

/// Exposure and tone map (`settings::exposure` resolves them, `film::tonemap` applies them):
/// a plain offset in stops, a physical exposure from shutter time, ISO and the shot's f-number,
/// the tone map of PNGs and the preview, and whether EXR files are exposed too.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ExposureSettings {
    /// Stops added on top of the physical exposure (or alone): the image is scaled by 2^ev.
    pub ev: Option<f64>,
    /// The sensor's ISO speed (needs a shutter time; default 100).
    pub iso: Option<f64>,
    /// Shutter time in seconds: with it, the image is exposed as a camera's,
    /// 1 / (1.2 * 2^EV100) with EV100 = log2(N^2 / shutter * 100 / ISO).
    pub shutter: Option<f64>,
    /// The tone map of PNG files and the preview (default agx).
    pub tonemap: Option<ToneMap>,
    /// Whether EXR files are exposed too (default: they keep the render's linear values).
    pub expose_exr: Option<bool>,
}

/// A real lens (`camera::real_lens`): its f-number, focus and film are `[camera]`'s
/// `f_number`, `focus_distance` and `sensor_height_mm`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LensSettings {
    /// A built-in lens's name (`lensray lens --help` lists them) or a prescription file (a
    /// scene file's relative path starts at its folder).
    pub prescription: Option<String>,
    /// Whether camera rays carry a wavelength through the lens's dispersive glass (default
    /// on; a lens without Abbe numbers has no dispersion either way).
    pub dispersion: Option<Switch>,
    /// Ghosts: light reflected twice inside the lens, from the image's bright sources and the
    /// punctual lights in view (`camera::flare`; default off).
    pub flare: Option<Switch>,
    /// The aperture's diffraction starburst around bright sources (default off).
    pub starburst: Option<Switch>,
}

/// On or off (`--dispersion off`, `dispersion = "off"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Switch {
    On,
    Off,
}

impl Switch {
    pub const ALL: [Switch; 2] = [Self::On, Self::Off];

    /// The name the command line and scene files take.
    pub fn name(self) -> &'static str {
        match self {
            Self::On => "on",
            Self::Off => "off",
        }
    }
}

/// The aperture's shape (`camera::aperture` states the conventions).
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ApertureSettings {
    /// Blades of the iris, 3 or more (absent: round).
    pub blades: Option<u32>,
    /// Angle of the first blade's vertex, degrees counter-clockwise from the image's +x.
    pub rotation: Option<f64>,
    /// 0: straight blades, 1: round; between, blades curved as arcs.
    pub roundness: Option<f64>,
    /// Anamorphic squeeze: the aperture's height over its width.
    pub aspect: Option<f64>,
    /// A transmission map (PNG or EXR) over the square circumscribing the aperture circle,
    /// instead of blades (a scene file's relative path starts at its folder).
    pub image: Option<PathBuf>,
}

#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageSettings {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub spp: Option<u32>,
    pub seed: Option<u32>,
    pub sampler: Option<SamplerKind>,
    /// Frames per second of a sequence: the rate a glTF animation's timeline is sampled at,
    /// a video's rate and the preview's playback rate (default 24).
    pub fps: Option<f64>,
}

#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RenderStyle {
    pub shading: Option<Shading>,
    pub background: Option<[f64; 3]>,
    /// What lights the scene from afar: a uniform sky's radiance (linear RGB) or an
    /// equirectangular map (`.hdr`, `.exr`); also the background unless one is given.
    pub environment: Option<EnvironmentSetting>,
    /// Turns the map counter-clockwise seen from above, degrees.
    pub environment_rotation: Option<f64>,
    /// Multiplies the environment's radiance.
    pub environment_intensity: Option<f64>,
    /// Surfaces a path shades: 1 (the default) is direct light, more add interreflection.
    pub bounces: Option<u32>,
    /// Adaptive sampling: a pixel stops once its estimated noise is below this (e.g. 0.01),
    /// with `spp` as its cap (docs/adaptive.md).
    pub noise_threshold: Option<f64>,
}

#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    #[serde(default)]
    pub camera: CameraSettings,
    #[serde(default)]
    pub image: ImageSettings,
    #[serde(default)]
    pub render: RenderStyle,
    /// One `[light]` table or several `[[light]]`.
    #[serde(default, skip_serializing_if = "Lights::is_empty")]
    pub light: Lights,
}

/// `a.or(b)` field by field: what `over` sets wins.
macro_rules! overlay {
    ($over:expr, $base:expr, $($field:ident),*) => {
        $( $base.$field = $over.$field.clone().or($base.$field.take()); )*
    };
}

impl Settings {
    /// These settings with every field that `over` sets replaced by its value.
    pub fn overridden_by(mut self, over: &Settings) -> Settings {
        let (c, i, r, l) = (&over.camera, &over.image, &over.render, &over.light);
        // The kind of lens is one choice: a real lens, a thin lens's radius or a focal length
        // given over replaces whichever the base has.
        if c.lens.prescription.is_some()
            || c.aperture_radius.is_some()
            || c.focal_length_mm.is_some()
        {
            self.camera.lens.prescription = None;
            self.camera.aperture_radius = None;
            self.camera.focal_length_mm = None;
        }
        // The plane of focus is given either by three points or by focus and tilt: the one
        // given over replaces the other.
        if c.focus_plane.is_some() {
            self.camera.focus_distance = None;
            self.camera.tilt = None;
            self.camera.tilt_direction = None;
        }
        if c.focus_distance.is_some() || c.tilt.is_some() || c.tilt_direction.is_some() {
            self.camera.focus_plane = None;
        }
        overlay!(
            c,
            self.camera,
            projection,
            eye,
            target,
            up,
            vfov_degrees,
            ortho_height,
            aperture_radius,
            focus_distance,
            focal_length_mm,
            f_number,
            sensor_height_mm,
            near,
            far,
            shift,
            tilt,
            tilt_direction,
            focus_plane
        );
        let (a, base) = (&c.aperture, &mut self.camera.aperture);
        overlay!(a, base, blades, rotation, roundness, aspect, image);
        let (lens, base) = (&c.lens, &mut self.camera.lens);
        overlay!(lens, base, prescription, dispersion, flare, starburst);
        let (sh, base) = (&c.shutter, &mut self.camera.shutter);
        overlay!(sh, base, motion_blur, angle, position, rolling);
        let (e, base) = (&c.exposure, &mut self.camera.exposure);
        overlay!(e, base, ev, iso, shutter, tonemap, expose_exr);
        overlay!(i, self.image, width, height, spp, seed, sampler, fps);
        // A map given over is seen behind the scene unless a background is given with it: the
        // base's background (a scene file's, say) does not hide it.
        if matches!(r.environment, Some(EnvironmentSetting::Map(_))) && r.background.is_none() {
            self.render.background = None;
        }
        overlay!(
            r,
            self.render,
            shading,
            background,
            environment,
            environment_rotation,
            environment_intensity,
            bounces,
            noise_threshold
        );
        self.light = std::mem::take(&mut self.light).overridden_by(l);
        self
    }
}

macro_rules! is_unset {
    ($($t:ty),*) => {
        $(impl $t {
            /// Whether no field is set (such a section is left out of a written scene file).
            pub fn is_unset(&self) -> bool {
                *self == Self::default()
            }
        })*
    };
}
is_unset!(
    CameraSettings,
    ApertureSettings,
    LensSettings,
    ExposureSettings,
    ShutterSettings,
    ImageSettings,
    RenderStyle
);
