//! What to render, from what a user gives to what a path computes:
//! - [`user`]: the settings of a scene file or the command line, every field optional (the
//!   command line overrides the file);
//! - [`shot`](mod@shot): those settings and the scene made into a [`Shot`], a validated camera and the
//!   render settings, with a default for what neither gives;
//! - [`render`]: the render settings every path (CPU and GPU) computes from: samples, seed,
//!   sampler, shading, background and environment;
//! - [`lights`]: the settings' lights, added to the scene's own;
//! - [`exposure`](mod@exposure): the exposure and tone map of what is shown, from the settings
//!   and the shot's lens;
//! - [`finite`]: the one check that every number of the settings is finite;
//! - [`shutter`](mod@shutter): when the shutter is open about a frame's time, for motion blur
//!   and a rolling shutter;
//! - [`keyframe`]: a scene file's `[[keyframe]]`s, the settings of each frame of a sequence;
//! - [`camera_timeline`]: a glTF camera animation on a sequence's frames.

pub mod aperture_image;
pub mod camera_timeline;
pub mod environment;
pub mod exposure;
pub mod finite;
pub mod framing;
pub mod keyframe;
pub mod lights;
pub mod render;
pub mod shot;
pub mod shutter;
pub mod user;

pub use camera_timeline::CameraTimeline;
pub use environment::EnvironmentSetting;
pub use exposure::{exposure, Exposure};
pub use framing::{
    BOARD_ELEVATION_DEGREES, BOARD_THINNESS, FRAMING_AZIMUTH_DEGREES, FRAMING_ELEVATION_DEGREES,
};
pub use keyframe::{fps, frame_seed, FocusKey, Interpolation, Keyframes, DEFAULT_FPS};
pub use lights::{
    emitters_light_share, light_scene, pinned_lights, settings_lights, LightSettings, LightType,
    Lights, EMITTERS_LIGHT_SHARE,
};
pub use render::{RenderSettings, Shading};
pub use shot::{
    shot, tilt_model, FocusChoice, SettingsError, Shot, DEFAULT_F_NUMBER, DEFAULT_HEIGHT,
    DEFAULT_SENSOR_HEIGHT_MM, DEFAULT_SPP, DEFAULT_VFOV_DEGREES, DEFAULT_WIDTH,
};
pub use shutter::{shutter, Shutter};
pub use user::{
    ApertureSettings, CameraSettings, ExposureSettings, ImageSettings, LensSettings,
    ProjectionKind, RenderStyle, Settings, ShutterPosition, ShutterSettings, Switch,
};
