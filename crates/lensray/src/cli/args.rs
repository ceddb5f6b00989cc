//! Command-line options shared by `render` and `bench`, mapped onto [`Settings`].

use std::path::PathBuf;

use clap::Args;

/// The crease angle of `--smooth-normals` given without one, degrees.
const DEFAULT_CREASE: &str = "60";

use super::named::by_name;
use crate::paths::{DeviceChoice, PathChoice, PathOptions};
use lensray_vulkan::GpuOptions;

use lensray_core::film::tonemap::ToneMap;
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::units::SceneUnits;
use lensray_core::settings::{
    ApertureSettings, CameraSettings, ExposureSettings, ImageSettings, LensSettings, LightSettings,
    Lights, ProjectionKind, RenderStyle, Settings, ShutterPosition, ShutterSettings, Switch,
};
use lensray_core::settings::{EnvironmentSetting, Shading};

/// Parses "x,y,z" into three finite-or-not numbers (validation names the option later).
/// `--environment`: three numbers are a uniform sky's radiance, an `.hdr` or `.exr` path a map.
pub fn parse_environment(s: &str) -> Result<EnvironmentSetting, String> {
    let ext = std::path::Path::new(s)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if matches!(ext.as_deref(), Some("hdr" | "exr")) {
        return Ok(EnvironmentSetting::Map(s.into()));
    }
    parse_triple(s)
        .map(EnvironmentSetting::Sky)
        .map_err(|e| format!("{e}; or name an equirectangular map (.hdr, .exr)"))
}

pub fn parse_triple(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected three comma-separated numbers like 1,2.5,-3, got '{s}'"
        ));
    }
    let mut out = [0.0; 3];
    for (o, p) in out.iter_mut().zip(&parts) {
        *o = p
            .parse::<f64>()
            .map_err(|_| format!("'{p}' is not a number (in '{s}')"))?;
    }
    Ok(out)
}

/// Parses "x,y" pixel coordinates.
pub fn parse_pixel(s: &str) -> Result<[u32; 2], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    match parts.as_slice() {
        [x, y] => Ok([
            x.parse()
                .map_err(|_| format!("'{x}' is not a pixel column"))?,
            y.parse().map_err(|_| format!("'{y}' is not a pixel row"))?,
        ]),
        _ => Err(format!(
            "expected a pixel as column,row like 320,240, got '{s}'"
        )),
    }
}

/// Parses "x,y" into two numbers (validation names the option later).
pub fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y] = parts.as_slice() else {
        return Err(format!(
            "expected two comma-separated numbers like 0,2.5, got '{s}'"
        ));
    };
    let number = |p: &str| {
        p.parse::<f64>()
            .map_err(|_| format!("'{p}' is not a number (in '{s}')"))
    };
    Ok([number(x)?, number(y)?])
}

/// A time in seconds: a number (0.008) or a fraction as cameras mark it (1/125).
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    let number = |p: &str| {
        p.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{s}' is not a time in seconds (like 0.008 or 1/125)"))
    };
    match s.split_once('/') {
        Some((a, b)) => Ok(number(a)? / number(b)?),
        None => number(s),
    }
}

/// Exposure and tone map (`settings::exposure`): shared by `render` and `preview` (through
/// [`ViewArgs`]).
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct ExposureArgs {
    /// Exposure in stops: the image is scaled by 2^EV; with --shutter, an offset on top of the
    /// camera's exposure (default 0: the render's values as they are).
    #[arg(long, value_name = "EV", allow_hyphen_values = true)]
    pub exposure: Option<f64>,
    /// The sensor's ISO speed for a physical exposure (needs --shutter; default 100).
    #[arg(long, value_name = "ISO", allow_hyphen_values = true)]
    pub iso: Option<f64>,
    /// Shutter time, seconds (0.008 or 1/125): expose as a camera does, 1 / (1.2 * 2^EV100)
    /// with EV100 = log2(N^2 / t * 100 / ISO) and N the lens's f-number (a pinhole's: f/16, or
    /// --f-number). For glTF's photometric lights: sunny 16 is --iso 100 --shutter 1/125 at f/16.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, allow_hyphen_values = true)]
    pub shutter: Option<f64>,
    /// The tone map of PNGs and the preview [default: neutral].
    #[arg(long, value_parser = by_name::<ToneMap>())]
    pub tonemap: Option<ToneMap>,
    /// Expose EXR output too (by default an EXR keeps the render's linear values; it is never
    /// tone mapped).
    #[arg(long)]
    pub expose_exr: bool,
}

impl ExposureArgs {
    pub fn to_settings(self) -> ExposureSettings {
        ExposureSettings {
            ev: self.exposure,
            iso: self.iso,
            shutter: self.shutter,
            tonemap: self.tonemap,
            expose_exr: self.expose_exr.then_some(true),
        }
    }
}

/// Which device: shared by `render`, `preview` (through [`PathArgs`]) and `bench`.
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct DeviceArgs {
    /// Which device: a Vulkan device (gpu), the CPU, or auto: a Vulkan device when one is
    /// usable, else the CPU.
    #[arg(long, value_enum, default_value_t = DeviceChoice::Auto)]
    pub device: DeviceChoice,
    /// Turn on the Vulkan validation layer; any warning or error fails the command.
    #[arg(long)]
    pub validate: bool,
    /// Use this Vulkan device (index from `lensray info`).
    #[arg(long, value_name = "INDEX")]
    pub gpu: Option<usize>,
    /// Act as if the Vulkan device had no ray-tracing support, neither ray queries nor the
    /// ray-tracing pipeline (to try the software path where it would be the only one).
    #[arg(long)]
    pub hide_ray_query: bool,
}

impl DeviceArgs {
    /// The Vulkan options these name (every traversal the device runs).
    pub fn gpu_options(&self) -> GpuOptions {
        GpuOptions {
            validate: self.validate,
            device_index: self.gpu,
            hide_ray_query: self.hide_ray_query,
            traversal: None,
            first_use_notice: true,
        }
    }
}

/// Which device and which algorithm: shared by `render` and `preview`.
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct PathArgs {
    /// Which algorithm renders: a path (listed below), or auto: the
    /// fastest the device supports, measured on a small render of the shot.
    #[arg(long, value_enum, default_value_t = PathChoice::Auto)]
    pub path: PathChoice,
    #[command(flatten)]
    pub device: DeviceArgs,
}

impl PathArgs {
    pub fn options(&self) -> PathOptions {
        PathOptions {
            path: self.path,
            device: self.device.device,
            gpu: self.device.gpu_options(),
        }
    }
}

/// Shift and tilt (`camera::movements`): shared by `render`, `preview` and `bench`.
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct MovementArgs {
    /// Shift the film window off the axis (a shift lens): mm on the film with a focal length
    /// or a real lens, else fractions of the image height; +X right, +Y up.
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    pub shift: Option<[f64; 2]>,
    /// Tilt the lens against the film, degrees in [0, 90): the plane of focus turns
    /// (Scheimpflug; with a focal length its hinge lies f / sin(tilt) from the lens).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub tilt: Option<f64>,
    /// Where in the image the tilted plane of focus comes nearer, degrees counter-clockwise
    /// from the image's bottom: 0 lays it like the ground, 90 like a wall on the right.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub tilt_direction: Option<f64>,
}

/// Camera, image and shading options; each overrides the scene file.
#[derive(Args, Clone, Debug, Default)]
pub struct ViewArgs {
    /// Scene file (.toml) or a mesh file (.gltf, .glb, .obj); the built-in default scene when
    /// absent.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// The scene's camera to use, by name or index (glTF cameras; default: the first).
    #[arg(long, value_name = "NAME|INDEX")]
    pub camera: Option<String>,
    /// Smooth normals for meshes that have none, creased at ANGLE degrees (default 60).
    #[arg(long, value_name = "ANGLE", num_args = 0..=1,
          default_missing_value = DEFAULT_CREASE, value_parser = parse_crease)]
    pub smooth_normals: Option<f64>,
    /// The unit of length of the scene's files and of the world lengths below (eye, target,
    /// focus distance, ...): m, cm, mm or in [default: the scene file's `units`, else m].
    #[arg(long, value_name = "UNITS", value_parser = SceneUnits::parse)]
    pub scene_units: Option<SceneUnits>,
    #[arg(long, value_parser = by_name::<ProjectionKind>())]
    pub projection: Option<ProjectionKind>,
    /// Camera position, in the scene's units (as every world length below; lens data is in mm).
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub eye: Option<[f64; 3]>,
    /// Point the camera looks at.
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub target: Option<[f64; 3]>,
    /// World up direction (default 0,1,0).
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub up: Option<[f64; 3]>,
    /// Vertical field of view, degrees (perspective).
    #[arg(
        long,
        value_name = "DEG",
        allow_hyphen_values = true,
        conflicts_with = "ortho_height"
    )]
    pub vfov: Option<f64>,
    /// View height (orthographic).
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub ortho_height: Option<f64>,
    /// Lens aperture radius (0 = pinhole).
    #[arg(
        long,
        value_name = "R",
        allow_hyphen_values = true,
        conflicts_with = "focal_length_mm"
    )]
    pub aperture_radius: Option<f64>,
    /// Distance of the focal plane along the view axis (a tilted plane: where it crosses
    /// the axis).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub focus_distance: Option<f64>,
    #[command(flatten)]
    pub movements: MovementArgs,
    /// Lay the plane of focus through the surfaces under three pixels (column,row each):
    /// sets focus distance, tilt and tilt direction, and prints them.
    #[arg(long, num_args = 3, value_parser = parse_pixel, value_name = "X,Y",
          conflicts_with_all = ["tilt", "tilt_direction", "focus_distance"])]
    pub focus_plane: Option<Vec<[u32; 2]>>,
    /// Blades of the iris, 3 to 32 (absent: a round aperture); its vertices lie on the
    /// aperture's circle.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub aperture_blades: Option<u32>,
    /// Angle of the first blade's vertex, degrees counter-clockwise from the image's +x axis.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub aperture_rotation: Option<f64>,
    /// Blades curved as arcs: 0 straight, 1 round.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub aperture_roundness: Option<f64>,
    /// Anamorphic squeeze: the aperture's height over its width (2: ovals twice as tall).
    #[arg(long, value_name = "A", allow_hyphen_values = true)]
    pub aperture_aspect: Option<f64>,
    /// The aperture's shape as an image (PNG or EXR, transmission in [0, 1]) filling the
    /// square around the aperture circle, its top row at the top; instead of blades.
    #[arg(long, value_name = "FILE")]
    pub aperture_image: Option<std::path::PathBuf>,
    /// Focal length in mm (physical units: the scene's are converted to metres).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub focal_length_mm: Option<f64>,
    /// A real lens traced surface by surface: a built-in name (see `lensray lens --help`)
    /// or a prescription file. Its f-number, focus distance and sensor height are the
    /// options of those names; the field of view follows from the lens and the film.
    #[arg(
        long,
        value_name = "NAME|FILE",
        conflicts_with_all = ["focal_length_mm", "aperture_radius", "vfov", "ortho_height"]
    )]
    pub lens: Option<String>,
    /// With --lens: whether each camera ray carries a wavelength through the lens's glass
    /// (colour fringes from dispersion; default on when the lens gives Abbe numbers).
    #[arg(long, value_parser = by_name::<Switch>(), value_name = "on|off")]
    pub dispersion: Option<Switch>,
    /// With --lens: ghosts, light reflected twice between the lens's coated surfaces, from the
    /// image's bright sources and the punctual lights in view (default off).
    #[arg(long, value_parser = by_name::<Switch>(), value_name = "on|off")]
    pub flare: Option<Switch>,
    /// With --lens: the aperture's diffraction starburst around bright sources, its spikes
    /// growing with the f-number (default off).
    #[arg(long, value_parser = by_name::<Switch>(), value_name = "on|off")]
    pub starburst: Option<Switch>,
    /// f-number N: aperture radius = f / (2N); with --lens, the stop is closed until the
    /// entrance pupil gives N (default: wide open).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub f_number: Option<f64>,
    /// Sensor height in mm (field of view from the thin-lens film distance, or the lens's).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub sensor_height_mm: Option<f64>,
    /// Near plane distance (default from the scene's extent).
    #[arg(long, allow_hyphen_values = true)]
    pub near: Option<f64>,
    /// Far plane distance (default from the scene's extent).
    #[arg(long, allow_hyphen_values = true)]
    pub far: Option<f64>,
    #[arg(long, value_name = "W")]
    pub width: Option<u32>,
    #[arg(long, value_name = "H")]
    pub height: Option<u32>,
    /// Samples per pixel.
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Adaptive sampling: a pixel stops taking samples once its estimated noise is below T
    /// (say 0.01; smaller is cleaner and slower), --spp being its cap (cpu, rayquery,
    /// rtpipeline, software; docs/adaptive.md).
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub noise_threshold: Option<f64>,
    /// Seed of the deterministic sampler.
    #[arg(long, value_name = "S")]
    pub seed: Option<u32>,
    /// How samples are drawn (default sobol).
    #[arg(long, value_parser = by_name::<SamplerKind>())]
    pub sampler: Option<SamplerKind>,
    /// Frames per second of a sequence (default 24): the rate a glTF camera animation is
    /// sampled at, a video's rate and the preview's playback rate.
    #[arg(long, value_name = "FPS", allow_hyphen_values = true)]
    pub fps: Option<f64>,
    #[arg(long, value_parser = by_name::<Shading>())]
    pub shading: Option<Shading>,
    /// Background colour, linear RGB.
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "R,G,B")]
    pub background: Option<[f64; 3]>,
    /// What lights every surface from afar: a uniform sky's radiance (linear RGB) or an
    /// equirectangular HDR map (.hdr, .exr), drawn by its power; also the background unless
    /// one is given.
    #[arg(long, value_parser = parse_environment, allow_hyphen_values = true, value_name = "R,G,B|FILE")]
    pub environment: Option<EnvironmentSetting>,
    /// Turns the environment map counter-clockwise seen from above, degrees.
    #[arg(long, allow_hyphen_values = true, value_name = "DEG")]
    pub environment_rotation: Option<f64>,
    /// Multiplies the environment's radiance (default 1).
    #[arg(long, allow_hyphen_values = true, value_name = "X")]
    pub environment_intensity: Option<f64>,
    /// Surfaces a lit path shades (default 1: direct light; 4 where the scene has glass, so
    /// that paths go through it); more add interreflection, each bounce costing about one
    /// more closest hit and its shading per sample.
    #[arg(long, value_name = "N")]
    pub bounces: Option<u32>,
    /// A point light's position: it replaces the scene file's lights, or moves its one light.
    /// Lights in the scene's glTF stay. Without any light or environment, a point light above
    /// the eye lights the scene.
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub light_position: Option<[f64; 3]>,
    /// That point light's intensity, W/sr per channel.
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "R,G,B")]
    pub light_intensity: Option<[f64; 3]>,
    #[command(flatten)]
    pub exposure: ExposureArgs,
    #[command(flatten)]
    pub shutter: ShutterArgs,
}

/// Motion blur and rolling shutter (`settings::shutter`): shared by `render` and `preview`
/// (through [`ViewArgs`]).
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct ShutterArgs {
    /// Blur what moves while the shutter is open: the camera's keyframes or glTF animation
    /// (cpu, software, rayquery and rtpipeline), a glTF file's animated meshes and lights
    /// (cpu and software); default off.
    #[arg(long, value_parser = by_name::<Switch>(), value_name = "on|off")]
    pub motion_blur: Option<Switch>,
    /// How long the shutter is open, degrees of a frame at --fps (default 180: half a frame);
    /// --shutter sets the time instead when given.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub shutter_angle: Option<f64>,
    /// Where the open time lies about the frame's own time (default center).
    #[arg(long, value_parser = by_name::<ShutterPosition>())]
    pub shutter_position: Option<ShutterPosition>,
    /// A rolling shutter: seconds from the top row's opening to the bottom row's (1/30 or
    /// 0.02); each row sees the scene that much later by its place down the image.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, allow_hyphen_values = true)]
    pub rolling_shutter: Option<f64>,
}

impl ShutterArgs {
    pub fn to_settings(self) -> ShutterSettings {
        ShutterSettings {
            motion_blur: self.motion_blur,
            angle: self.shutter_angle,
            position: self.shutter_position,
            rolling: self.rolling_shutter,
        }
    }
}

impl ViewArgs {
    pub fn to_settings(&self) -> Settings {
        Settings {
            camera: CameraSettings {
                projection: self.projection,
                eye: self.eye,
                target: self.target,
                up: self.up,
                vfov_degrees: self.vfov,
                ortho_height: self.ortho_height,
                aperture_radius: self.aperture_radius,
                focus_distance: self.focus_distance,
                focal_length_mm: self.focal_length_mm,
                f_number: self.f_number,
                sensor_height_mm: self.sensor_height_mm,
                near: self.near,
                far: self.far,
                shift: self.movements.shift,
                tilt: self.movements.tilt,
                tilt_direction: self.movements.tilt_direction,
                focus_plane: self.focus_plane.as_deref().map(|p| [p[0], p[1], p[2]]),
                aperture: ApertureSettings {
                    blades: self.aperture_blades,
                    rotation: self.aperture_rotation,
                    roundness: self.aperture_roundness,
                    aspect: self.aperture_aspect,
                    image: self.aperture_image.clone(),
                },
                lens: LensSettings {
                    prescription: self.lens.clone(),
                    dispersion: self.dispersion,
                    flare: self.flare,
                    starburst: self.starburst,
                },
                exposure: self.exposure.to_settings(),
                shutter: self.shutter.to_settings(),
            },
            image: ImageSettings {
                width: self.width,
                height: self.height,
                spp: self.spp,
                seed: self.seed,
                sampler: self.sampler,
                fps: self.fps,
            },
            render: RenderStyle {
                shading: self.shading,
                background: self.background,
                environment: self.environment.clone(),
                environment_rotation: self.environment_rotation,
                environment_intensity: self.environment_intensity,
                bounces: self.bounces,
                noise_threshold: self.noise_threshold,
            },
            light: if self.light_position.is_some() || self.light_intensity.is_some() {
                Lights(vec![LightSettings {
                    position: self.light_position,
                    intensity: self.light_intensity,
                    ..LightSettings::default()
                }])
            } else {
                Lights::default()
            },
        }
    }
}

/// A crease angle in degrees, 0 to 180.
fn parse_crease(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(a) if (0.0..=180.0).contains(&a) => Ok(a),
        _ => Err(format!("`{text}` is not an angle from 0 to 180 degrees")),
    }
}
