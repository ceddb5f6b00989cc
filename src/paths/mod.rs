//! The render paths behind [`RenderPath`], and the choice of one: `--device` says which device,
//! `--path` which algorithm; `auto` measures the paths the device supports and takes the
//! fastest.

mod auto;
mod cpu;
mod gpu;
pub mod hybrid;
mod path;

use std::fmt;

use anyhow::{bail, Context, Result};

pub use auto::{pick_path, pick_traversal};
pub use cpu::CpuPath;
pub use gpu::GpuPath;
pub use hybrid::HybridPath;
pub use path::{Clock, PathKind, PathReport, RenderPath};

use crate::camera::Camera;
use crate::film::Accumulation;
use crate::gpu::{GpuOptions, GpuRenderer, Traversal};
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// Which device renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum DeviceChoice {
    /// A Vulkan device when one is usable, else the CPU.
    #[default]
    Auto,
    /// The CPU (the reference renderer).
    Cpu,
    /// A Vulkan device; an error when none is usable.
    Gpu,
}

/// Which algorithm renders: a path, or `auto`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum PathChoice {
    /// The fastest path the device supports, measured on a small render of the shot.
    #[default]
    Auto,
    /// Vulkan ray queries (VK_KHR_ray_query).
    #[value(name = "rayquery")]
    RayQuery,
    /// lensray's own BVH traversed in the compute shader: any Vulkan device.
    Software,
    /// G-buffer-guided: rays only where the circle of confusion needs them (docs/hybrid.md).
    Hybrid,
    /// Accumulation-buffer depth of field: the scene rasterized through one lens point per
    /// sample (docs/raster.md).
    Raster,
    /// The CPU reference renderer.
    Cpu,
}

impl PathChoice {
    pub fn kind(self) -> Option<PathKind> {
        match self {
            PathChoice::Auto => None,
            PathChoice::RayQuery => Some(PathKind::RayQuery),
            PathChoice::Software => Some(PathKind::Software),
            PathChoice::Hybrid => Some(PathKind::Hybrid),
            PathChoice::Raster => Some(PathKind::Raster),
            PathChoice::Cpu => Some(PathKind::Cpu),
        }
    }
}

impl From<PathKind> for PathChoice {
    fn from(kind: PathKind) -> Self {
        match kind {
            PathKind::RayQuery => PathChoice::RayQuery,
            PathKind::Software => PathChoice::Software,
            PathKind::Hybrid => PathChoice::Hybrid,
            PathKind::Raster => PathChoice::Raster,
            PathKind::Cpu => PathChoice::Cpu,
        }
    }
}

impl fmt::Display for PathChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind() {
            Some(kind) => kind.fmt(f),
            None => f.write_str("auto"),
        }
    }
}

/// How to open a path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PathOptions {
    pub path: PathChoice,
    pub device: DeviceChoice,
    /// Validation and device index of the Vulkan device.
    pub gpu: GpuOptions,
}

/// An open path with its scene loaded, and why it was chosen (for the summary line).
pub struct OpenedPath {
    pub path: Box<dyn RenderPath>,
    pub why: String,
}

/// The traversal a GPU path is tied to (`None`: the CPU, or the hybrid and raster paths, which
/// trace with the device's fastest).
pub fn traversal_of(kind: PathKind) -> Option<Traversal> {
    match kind {
        PathKind::RayQuery => Some(Traversal::RayQuery),
        PathKind::Software => Some(Traversal::Software),
        PathKind::Hybrid | PathKind::Raster | PathKind::Cpu => None,
    }
}

fn kind_of(traversal: Traversal) -> PathKind {
    match traversal {
        Traversal::RayQuery => PathKind::RayQuery,
        Traversal::Software => PathKind::Software,
    }
}

/// Opens the path `options` ask for and loads `scene`. `auto` renders a small version of
/// `shot` with each path the device supports and keeps the fastest. Under `--device auto`, a
/// missing or unusable Vulkan device falls back to the CPU with a notice, unless a Vulkan
/// option (`--validate`, `--gpu`) or a GPU path was asked for.
pub fn open(
    options: &PathOptions,
    scene: &Scene,
    shot: (&Camera, &RenderSettings),
) -> Result<OpenedPath> {
    let gpu_option = if options.gpu.validate {
        Some("--validate checks the Vulkan renderer".to_string())
    } else {
        options
            .gpu
            .device_index
            .map(|index| format!("--gpu {index} picks a Vulkan device"))
    };
    let wants_cpu = options.device == DeviceChoice::Cpu || options.path == PathChoice::Cpu;
    if wants_cpu {
        if let Some(option) = gpu_option {
            let by = if options.path == PathChoice::Cpu {
                "--path cpu"
            } else {
                "--device cpu"
            };
            bail!("{option}: it cannot be used with {by}");
        }
        match (options.device, options.path) {
            (DeviceChoice::Gpu, _) => {
                bail!("--path cpu runs on the CPU: it cannot be used with --device gpu")
            }
            (
                _,
                PathChoice::RayQuery
                | PathChoice::Software
                | PathChoice::Hybrid
                | PathChoice::Raster,
            ) => bail!(
                "--path {} runs on a Vulkan device: it cannot be used with --device cpu",
                options.path
            ),
            _ => {}
        }
        let why = if options.path == PathChoice::Cpu {
            "asked for"
        } else {
            "--device cpu"
        };
        return open_cpu(scene, why);
    }

    let traversal = options.path.kind().and_then(traversal_of);
    let gpu_options = GpuOptions {
        traversal,
        ..options.gpu
    };
    let renderer = match GpuRenderer::new(&gpu_options) {
        Ok(renderer) => renderer,
        Err(error) => {
            let error = anyhow::Error::from(error);
            return match (options.path, options.device, gpu_option) {
                (PathChoice::Auto, DeviceChoice::Auto, None) => {
                    eprintln!("notice: rendering on the CPU: no usable GPU ({error:#})");
                    open_cpu(scene, "auto: no usable Vulkan device")
                }
                (PathChoice::Auto, DeviceChoice::Auto, Some(_)) => {
                    Err(error.context(if options.gpu.validate {
                        "--validate".to_string()
                    } else {
                        format!("--gpu {}", options.gpu.device_index.unwrap_or(0))
                    }))
                }
                (PathChoice::Auto, _, _) => Err(error.context("--device gpu")),
                (path, _, _) => Err(error.context(format!("--path {path}"))),
            };
        }
    };
    let mut renderer = renderer;
    renderer.load_scene(scene)?;
    if matches!(options.path, PathChoice::Hybrid | PathChoice::Raster) {
        let (traversal, why) = pick_traversal(&mut renderer, shot)?;
        let path: Box<dyn RenderPath> = if options.path == PathChoice::Hybrid {
            Box::new(HybridPath::new(renderer)?)
        } else {
            Box::new(GpuPath::new(renderer, PathKind::Raster)?)
        };
        return Ok(OpenedPath {
            path,
            why: format!("asked for; traces with {traversal} ({why})"),
        });
    }
    if let Some(kind) = options.path.kind() {
        let traversal = traversal_of(kind).expect("a GPU path");
        renderer
            .set_traversal(traversal)
            .with_context(|| format!("--path {kind}"))?;
        return Ok(OpenedPath {
            path: Box::new(GpuPath::new(renderer, kind)?),
            why: "asked for".into(),
        });
    }
    let (kind, why) = pick_path(&mut renderer, shot)?;
    let path: Box<dyn RenderPath> = match kind {
        PathKind::Hybrid => Box::new(HybridPath::new(renderer)?),
        PathKind::Raster => Box::new(GpuPath::new(renderer, PathKind::Raster)?),
        _ => Box::new(GpuPath::new(renderer, kind)?),
    };
    Ok(OpenedPath { path, why })
}

fn open_cpu(scene: &Scene, why: &str) -> Result<OpenedPath> {
    let mut path = CpuPath::new();
    path.load_scene(scene)?;
    Ok(OpenedPath {
        path: Box::new(path),
        why: why.into(),
    })
}

/// The accumulation must match the camera, and only traced shadings add samples.
fn check_accumulation(
    camera: &Camera,
    settings: &RenderSettings,
    accumulation: &Accumulation,
) -> Result<()> {
    if (accumulation.width, accumulation.height) != (camera.width, camera.height) {
        bail!(
            "accumulation {}x{} does not match the {}x{} image",
            accumulation.width,
            accumulation.height,
            camera.width,
            camera.height
        );
    }
    if settings.shading.is_aov() {
        bail!(
            "{:?} is an AOV: it has no samples to accumulate",
            settings.shading
        );
    }
    Ok(())
}

/// Who traces the preview's samples (`preview_options`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PreviewChoice {
    /// The window's Vulkan options (the traversal, when the path names one).
    pub gpu: GpuOptions,
    /// The CPU path traces (the window only shows).
    pub cpu: bool,
    /// The hybrid path: the trace dispatches follow a plan made on the device from each
    /// restart's G-buffer (docs/hybrid.md, "In the preview").
    pub hybrid: bool,
    /// The raster path: per sample a raster pass through its lens point, then the shading
    /// pass (docs/raster.md).
    pub raster: bool,
}

/// The preview window always draws with Vulkan; the path only says who traces the samples.
pub fn preview_options(options: &PathOptions) -> Result<PreviewChoice> {
    let cpu = match (options.device, options.path) {
        (
            DeviceChoice::Cpu,
            PathChoice::RayQuery | PathChoice::Software | PathChoice::Hybrid | PathChoice::Raster,
        ) => {
            bail!(
                "--path {} runs on a Vulkan device: it cannot be used with --device cpu",
                options.path
            )
        }
        (DeviceChoice::Gpu, PathChoice::Cpu) => {
            bail!("--path cpu runs on the CPU: it cannot be used with --device gpu")
        }
        (DeviceChoice::Cpu, _) | (_, PathChoice::Cpu) => true,
        _ => false,
    };
    // The hybrid and raster paths trace with the device's fastest traversal (picked as `render`
    // picks it).
    let traversal = options.path.kind().and_then(traversal_of);
    Ok(PreviewChoice {
        gpu: GpuOptions {
            traversal,
            ..options.gpu
        },
        cpu,
        hybrid: options.path == PathChoice::Hybrid,
        raster: options.path == PathChoice::Raster,
    })
}
