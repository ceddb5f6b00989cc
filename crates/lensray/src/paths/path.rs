//! The render-path interface: one algorithm for the thin-lens image on one device. The CPU
//! reference and each GPU path implement it (`crate::paths`), so `render`, `bench` and
//! `preview` drive every path the same way and compare them on equal terms.

use std::fmt;
use std::ops::Range;

use anyhow::Result;
use serde::Serialize;

use lensray_core::camera::flare::ghosts::{FilmLight, FlareLens};
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Image, Progress};
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;
use lensray_vulkan::{Estimator, GhostRequest, Traversal};

/// The algorithms lensray can render with: the one description of a path. What a path needs
/// (its device, the GPU traversal it is tied to) is a property here, not another enum kept in
/// step; `--path` and `--device` choose with [`Choice`].
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum PathKind {
    /// GPU compute pass, closest hits from Vulkan ray queries (VK_KHR_ray_query).
    #[value(name = "rayquery")]
    RayQuery,
    /// GPU ray-tracing pipeline (VK_KHR_ray_tracing_pipeline): the compute pass's per-pixel
    /// work as a ray generation stage, closest hits and shadow rays from traceRayEXT over the
    /// same acceleration structures as rayquery (for devices without ray queries).
    #[value(name = "rtpipeline")]
    RtPipeline,
    /// GPU compute pass, closest hits from lensray's own BVH traversed in the shader: needs no
    /// ray-tracing support.
    Software,
    /// GPU, guided by the raster G-buffer: pixels whose dilated circle of confusion is under
    /// half a pixel take the G-buffer's value (checked by a few traced samples, unbiased), the
    /// others trace a number of samples that grows with it (docs/hybrid.md).
    Hybrid,
    /// GPU, accumulation-buffer depth of field: per camera sample (shared by every pixel) the
    /// scene rasterized through that lens point with a sheared projection, then shaded
    /// (docs/raster.md).
    Raster,
    /// The CPU reference renderer.
    Cpu,
}

/// The devices a path runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum DeviceKind {
    /// The CPU (the reference renderer).
    Cpu,
    /// A Vulkan device.
    Gpu,
}

impl PathKind {
    pub const ALL: [PathKind; 6] = [
        PathKind::RayQuery,
        PathKind::RtPipeline,
        PathKind::Software,
        PathKind::Hybrid,
        PathKind::Raster,
        PathKind::Cpu,
    ];

    pub fn name(self) -> &'static str {
        match self {
            PathKind::RayQuery => "rayquery",
            PathKind::RtPipeline => "rtpipeline",
            PathKind::Software => "software",
            PathKind::Hybrid => "hybrid",
            PathKind::Raster => "raster",
            PathKind::Cpu => "cpu",
        }
    }

    pub fn device(self) -> DeviceKind {
        match self {
            PathKind::Cpu => DeviceKind::Cpu,
            _ => DeviceKind::Gpu,
        }
    }

    pub fn is_gpu(self) -> bool {
        self.device() == DeviceKind::Gpu
    }

    /// The traversal the path is (`None`: the CPU, or the hybrid and raster paths, which trace
    /// with the device's fastest).
    pub fn traversal(self) -> Option<Traversal> {
        match self {
            PathKind::RayQuery => Some(Traversal::RayQuery),
            PathKind::RtPipeline => Some(Traversal::RtPipeline),
            PathKind::Software => Some(Traversal::Software),
            PathKind::Hybrid | PathKind::Raster | PathKind::Cpu => None,
        }
    }

    /// How the path adds samples on the Vulkan device (the CPU and both traversals trace).
    pub fn estimator(self) -> Estimator {
        match self {
            PathKind::Hybrid => Estimator::Hybrid,
            PathKind::Raster => Estimator::Raster,
            PathKind::RayQuery | PathKind::RtPipeline | PathKind::Software | PathKind::Cpu => {
                Estimator::Traced
            }
        }
    }

    /// Why the path cannot sample adaptively (`--noise-threshold`), or `None` when it can: the
    /// CPU and the traced paths give each pixel its own samples; the raster path's samples are
    /// passes over the whole image, one camera sample shared by every pixel, and the hybrid's
    /// plan already sets each pixel's samples, in the per-pixel buffer adaptive sampling uses
    /// (docs/adaptive.md).
    pub fn adaptive_refusal(self) -> Option<&'static str> {
        match self {
            PathKind::Raster => Some(
                "its samples are raster passes of the whole image, one camera sample shared by every pixel",
            ),
            PathKind::Hybrid => Some("its plan already sets how many samples each pixel takes"),
            PathKind::Cpu | PathKind::RayQuery | PathKind::RtPipeline | PathKind::Software => None,
        }
    }

    /// Why the path cannot take a camera that moves while the shutter is open (motion blur,
    /// a rolling shutter: `camera::motion`), or `None` where it traces each sample at its time.
    pub fn motion_refusal(self) -> Option<&'static str> {
        match self {
            PathKind::Raster => {
                Some("its samples are raster passes of the whole image, through one camera pose")
            }
            PathKind::Hybrid => Some("its plan reprojects the image of one camera pose"),
            PathKind::Cpu | PathKind::RayQuery | PathKind::RtPipeline | PathKind::Software => None,
        }
    }

    /// How the path renders a real lens (`camera::real_lens`).
    pub fn real_lens_support(self) -> RealLensSupport {
        match self {
            PathKind::Cpu | PathKind::RayQuery | PathKind::RtPipeline | PathKind::Software => {
                RealLensSupport::Traced
            }
            PathKind::Raster => RealLensSupport::FirstOrder,
            // Its shortcuts and windows bound where thin-lens rays go, not where a real
            // lens's aberrated, vignetted rays go.
            PathKind::Hybrid => RealLensSupport::Refused,
        }
    }

    /// The path that traces every sample with `traversal`.
    pub fn of_traversal(traversal: Traversal) -> PathKind {
        match traversal {
            Traversal::RayQuery => PathKind::RayQuery,
            Traversal::RtPipeline => PathKind::RtPipeline,
            Traversal::Software => PathKind::Software,
        }
    }
}

/// What a path does with a real lens.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RealLensSupport {
    /// Every camera ray is traced through the lens's surfaces.
    Traced,
    /// The lens's first-order model: a thin lens at the entrance pupil, with the pupil's
    /// radius and the real lens's focus (no aberration, distortion or vignetting).
    FirstOrder,
    /// The path says so in one line.
    Refused,
}

impl fmt::Display for PathKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for DeviceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DeviceKind::Cpu => "cpu",
            DeviceKind::Gpu => "gpu",
        })
    }
}

/// `auto`, or one of `T` (`--path`, `--device`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Choice<T> {
    /// lensray decides (`auto`).
    #[default]
    Auto,
    Only(T),
}

/// `--path`: `auto` (the fastest path the device supports, measured on a small render of the
/// shot) or a path.
pub type PathChoice = Choice<PathKind>;
/// `--device`: `auto` (a Vulkan device when one is usable, else the CPU) or a device.
pub type DeviceChoice = Choice<DeviceKind>;

impl<T: Copy> Choice<T> {
    /// The one asked for; `None` for `auto`.
    pub fn only(self) -> Option<T> {
        match self {
            Choice::Auto => None,
            Choice::Only(t) => Some(t),
        }
    }
}

impl<T> From<T> for Choice<T> {
    fn from(t: T) -> Self {
        Choice::Only(t)
    }
}

impl<T: fmt::Display> fmt::Display for Choice<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Choice::Auto => f.write_str("auto"),
            Choice::Only(t) => t.fmt(f),
        }
    }
}

/// `auto` followed by every value of `T` (clap's list of a `Choice`).
const fn choices<T: Copy, const N: usize, const M: usize>(all: [T; N]) -> [Choice<T>; M] {
    let mut out = [Choice::Auto; M];
    let mut i = 0;
    while i < N {
        out[i + 1] = Choice::Only(all[i]);
        i += 1;
    }
    out
}

const PATH_CHOICES: [PathChoice; 7] = choices(PathKind::ALL);
const DEVICE_CHOICES: [DeviceChoice; 3] = choices([DeviceKind::Cpu, DeviceKind::Gpu]);

macro_rules! choice_value_enum {
    ($t:ty, $all:expr, $auto_help:literal) => {
        impl clap::ValueEnum for Choice<$t> {
            fn value_variants<'a>() -> &'a [Self] {
                &$all
            }

            fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
                match self {
                    Choice::Auto => {
                        Some(clap::builder::PossibleValue::new("auto").help($auto_help))
                    }
                    Choice::Only(t) => clap::ValueEnum::to_possible_value(t),
                }
            }
        }
    };
}

choice_value_enum!(
    PathKind,
    PATH_CHOICES,
    "The fastest path the device supports, for the shot"
);
choice_value_enum!(
    DeviceKind,
    DEVICE_CHOICES,
    "A Vulkan device when one is usable, else the CPU"
);

/// How a path's trace time was measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Clock {
    /// GPU timestamp queries around each dispatch (a pipeline's first dispatch excluded: drivers
    /// may compile it lazily).
    GpuTimestamps,
    /// Host wall clock.
    #[default]
    WallClock,
}

/// What a path did since it was opened.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PathReport {
    /// Camera and shadow rays traced.
    pub rays: u64,
    /// Time spent tracing, seconds.
    pub trace_seconds: f64,
    pub clock: Clock,
    /// Time spent building the loaded scene's acceleration structures, seconds.
    pub build_seconds: f64,
    /// Bytes of the acceleration structures the path traverses (device memory for GPU paths,
    /// host memory for the CPU).
    pub accel_bytes: u64,
    /// Bytes of all device memory the path holds at its peak so far (0 on the CPU).
    pub peak_device_bytes: u64,
    /// AOV images made (GPU: raster G-buffer passes; CPU: traced AOV images), and their time
    /// (GPU: timestamps of the G-buffer draws; CPU: wall clock).
    pub aov_passes: u64,
    pub aov_seconds: f64,
    /// What the host asked of the device (0 on the CPU): queue submissions, waits that block the
    /// host on the device, and bytes read back from it.
    pub submits: u64,
    pub cpu_waits: u64,
    pub readback_bytes: u64,
    /// Wall-clock seconds of bringing sums to the host (`read_sums`; 0 on the CPU, whose sums
    /// are there).
    pub readback_seconds: f64,
    /// Time the driver took to make the path's pipelines (its shader compiler), seconds: long
    /// on a device's first use, apart from the render's time.
    pub compile_seconds: f64,
    /// Samples adaptive renders took, over all their pixels (0: no render was adaptive).
    pub adaptive_samples: u64,
}

impl PathReport {
    pub fn rays_per_second(&self) -> f64 {
        self.rays as f64 / self.trace_seconds.max(1e-12)
    }

    /// What happened between `earlier` and `self` (peaks and sizes are kept).
    pub fn since(&self, earlier: &PathReport) -> PathReport {
        PathReport {
            rays: self.rays - earlier.rays,
            trace_seconds: self.trace_seconds - earlier.trace_seconds,
            aov_passes: self.aov_passes - earlier.aov_passes,
            aov_seconds: self.aov_seconds - earlier.aov_seconds,
            submits: self.submits - earlier.submits,
            cpu_waits: self.cpu_waits - earlier.cpu_waits,
            readback_bytes: self.readback_bytes - earlier.readback_bytes,
            readback_seconds: self.readback_seconds - earlier.readback_seconds,
            compile_seconds: self.compile_seconds - earlier.compile_seconds,
            adaptive_samples: self.adaptive_samples - earlier.adaptive_samples,
            ..*self
        }
    }
}

/// One render path, open on its device (`Send`: `render` closes it on a thread while the image
/// encodes).
pub trait RenderPath: Send {
    fn kind(&self) -> PathKind;

    /// The device it runs on, in words ("llvmpipe (LLVM 15.0.6, 256 bits)", "CPU, 2 threads, Embree avx2").
    fn device_name(&self) -> String;

    /// Loads `scene` (and builds what the path traverses), replacing any earlier scene.
    fn load_scene(&mut self, scene: &Scene) -> Result<()>;

    /// Loads `scene` with the meshes `motion` names moving through its steps while the shutter
    /// is open (motion blur of moving objects). The CPU path and the software traversal blur
    /// them (`paths::open_moving_objects` opens no other); the others refuse in one line.
    fn load_moving_scene(&mut self, scene: &Scene, motion: &ObjectMotion) -> Result<()> {
        let _ = (scene, motion);
        Err(super::moving_objects_refusal(self.kind()))
    }

    /// Adds samples `samples` of every pixel of `shot` (thin lens: `Unlit` or `Lit`) to
    /// `accumulation`, which has the camera's size. Any split of a range into calls gives the
    /// same sums. A GPU path keeps the sums on its device from call to call: read them with
    /// `read_sums`. `progress(done, total)` reports the work done in the call.
    fn add_samples(
        &mut self,
        shot: &Shot,
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()>;

    /// Renders `shot` adaptively (`shot.render.noise_threshold`, `film::adaptive`) into
    /// `accumulation`, new and the camera's size. The CPU and the traced GPU paths sample
    /// adaptively (`PathKind::adaptive_refusal`); `paths::open` refuses the others before they
    /// render.
    fn add_adaptive(
        &mut self,
        shot: &Shot,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()> {
        let _ = (shot, accumulation, progress);
        anyhow::bail!(
            "--path {} does not sample adaptively (--noise-threshold): use cpu, rayquery, rtpipeline, software or auto",
            self.kind()
        )
    }

    /// The AOV of `shot` (its shading: `Depth`, `Normal`, `Albedo`): the surface seen by the
    /// aperture-centre ray at each pixel centre (GPU paths: the raster G-buffer).
    fn aov(&mut self, shot: &Shot) -> Result<Image>;

    /// The view depth of the surface seen through the centre of `pixel` by the aperture-centre
    /// ray, `None` where no surface is (autofocus, click to focus).
    fn focus_depth_at(&mut self, camera: &Camera, pixel: [u32; 2]) -> Result<Option<f32>>;

    /// Brings `accumulation`'s sums to the host (`Accumulation::host`): a GPU path keeps them on
    /// its device while it adds samples, and reads them back here, once. An error when another
    /// device holds them.
    fn read_sums(&mut self, accumulation: &mut Accumulation) -> Result<()>;

    /// The mean of each pixel's samples of `accumulation`, its sums read first.
    fn image_of(&mut self, accumulation: &mut Accumulation) -> Result<Image> {
        self.read_sums(accumulation)?;
        Ok(accumulation.image()?)
    }

    /// A real lens's light from a distant source (`--flare`: ghosts and the source's own
    /// image), traced and drawn on the path's device; `None` where the flare traces it on the
    /// CPU (`FlareLens::distant_source`).
    fn ghost_light(
        &mut self,
        camera: &Camera,
        lens: &FlareLens,
        request: &GhostRequest,
    ) -> Option<Result<FilmLight>> {
        let _ = (camera, lens, request);
        None
    }

    /// What the path did since it was opened.
    fn report(&self) -> PathReport;

    /// Releases the device; with validation on, fails on any message of the layer, the leak
    /// report of the device's destruction included.
    fn close(self: Box<Self>) -> Result<()>;

    /// The whole image of `shot`: traced samples 0..spp (adaptively with a noise threshold), or
    /// the AOV.
    fn render(&mut self, shot: &Shot, progress: &mut Progress) -> Result<Image> {
        if shot.render.noise_threshold.is_some() && !shot.render.shading.is_aov() {
            let mut accumulation = Accumulation::new(shot.camera.width, shot.camera.height);
            self.add_adaptive(shot, &mut accumulation, progress)?;
            return self.image_of(&mut accumulation);
        }
        let (image, ()) = lensray_core::film::whole_image(
            self,
            progress,
            shot,
            |this, progress| lensray_core::film::one_pass(progress, || this.aov(shot)),
            |this, samples, accumulation, progress| {
                this.add_samples(shot, samples, accumulation, progress)
            },
            |this, accumulation| this.read_sums(accumulation),
        )?;
        Ok(image)
    }
}
