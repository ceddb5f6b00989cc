//! [`GpuRenderer`]: the device and the passes it owns, the scene on the device, and the
//! renderer's entries (G-buffer, render, AOVs, sums). How samples are added lives in
//! `estimators`, adaptive sampling's rounds in `adaptive`; the passes made on first use in `raster`; what the preview records into its
//! frames in `frames`; the probes' hooks in `probe_hooks`. The fields are private to this
//! module: the rest of the crate (the preview included) goes through these functions.

pub(crate) mod adaptive;
mod batch;
mod estimators;
mod frames;
#[cfg(feature = "probes")]
mod probe_hooks;
mod raster;

use std::sync::Arc;

use glam::Vec3;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::core::device::Context;
use crate::core::error::vk_err;
use crate::core::instance::Instance;
use crate::core::surface::WindowSurface;
use crate::passes::ghosts::GhostRequest;
use crate::passes::trace::TracePass;
use crate::scene::SceneBuffers;
use crate::{
    BvhParams, Counters, DeviceReport, Estimator, GBuffer, GpuError, GpuOptions, Timings,
    Traversal, ValidationLog,
};
use lensray_core::camera::flare::ghosts::{FilmLight, FlareLens};
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Image, Progress};
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::Scene;
use lensray_core::settings::{Shading, Shot};

pub(crate) use batch::SampleBatch;
pub use estimators::SamplesAdded;
use raster::RasterPasses;

/// The Vulkan renderer. Fields drop in order; everything holds an `Arc` to the device context,
/// which is destroyed last, then the instance.
pub struct GpuRenderer {
    trace: TracePass,
    /// The G-buffer, the raster path's visibility and the hybrid's plan, made on first use.
    raster: RasterPasses,
    scene: Option<SceneBuffers>,
    bvh_params: BvhParams,
    timings: Timings,
    /// Seconds the Vulkan instance and device took to open (what no pipeline adds to).
    open_seconds: f64,
    log: ValidationLog,
    ctx: Arc<Context>,
}

impl GpuRenderer {
    /// Opens the device; a clear error when no device (or not the chosen one) can run the
    /// requested traversal.
    pub fn new(options: &GpuOptions) -> Result<Self, GpuError> {
        Ok(Self::open(options, None)?.0)
    }

    /// Opens the device, able to present to `window` when given (returned as a surface).
    pub(crate) fn open(
        options: &GpuOptions,
        window: Option<(RawDisplayHandle, RawWindowHandle)>,
    ) -> Result<(Self, Option<WindowSurface>), GpuError> {
        let window_extensions = match window {
            Some((display, _)) => ash_window::enumerate_required_extensions(display)
                .map_err(vk_err("vkEnumerateInstanceExtensionProperties"))?,
            None => &[],
        };
        let start = std::time::Instant::now();
        let instance = Arc::new(Instance::new(options.validate, window_extensions)?);
        let log = instance.log.clone();
        let surface = window
            .map(|(display, window)| WindowSurface::new(&instance, display, window))
            .transpose()?;
        let ctx = Arc::new(Context::new(instance, options, surface.as_ref())?);
        let open_seconds = start.elapsed().as_secs_f64();
        let trace = TracePass::new(&ctx)?;
        let renderer = Self {
            trace,
            raster: RasterPasses::new(&ctx),
            scene: None,
            bvh_params: BvhParams::default(),
            timings: Timings::default(),
            open_seconds,
            log,
            ctx,
        };
        Ok((renderer, surface))
    }

    /// Seconds the Vulkan instance and device took to open, of the time `new` took (the rest
    /// is pipelines).
    pub fn open_seconds(&self) -> f64 {
        self.open_seconds
    }

    pub fn device_name(&self) -> String {
        self.ctx.report.name.clone()
    }

    pub fn device_report(&self) -> DeviceReport {
        self.ctx.report.clone()
    }

    /// The traversals this device can trace with (what it was opened for).
    pub fn traversals(&self) -> Vec<Traversal> {
        self.trace.pipelines.traversals()
    }

    /// The traversal `render` uses.
    pub fn traversal(&self) -> Traversal {
        self.trace.pipelines.traversal()
    }

    /// Uses `traversal` from now on (the preview's later frames included); an error when the
    /// device was not opened for it.
    pub fn set_traversal(&mut self, traversal: Traversal) -> Result<(), GpuError> {
        if self.scene.as_ref().is_some_and(|scene| scene.moving) {
            moving_traversal(traversal)?;
        }
        self.trace.pipelines.set_traversal(traversal)
    }

    /// Uploads the scene and builds the structures of the device's traversals: acceleration
    /// structures, the software traversal's BVH, or both (replacing any earlier scene).
    pub fn load_scene(&mut self, scene: &Scene) -> Result<(), GpuError> {
        self.load_moving_scene(scene, None)
    }

    /// [`Self::load_scene`] with the meshes `motion` names moving through its steps while the
    /// shutter is open: the software traversal meets each where it is at a ray's moment; the
    /// acceleration structures (ray queries, the ray-tracing pipeline) and the raster passes
    /// hold the scene's own pose.
    pub fn load_moving_scene(
        &mut self,
        scene: &Scene,
        motion: Option<&ObjectMotion>,
    ) -> Result<(), GpuError> {
        if motion.is_some() {
            moving_traversal(self.traversal())?;
        }
        self.scene = None;
        let buffers = SceneBuffers::new(&self.ctx, scene, motion, &self.bvh_params)?;
        self.raster.bind_scene(&buffers);
        self.trace.pipelines.bind_scene(&buffers)?;
        let t = &mut self.timings;
        let accel = buffers.accel.as_ref();
        t.accel_build_gpu_ms = accel.map_or(0.0, |a| a.build_gpu_ns * 1e-6);
        t.accel_build_wall_ms = accel.map_or(0.0, |a| a.build_wall_ns * 1e-6);
        t.blas_bytes = accel.map_or(0, |a| a.blas_bytes);
        t.blas_compacted_bytes = accel.map_or(0, |a| a.blas_compacted_bytes);
        t.accel_bytes = accel.map_or(0, |a| a.device_bytes);
        t.bvh_bytes = buffers.bvh.as_ref().map_or(0, |b| b.bytes);
        t.bvh_build_ms = buffers.bvh.as_ref().map_or(0.0, |b| b.build_ns * 1e-6);
        self.scene = Some(buffers);
        Ok(())
    }

    /// The raster G-buffer of the loaded scene seen by `camera` (one sample at each pixel
    /// centre, no depth of field). The images stay on the device for later passes.
    pub fn render_gbuffer(
        &mut self,
        camera: &Camera,
        background: Vec3,
    ) -> Result<GBuffer, GpuError> {
        check_size(camera)?;
        if self.scene.is_none() {
            return Err(GpuError::NoScene);
        }
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let pass = self.raster.gbuffer_pass(Some(scene))?;
        let gbuffer = pass.render(scene, camera, background)?;
        self.timings.gbuffer_passes += 1;
        self.timings.gbuffer_gpu_ms += pass.last_gpu_ms;
        Ok(gbuffer)
    }

    /// Renders `shot` in its shading: `Unlit` and `Lit` through the thin lens with the compute
    /// pass (adaptively with a noise threshold: `add_adaptive`); `Depth`, `Normal` and `Albedo`
    /// from the G-buffer. `progress(done, total)` counts pixel-samples (rounds' ends when
    /// adaptive).
    pub fn render(&mut self, shot: &Shot, progress: &mut Progress) -> Result<Image, GpuError> {
        let camera = &shot.camera;
        check_size(camera)?;
        if shot.render.spp == 0 {
            return Err(GpuError::Invalid("spp must be at least 1".into()));
        }
        if self.scene.is_none() {
            return Err(GpuError::NoScene);
        }
        if camera.width > self.ctx.report.max_image_dimension_2d
            || camera.height > self.ctx.report.max_image_dimension_2d
        {
            return Err(GpuError::Invalid(format!(
                "image {}x{} exceeds the device's maximum image dimension {}",
                camera.width, camera.height, self.ctx.report.max_image_dimension_2d
            )));
        }
        let (image, ()) = lensray_core::film::whole_image(
            self,
            progress,
            shot,
            |this, progress| lensray_core::film::one_pass(progress, || this.aov(shot)),
            |this, samples, accumulation, progress| match shot.render.noise_threshold {
                Some(_) => this.add_adaptive(shot, accumulation, progress).map(|_| ()),
                None => this
                    .add_samples(shot, Estimator::Traced, samples, accumulation, progress)
                    .map(|_| ()),
            },
            |this, accumulation| this.read_sums(accumulation),
        )?;
        Ok(image)
    }

    /// The AOV of `shot` (its shading: `Depth`, `Normal`, `Albedo`) read from the G-buffer.
    pub fn aov(&mut self, shot: &Shot) -> Result<Image, GpuError> {
        let aov = shot.render.shading;
        if !aov.is_aov() {
            return Err(GpuError::Invalid(format!(
                "{aov:?} is traced: it is not an AOV of the G-buffer"
            )));
        }
        let g = self.render_gbuffer(&shot.camera, shot.render.background)?;
        let pixels = (0..g.coverage.len())
            .map(|i| match aov {
                Shading::Depth => Vec3::splat(g.view_depth[i]),
                Shading::Normal => g.normal[i],
                _ => g.albedo[i],
            })
            .collect();
        Ok(Image {
            width: g.width,
            height: g.height,
            pixels,
        })
    }

    /// Brings `accumulation`'s sums to the host when this renderer holds them on its device
    /// (one read-back of the image's sums); an error when another device holds them.
    pub fn read_sums(&mut self, accumulation: &mut Accumulation) -> Result<(), GpuError> {
        self.trace.films.read(accumulation)
    }

    /// A real lens's ghosts and direct light from a distant source (`request`), traced and
    /// drawn on this device (shaders/passes/ghosts.comp) as lensray-core's `lens` does on the
    /// CPU: `camera`'s lens, focused and stopped, and its aperture.
    pub fn ghost_light(
        &self,
        camera: &Camera,
        lens: &FlareLens,
        request: &GhostRequest,
    ) -> Result<FilmLight, GpuError> {
        crate::passes::ghosts::distant_source(&self.ctx, camera, lens, request)
    }

    /// Destroys every Vulkan object, then, with validation on, fails on any message the layer
    /// reported, the leak report of the device's and instance's destruction included.
    pub fn close(self) -> Result<(), GpuError> {
        let log = self.log.clone();
        drop(self);
        check_validation_log(&log)
    }

    /// Validation warnings and errors so far (empty without validation).
    pub fn validation_messages(&self) -> Vec<String> {
        self.log.messages()
    }

    /// A handle to the validation log that outlives the renderer: the layer reports leaked
    /// objects while the device and instance are destroyed.
    pub fn validation_log(&self) -> ValidationLog {
        self.log.clone()
    }

    pub fn timings(&self) -> Timings {
        self.timings
    }

    /// Submissions, host waits and bytes read back since the device was opened.
    pub fn counters(&self) -> Counters {
        self.ctx.counters.snapshot()
    }

    /// Bytes of device memory allocated now (every buffer and image of the renderer).
    pub fn allocated_bytes(&self) -> u64 {
        self.ctx.allocator().generate_report().total_allocated_bytes
    }
}

impl Drop for GpuRenderer {
    fn drop(&mut self) {
        // Nothing of a submission still running may be destroyed: the passes and buffers drop
        // after this (the device's idle wait comes only with the context, last).
        let _ = self.ctx.wait_all();
    }
}

/// After every object of a renderer was dropped: any validation message (the leak report of
/// the device's and instance's destruction included) is an error, and so is an instance still
/// alive (an object kept elsewhere).
pub(crate) fn check_validation_log(log: &ValidationLog) -> Result<(), GpuError> {
    let messages = log.messages();
    if let Some(first) = messages.first() {
        return Err(GpuError::Validation {
            count: messages.len(),
            first: first.lines().next().unwrap_or("").to_string(),
        });
    }
    if !log.instance_destroyed() {
        return Err(GpuError::Invalid(
            "the Vulkan instance outlived the renderer: an object leaked".into(),
        ));
    }
    Ok(())
}

/// What accumulating samples of `shot` needs: an image the device can hold, a traced shading.
pub(crate) fn check_samples(shot: &Shot) -> Result<(), GpuError> {
    check_size(&shot.camera)?;
    if shot.render.shading.is_aov() {
        return Err(GpuError::Invalid(format!(
            "{:?} is read from the G-buffer: it has no samples to accumulate",
            shot.render.shading
        )));
    }
    Ok(())
}

pub(crate) fn check_size(camera: &Camera) -> Result<(), GpuError> {
    if camera.width == 0 || camera.height == 0 {
        return Err(GpuError::Invalid(format!(
            "image {}x{} is empty",
            camera.width, camera.height
        )));
    }
    Ok(())
}

/// An error unless `traversal` meets moving meshes at a ray's moment: the software traversal's
/// BVH holds the box each sweeps, the acceleration structures one pose.
fn moving_traversal(traversal: Traversal) -> Result<(), GpuError> {
    match traversal {
        Traversal::Software => Ok(()),
        other => Err(GpuError::Invalid(format!(
            "the {other} traversal does not meet meshes that move while the shutter is open: \
             its acceleration structures hold one pose of the scene (the software traversal's \
             BVH holds the box each sweeps)"
        ))),
    }
}
