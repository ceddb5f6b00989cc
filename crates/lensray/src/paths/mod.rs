//! The render paths behind [`RenderPath`]: `cpu` (the CPU reference) and `gpu` (the Vulkan
//! renderer with one of its estimators: traced for `rayquery` and `software`, raster, hybrid);
//! and the choice of one. `--device` says which device,
//! `--path` which algorithm ([`PathKind`] describes them, [`request`] checks what the two ask
//! for together); `auto` measures the paths the device supports and takes the fastest (`auto`).

mod auto;
pub mod calibration;
mod cpu;
mod gpu;
mod path;
mod phases;
pub mod request;

use std::time::Instant;

use anyhow::{bail, Context, Result};

pub use auto::{pick_path, pick_traversal};
pub use cpu::CpuPath;
pub use gpu::GpuPath;
pub use path::{
    Choice, Clock, DeviceChoice, DeviceKind, PathChoice, PathKind, PathReport, RealLensSupport,
    RenderPath,
};
pub use phases::Phases;
pub use request::PathOptions;

use lensray_core::film::Accumulation;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;
use lensray_vulkan::{Estimator, GpuOptions, GpuRenderer};

/// An open path with its scene loaded, why it was chosen (for the summary line), and what
/// opening it took.
pub struct OpenedPath {
    pub path: Box<dyn RenderPath>,
    pub why: String,
    pub startup: Startup,
}

/// What opening a path took, wall-clock seconds: the device and its pipelines (Vulkan
/// instance, device, pipeline creation and compilation, and `auto`'s calibration and choice),
/// and the scene on it (upload, acceleration structures or BVH).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Startup {
    pub device_seconds: f64,
    /// Of `device_seconds`, the Vulkan instance and device alone (the rest is pipelines and
    /// `auto`'s choice).
    pub instance_seconds: f64,
    pub scene_seconds: f64,
}

/// Opens the path `options` ask for and loads `scene`. `auto` renders a small version of
/// `shot` with each path the device supports and keeps the fastest. Under `--device auto`, a
/// missing or unusable Vulkan device falls back to the CPU with a notice, unless a Vulkan
/// option (`--validate`, `--gpu`) or a GPU path was asked for.
pub fn open(options: &PathOptions, scene: &Scene, shot: &Shot) -> Result<OpenedPath> {
    let device = options.device_to_use("--path")?;
    let real_lens = shot.camera.lens.real();
    if let (Some(real), Some(kind)) = (real_lens, options.path.only()) {
        match kind.real_lens_support() {
            RealLensSupport::Refused => bail!(
                "--path {kind} does not trace real lenses (--lens {}): use cpu, rayquery, rtpipeline, software or auto",
                real.name()
            ),
            RealLensSupport::FirstOrder => eprintln!(
                "notice: --path {kind} renders lens {} by its first-order model (a thin lens at its entrance pupil): no aberrations, distortion or vignetting",
                real.name()
            ),
            RealLensSupport::Traced => {}
        }
    }
    if device == Choice::Only(DeviceKind::Cpu) {
        let why = if options.path == Choice::Only(PathKind::Cpu) {
            "asked for"
        } else {
            "--device cpu"
        };
        return open_cpu(scene, why);
    }
    let (adaptive, moving) = refuse_unsupported(options, shot)?;

    // Auto's calibration counts with the device: it is what opening one costs.
    let device_start = Instant::now();
    let mut gpu_options = GpuOptions {
        traversal: options.path.only().and_then(PathKind::traversal),
        ..options.gpu
    };
    if options.path == Choice::Auto {
        match auto_device(options, &gpu_options, auto::pixel_samples(shot)) {
            Some(calibration::DeviceDecision::Cpu(why)) => return open_cpu(scene, &why),
            // The calibrated traversal alone: only its trace pipeline is made.
            Some(calibration::DeviceDecision::Gpu(traversal, _)) => {
                gpu_options.traversal = traversal;
            }
            None => {}
        }
    }
    let mut renderer = match GpuRenderer::new(&gpu_options) {
        Ok(renderer) => renderer,
        Err(error) => {
            let error = anyhow::Error::from(error);
            return match (options.path, options.device, options.gpu_option()) {
                (Choice::Auto, Choice::Auto, None) => {
                    eprintln!("notice: rendering on the CPU: no usable GPU ({error:#})");
                    open_cpu(scene, "auto: no usable Vulkan device")
                }
                (Choice::Auto, Choice::Auto, Some(option)) => Err(error.context(option.flag)),
                (Choice::Auto, _, _) => Err(error.context("--device gpu")),
                (path, _, _) => Err(error.context(format!("--path {path}"))),
            };
        }
    };
    let mut startup = Startup {
        device_seconds: device_start.elapsed().as_secs_f64(),
        instance_seconds: renderer.open_seconds(),
        scene_seconds: 0.0,
    };
    if options.path.only().and_then(PathKind::traversal).is_none() {
        auto::preset_cached_traversal(&mut renderer, shot)?;
    }
    let scene_start = Instant::now();
    renderer.load_scene(scene)?;
    startup.scene_seconds = scene_start.elapsed().as_secs_f64();
    let choice_start = Instant::now();
    let (kind, why) = match options.path.only() {
        Some(kind) => match kind.traversal() {
            Some(traversal) => {
                renderer
                    .set_traversal(traversal)
                    .with_context(|| format!("--path {kind}"))?;
                (kind, "asked for".to_string())
            }
            None => {
                let (traversal, why) = pick_traversal(&mut renderer, shot)?;
                (kind, format!("asked for; traces with {traversal} ({why})"))
            }
        },
        // Only the traversal paths trace a real lens's rays, sample adaptively
        // and trace each sample at its own time.
        None if real_lens.is_some() || adaptive || moving => pick_traversal(&mut renderer, shot)?,
        None => pick_path(&mut renderer, shot)?,
    };
    // Setting the traversal makes its pipeline; auto's choice renders with each path.
    startup.device_seconds += choice_start.elapsed().as_secs_f64();
    Ok(OpenedPath {
        path: Box::new(GpuPath::new(renderer, kind)?),
        why,
        startup,
    })
}

/// `auto`'s choice of the device, where the CPU may render (`--device auto` and no Vulkan
/// option): the CPU reference when `calibration::decide` says so, from the device's type and
/// its cached calibration. A GPU that is not a CPU implementation and has no calibration yet is
/// calibrated now, once (a failure is a notice: `auto` then times the GPU paths as before).
/// `None`: no decision (the CPU may not render, or no device is there: `open` says why).
fn auto_device(
    options: &PathOptions,
    gpu_options: &GpuOptions,
    samples: u64,
) -> Option<calibration::DeviceDecision> {
    if options.device != Choice::Auto || options.gpu_option().is_some() {
        return None;
    }
    let device = lensray_vulkan::preferred_device(gpu_options).ok()?;
    let key = calibration::key(&device);
    let cached = calibration::load(&key).or_else(|| {
        if device.is_cpu() {
            return None;
        }
        match calibration::measure(gpu_options).and_then(|c| {
            calibration::store(&c)?;
            Ok(c)
        }) {
            Ok(c) => Some(c),
            Err(e) => {
                eprintln!("notice: could not calibrate {}: {e:#}", device.name);
                None
            }
        }
    });
    Some(calibration::decide(&device, cached.as_ref(), samples))
}

fn open_cpu(scene: &Scene, why: &str) -> Result<OpenedPath> {
    let mut path = CpuPath::new();
    let start = Instant::now();
    path.load_scene(scene)?;
    Ok(OpenedPath {
        path: Box::new(path),
        why: why.into(),
        startup: Startup {
            scene_seconds: start.elapsed().as_secs_f64(),
            ..Startup::default()
        },
    })
}

/// Whether `shot` samples adaptively and has a moving camera; an error where the path asked
/// for cannot: only the CPU and the traced paths sample adaptively and trace each sample at
/// its time, and `auto` chooses among the traced ones (`open`).
fn refuse_unsupported(options: &PathOptions, shot: &Shot) -> Result<(bool, bool)> {
    let adaptive = shot.render.noise_threshold.is_some() && !shot.render.shading.is_aov();
    if let Some((kind, why)) = options
        .path
        .only()
        .and_then(|kind| Some((kind, kind.adaptive_refusal()?)))
        .filter(|_| adaptive)
    {
        bail!(
            "--path {kind} does not sample adaptively (--noise-threshold): {why}; use cpu, rayquery, rtpipeline, software or auto"
        );
    }
    let moving = shot.camera.motion.is_some();
    if let Some(kind) = options.path.only().filter(|_| moving) {
        refuse_motion(kind)?;
    }
    Ok((adaptive, moving))
}

/// Opens the path for shots whose meshes move while the shutter is open (motion blur of a
/// file's animated meshes): the CPU path or the software traversal, the paths that meet a mesh
/// where it is at a ray's moment; another path asked for refuses in one line
/// (`moving_objects_refusal`). `auto` takes the CPU where its device choice does (`--device
/// cpu`, a software rasterizer, no usable Vulkan device), else `software`. The path loads
/// `scene` as it stands; each frame loads its moving scene over it.
pub fn open_moving_objects(
    options: &PathOptions,
    scene: &Scene,
    shot: &Shot,
) -> Result<OpenedPath> {
    match options.path.only() {
        Some(PathKind::Cpu | PathKind::Software) => return open(options, scene, shot),
        Some(kind) => return Err(moving_objects_refusal(kind)),
        None => {}
    }
    const WHY: &str = "auto: the cpu and software paths blur moving objects";
    let device = options.device_to_use("--path")?;
    let gpu_options = GpuOptions {
        traversal: Some(lensray_vulkan::Traversal::Software),
        ..options.gpu
    };
    let decision = match device {
        Choice::Only(DeviceKind::Cpu) => return open_cpu(scene, WHY),
        Choice::Only(DeviceKind::Gpu) => None,
        Choice::Auto => auto_device(options, &gpu_options, auto::pixel_samples(shot)),
    };
    if let Some(calibration::DeviceDecision::Cpu(why)) = decision {
        return open_cpu(scene, &format!("{WHY}; {why}"));
    }
    let software = PathOptions {
        path: Choice::Only(PathKind::Software),
        ..*options
    };
    match open(&software, scene, shot) {
        Ok(opened) => Ok(OpenedPath {
            why: WHY.into(),
            ..opened
        }),
        Err(error) if device == Choice::Auto && options.gpu_option().is_none() => {
            eprintln!("notice: rendering on the CPU: no usable GPU ({error:#})");
            open_cpu(scene, "auto: no usable Vulkan device")
        }
        Err(error) => Err(error),
    }
}

/// The error of path `kind` asked to blur moving objects.
pub(crate) fn moving_objects_refusal(kind: PathKind) -> anyhow::Error {
    anyhow::anyhow!(
        "--path {kind} does not blur moving objects (--motion-blur, --rolling-shutter on a file's animated meshes): {}; use --path cpu, software or auto, or --motion-blur off",
        match kind {
            PathKind::Raster | PathKind::Hybrid => "it draws the scene rasterized in one pose",
            _ => "its acceleration structures hold one pose of the scene, where the cpu and software paths meet each mesh where it is at a ray's moment",
        }
    )
}

/// An error where path `kind` cannot render a camera that moves while the shutter is open.
pub(crate) fn refuse_motion(kind: PathKind) -> Result<()> {
    match kind.motion_refusal() {
        Some(why) => bail!(
            "--path {kind} does not render motion blur or a rolling shutter (--motion-blur, --rolling-shutter): {why}; use cpu, rayquery, rtpipeline, software or auto"
        ),
        None => Ok(()),
    }
}

/// The accumulation must match the camera of `shot`, and only traced shadings add samples.
fn check_accumulation(shot: &Shot, accumulation: &Accumulation) -> Result<()> {
    let (camera, settings) = (&shot.camera, &shot.render);
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
    /// How the window adds samples (the path asked for; `auto` decides after the window
    /// opened).
    pub estimator: Estimator,
}

/// The preview window always draws with Vulkan; the path only says who traces the samples.
pub fn preview_options(options: &PathOptions) -> Result<PreviewChoice> {
    // The window is Vulkan's whatever traces, so the Vulkan options stand with the CPU path.
    let device = PathOptions {
        gpu: GpuOptions::default(),
        ..*options
    }
    .device_to_use("--path")?;
    // The hybrid and raster paths trace with the device's fastest traversal (picked as `render`
    // picks it).
    Ok(PreviewChoice {
        gpu: GpuOptions {
            traversal: options.path.only().and_then(PathKind::traversal),
            ..options.gpu
        },
        cpu: device == Choice::Only(DeviceKind::Cpu),
        estimator: options
            .path
            .only()
            .map_or(Estimator::Traced, PathKind::estimator),
    })
}
