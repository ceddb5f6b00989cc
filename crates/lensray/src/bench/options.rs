//! What a bench run measures: the scene, the paths, the shot, the repetitions, the reference
//! and the sweep. The command line (`cli::bench`) fills this in; tests may too.

use std::path::PathBuf;

use crate::paths::{DeviceChoice, PathChoice};
use lensray_core::camera::flare::FlareSwitches;
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::units::SceneUnits;
use lensray_vulkan::GpuOptions;

/// The named scenes a bench can use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum NamedScene {
    /// The built-in default scene (seven spheres on a checkerboard).
    Default,
    /// The generated dense scene (`--dense-triangles`, default 1M).
    Dense,
    /// The generated Cornell-box-style room.
    Cornell,
    /// The generated terrain: a 513 x 513 height field and 700 icospheres (748,288 triangles).
    Terrain,
}

impl NamedScene {
    pub fn name(self) -> &'static str {
        match self {
            NamedScene::Default => "default",
            NamedScene::Dense => "dense",
            NamedScene::Cornell => "cornell",
            NamedScene::Terrain => "terrain",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneChoice {
    Named(NamedScene),
    File(PathBuf),
}

impl SceneChoice {
    pub fn default_scene() -> Self {
        SceneChoice::Named(NamedScene::Default)
    }
}

/// What a sweep varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum SweepKind {
    /// Samples per pixel 1, 2, 4, ... up to --spp: error against time, one curve per path.
    Spp,
    /// Image sizes 160x120 to 1280x960.
    Resolution,
    /// Generated scenes of about 10k to 1M triangles.
    Triangles,
    /// Aperture shapes (round, 6 blades, 9 curved blades, squeezed, an image): each one's cost
    /// against the round aperture, measured in turns.
    Aperture,
    /// Real lenses (every built-in one) against their first-order thin lenses, measured in
    /// turns: time, camera rays that reach the scene per second, each one's cost over the thin
    /// lens's, and the share of camera samples the lens lets through (image and centre).
    Lens,
    /// The shot plain and moved (shifted and tilted; also shifted only or tilted only), measured
    /// in turns: each moved point's time per sample over the plain point's.
    Movements,
}

impl SweepKind {
    pub fn name(self) -> &'static str {
        match self {
            SweepKind::Spp => "spp",
            SweepKind::Resolution => "resolution",
            SweepKind::Triangles => "triangles",
            SweepKind::Aperture => "aperture",
            SweepKind::Lens => "lens",
            SweepKind::Movements => "movements",
        }
    }
}

#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub scene: SceneChoice,
    /// Triangles of the dense scene.
    pub dense_triangles: usize,
    /// The unit of length of the scene and of `aperture_radius` and `focus_distance` (the
    /// scene file's when `None`, else metres).
    pub scene_units: Option<SceneUnits>,
    /// Paths to compare, in this order; empty: every path the machine can run.
    pub paths: Vec<PathChoice>,
    pub device: DeviceChoice,
    /// Validation and device index for the GPU paths.
    pub gpu: GpuOptions,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Adaptive sampling (`render --noise-threshold`), `spp` its cap; the scene's own when
    /// `None`. The references stay uniform.
    pub noise_threshold: Option<f64>,
    pub shading: lensray_core::settings::Shading,
    /// The scene's own when `None` (a radius replaces a lens given by focal length and
    /// f-number, as on `render`).
    pub aperture_radius: Option<f64>,
    pub focus_distance: Option<f64>,
    /// The lens's f-number (a real lens of the lens sweep: `None` opens it fully; else the
    /// scene's physical lens).
    pub f_number: Option<f64>,
    /// Shift and tilt as on `render` (`--shift`, `--tilt`, `--tilt-direction`): of the shot,
    /// or under the movements sweep of its moved points (`None`: the sweep's own values).
    pub shift: Option<[f64; 2]>,
    pub tilt: Option<f64>,
    pub tilt_direction: Option<f64>,
    /// The scene's own when `None`.
    pub sampler: Option<SamplerKind>,
    pub seed: Option<u32>,
    /// Timed runs after the warm-up, >= 1.
    pub repeat: usize,
    /// Samples per pixel of the converged reference.
    pub reference_spp: u32,
    /// Where references are kept between runs; `None`: rendered every time.
    pub cache_dir: Option<PathBuf>,
    pub sweep: Option<SweepKind>,
    /// The sweep's values instead of its defaults ("1,4,16"; "160x120,320x240"; "10000,1000000").
    pub sweep_points: Option<String>,
    /// The lens's own light each render draws too (`--flare`, `--starburst`), timed apart.
    pub flare: FlareSwitches,
}

/// Where references are cached unless `--cache-dir` says otherwise (relative to the working
/// folder, as cargo's own `target/`).
pub const DEFAULT_CACHE_DIR: &str = "target/lensray-bench-cache";
pub const DEFAULT_REFERENCE_SPP: u32 = 1024;

impl Default for BenchOptions {
    fn default() -> Self {
        Self {
            scene: SceneChoice::Named(NamedScene::Default),
            dense_triangles: lensray_core::scene::generate::DEFAULT_DENSE_TRIANGLES,
            scene_units: None,
            paths: Vec::new(),
            device: DeviceChoice::Auto,
            gpu: GpuOptions::default(),
            width: lensray_core::settings::DEFAULT_WIDTH,
            height: lensray_core::settings::DEFAULT_HEIGHT,
            spp: lensray_core::settings::DEFAULT_SPP,
            noise_threshold: None,
            shading: lensray_core::settings::Shading::Unlit,
            aperture_radius: None,
            focus_distance: None,
            f_number: None,
            shift: None,
            tilt: None,
            tilt_direction: None,
            sampler: None,
            seed: None,
            repeat: 5,
            reference_spp: DEFAULT_REFERENCE_SPP,
            cache_dir: Some(PathBuf::from(DEFAULT_CACHE_DIR)),
            sweep: None,
            sweep_points: None,
            flare: FlareSwitches::default(),
        }
    }
}
