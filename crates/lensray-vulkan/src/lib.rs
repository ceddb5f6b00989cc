//! The Vulkan renderer (ash, raw Vulkan 1.2): a raster G-buffer pass and a thin-lens compute
//! pass that finds closest hits with one of two [`Traversal`]s: VK_KHR_ray_query against
//! per-mesh BLASes under one TLAS, or a software traversal of the project's own BVH in the
//! shader, which needs no ray-tracing support.
//!
//! The camera is the Rust [`Camera`]: the raster pass projects with `clip_from_world()`, the
//! compute pass generates rays with `shaders/include/camera.glsl`, a function-by-function
//! mirror of `lensray-core/src/camera`, fed with the camera's own matrices. This module is the only place in
//! the crate with `unsafe` code; every Vulkan object is owned by a Rust value and destroyed on
//! drop.
//!
//! Layers, each a folder (the shaders in `shaders/` have the same ones):
//! - `core`: Vulkan itself: instance and validation, device and submissions, buffers, images,
//!   queries, pipelines, embedded SPIR-V, host data in the shaders' layouts, errors;
//! - `scene`: a scene on the device: its arrays, acceleration structures, the software BVH;
//! - `passes`: the renderer's passes: G-buffer, thin-lens trace, the raster path's visibility
//!   pass and the hybrid's plan, each with the renderer's entry points of its path;
//! - `present`: the preview window: surface, swapchain, frames in flight, resolve, view pass,
//!   egui overlay, and the viewer that drives a frame;
//! - `probes` (feature `probes`, on for the crate's tests and benches): GLSL mirror checks,
//!   the hybrid plan's host reference, shared-struct layouts, the preview's view routes, sample
//!   generation cost, pass timings.
//!
//! This file holds [`GpuRenderer`], which owns the device and the passes, and its options.
//!
//! ```no_run
//! use lensray_vulkan::{GpuOptions, GpuRenderer};
//! # fn demo(scene: &lensray_core::scene::Scene,
//! #         shot: &lensray_core::settings::Shot) -> Result<(), lensray_vulkan::GpuError> {
//! let mut gpu = GpuRenderer::new(&GpuOptions::default())?;
//! gpu.load_scene(scene)?; // BLAS per mesh (compacted) + TLAS and/or BVH, scene arrays uploaded
//! println!("tracing with {} of {:?}", gpu.traversal(), gpu.traversals());
//! let image = gpu.render(shot, &mut |done, total| eprint!("\r{done}/{total}"))?;
//! let camera = &shot.camera;
//! let gbuffer = gpu.render_gbuffer(camera, shot.render.background)?;
//! let focus = lensray_vulkan::focus_distance_at(&gbuffer, camera.width / 2, camera.height / 2);
//! println!("{} rays/s", gpu.timings().rays_per_second().unwrap_or(0.0));
//! # let _ = (image, focus); Ok(()) }
//! ```

// `pub` means exported: what no other crate can reach is `pub(crate)`.
#![deny(unreachable_pub)]
#![deny(clippy::undocumented_unsafe_blocks)]

mod core;
mod estimators;
mod passes;
mod present;
#[cfg(feature = "probes")]
mod probes;
mod scene;
mod traversal;
mod upload;

use std::sync::Arc;

use glam::Vec3;

use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Image, Progress};
use lensray_core::scene::Scene;
use lensray_core::settings::{Shading, Shot};

pub use core::adapter::DeviceReport;
pub use core::counters::Counters;
pub use core::error::GpuError;
pub use core::instance::ValidationLog;
pub use estimators::SamplesAdded;
pub use passes::gbuffer::{focus_distance_at, GBuffer};
pub use passes::trace::Timings;
pub use present::overlay::OverlayFrame;
pub use present::viewer::{
    FrameRequest, FrameResult, FrameTimes, HostSamples, PresentMode, Viewer, ViewerOptions,
};
#[cfg(feature = "probes")]
pub use probes::hybrid_plan::{device_plan, host_plan, read_plan, Plan};
#[cfg(feature = "probes")]
pub use probes::layouts::LayoutReport;
#[cfg(feature = "probes")]
pub use probes::mirrors::{ProbeQuery, ProbeResult};
#[cfg(feature = "probes")]
pub use probes::timing::{bench, bench_renderer, BenchedPass, PassBenchOptions, PassBenchReport};
#[cfg(feature = "probes")]
pub use probes::view_routes::ViewRoutes;
pub use scene::bvh::BvhParams;
pub use traversal::Traversal;

/// How a render adds samples to an accumulation: traced per pixel through the lens with the
/// renderer's [`Traversal`], rasterized once per lens sample through a sheared projection
/// (every pixel sharing the sample), or the hybrid's mix of the G-buffer and traced samples
/// where its plan says the lens matters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Estimator {
    #[default]
    Traced,
    Raster,
    Hybrid,
}

use core::device::Context;
use core::error::vk_err;
use core::instance::Instance;
use core::surface::WindowSurface;
use passes::gbuffer::GBufferPass;
use passes::hybrid_plan::HybridPlanPass;
use passes::trace::TracePass;
use passes::visibility::VisibilityPass;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};
use scene::SceneBuffers;

/// How to open the GPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpuOptions {
    /// Enable VK_LAYER_KHRONOS_validation (with synchronization validation) and record its
    /// warnings and errors (see [`GpuRenderer::validation_messages`]).
    pub validate: bool,
    /// Use this device of [`list_devices`]; default: the best one for `traversal` (discrete
    /// first).
    pub device_index: Option<usize>,
    /// The traversal to open the device for: `RayQuery` needs a device with ray queries,
    /// `Software` enables no ray-tracing extension and builds only the BVH; None opens both
    /// where the device has ray queries (ray queries in use first), else software only.
    pub traversal: Option<Traversal>,
    /// Treat every device as lacking VK_KHR_ray_query (tests of the software traversal on a
    /// device that has it).
    pub hide_ray_query: bool,
}

/// Every Vulkan device, with what it lacks for lensray (for `lensray info`).
pub fn list_devices() -> Result<Vec<DeviceReport>, GpuError> {
    let instance = Instance::new(false, &[])?;
    Ok(core::adapter::enumerate(&instance.instance)?
        .into_iter()
        .map(|(_, r)| r)
        .collect())
}

/// The device [`GpuRenderer::new`] would open with `options` (the same selection), without
/// opening it: the instance and the device list only.
pub fn preferred_device(options: &GpuOptions) -> Result<DeviceReport, GpuError> {
    let instance = Instance::new(false, &[])?;
    let mut devices = core::adapter::enumerate(&instance.instance)?;
    if options.hide_ray_query {
        for (_, report) in &mut devices {
            report.hide_ray_query();
        }
    }
    Ok(core::adapter::select(&devices, options.device_index, options.traversal)?.1)
}

/// The Vulkan renderer. Fields drop in order; everything holds an `Arc` to the device context,
/// which is destroyed last, then the instance.
pub struct GpuRenderer {
    trace: TracePass,
    /// The raster G-buffer (AOVs, focus picking, the hybrid's plan, the preview), made on its
    /// first use: a traced render compiles no raster pipeline.
    gbuffer: Option<GBufferPass>,
    /// The raster path's pass, made on its first use.
    visibility: Option<VisibilityPass>,
    /// The hybrid path's plan on the device (the render path's and the preview's).
    hybrid_plan: Option<HybridPlanPass>,
    scene: Option<SceneBuffers>,
    bvh_params: BvhParams,
    timings: Timings,
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
    fn open(
        options: &GpuOptions,
        window: Option<(RawDisplayHandle, RawWindowHandle)>,
    ) -> Result<(Self, Option<WindowSurface>), GpuError> {
        let window_extensions = match window {
            Some((display, _)) => ash_window::enumerate_required_extensions(display)
                .map_err(vk_err("vkEnumerateInstanceExtensionProperties"))?,
            None => &[],
        };
        let instance = Arc::new(Instance::new(options.validate, window_extensions)?);
        let log = instance.log.clone();
        let surface = window
            .map(|(display, window)| WindowSurface::new(&instance, display, window))
            .transpose()?;
        let ctx = Arc::new(Context::new(instance, options, surface.as_ref())?);
        let trace = TracePass::new(&ctx)?;
        let renderer = Self {
            trace,
            gbuffer: None,
            visibility: None,
            hybrid_plan: None,
            scene: None,
            bvh_params: BvhParams::default(),
            timings: Timings::default(),
            log,
            ctx,
        };
        Ok((renderer, surface))
    }

    pub fn device_name(&self) -> String {
        self.ctx.report.name.clone()
    }

    pub fn device_report(&self) -> DeviceReport {
        self.ctx.report.clone()
    }

    /// The traversals this device can trace with (what it was opened for).
    pub fn traversals(&self) -> Vec<Traversal> {
        self.trace.traversals()
    }

    /// The traversal `render` uses.
    pub fn traversal(&self) -> Traversal {
        self.trace.traversal()
    }

    /// Uses `traversal` from now on (the preview's later frames included); an error when the
    /// device was not opened for it.
    pub fn set_traversal(&mut self, traversal: Traversal) -> Result<(), GpuError> {
        self.trace.set_traversal(traversal)
    }

    /// Uploads the scene and builds the structures of the device's traversals: acceleration
    /// structures, the software traversal's BVH, or both (replacing any earlier scene).
    pub fn load_scene(&mut self, scene: &Scene) -> Result<(), GpuError> {
        self.scene = None;
        let buffers = SceneBuffers::new(&self.ctx, scene, &self.bvh_params)?;
        if let Some(gbuffer) = &self.gbuffer {
            gbuffer.bind_scene(&buffers);
        }
        self.trace.bind_scene(&buffers);
        if let Some(visibility) = &self.visibility {
            visibility.bind_scene(&buffers);
        }
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
        self.gbuffer_pass()?;
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let pass = self.gbuffer.as_mut().expect("made above");
        let gbuffer = pass.render(scene, camera, background)?;
        self.timings.gbuffer_passes += 1;
        self.timings.gbuffer_gpu_ms += pass.last_gpu_ms;
        Ok(gbuffer)
    }

    /// The G-buffer pass, made (and bound to the loaded scene) on first use.
    fn gbuffer_pass(&mut self) -> Result<&mut GBufferPass, GpuError> {
        if self.gbuffer.is_none() {
            let pass = GBufferPass::new(&self.ctx)?;
            if let Some(scene) = &self.scene {
                pass.bind_scene(scene);
            }
            self.gbuffer = Some(pass);
        }
        Ok(self.gbuffer.as_mut().expect("made above"))
    }

    /// Renders `shot` in its shading: `Unlit` and `Lit` through the thin lens with the compute
    /// pass; `Depth`, `Normal` and `Albedo` from the G-buffer. `progress(done, total)` counts
    /// pixel-samples.
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
            |this, samples, accumulation, progress| {
                this.accumulate(shot, samples, accumulation, progress)
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
fn check_validation_log(log: &ValidationLog) -> Result<(), GpuError> {
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
fn check_samples(shot: &Shot) -> Result<(), GpuError> {
    check_size(&shot.camera)?;
    if shot.render.shading.is_aov() {
        return Err(GpuError::Invalid(format!(
            "{:?} is read from the G-buffer: it has no samples to accumulate",
            shot.render.shading
        )));
    }
    Ok(())
}

fn check_size(camera: &Camera) -> Result<(), GpuError> {
    if camera.width == 0 || camera.height == 0 {
        return Err(GpuError::Invalid(format!(
            "image {}x{} is empty",
            camera.width, camera.height
        )));
    }
    Ok(())
}
