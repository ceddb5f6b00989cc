//! The Vulkan renderer (ash, raw Vulkan 1.2): a raster G-buffer pass and a thin-lens compute
//! pass that finds closest hits with one of two [`Traversal`]s: VK_KHR_ray_query against
//! per-mesh BLASes under one TLAS, or a software traversal of the project's own BVH in the
//! shader, which needs no ray-tracing support.
//!
//! The camera is the Rust [`Camera`]: the raster pass projects with `clip_from_world()`, the
//! compute pass generates rays with `shaders/camera.glsl`, a function-by-function mirror of
//! `src/camera`, fed with the camera's own matrices. This module is the only place in the crate
//! with `unsafe` code; every Vulkan object is owned by a Rust value and destroyed on drop.
//!
//! Files: `instance` (instance, validation, messenger), `device` (device reports, selection,
//! logical device, allocator, submissions), `buffer`, `image`, `query`, `accel` (BLAS/TLAS),
//! `bvh` (the software traversal's BVH, flattened), `traversal`, `shader` (embedded SPIR-V),
//! `pipeline`, `scene` (scene buffers), `draw` (a raster pass's scene draw), `gbuffer` (raster
//! pass), `trace` (compute pass), `visibility` (the raster path's pass), `hybrid_plan` (the
//! hybrid path's plan on the device), `probe` (GLSL mirror checks), `layout_probe` (shared
//! struct layouts as the shaders read them), `sampler_cost` (sample generation timed alone),
//! `conv` (host data -> the structs of `crate::interface`), `error`, `bench`; for the preview
//! window: `surface`, `swapchain`, `frames` (frames in flight), `resolve` (display pass),
//! `overlay` (egui panel), `viewer`.
//!
//! ```no_run
//! use lensray::gpu::{GpuOptions, GpuRenderer};
//! # fn demo(scene: &lensray::scene::Scene, camera: &lensray::camera::Camera,
//! #         settings: &lensray::settings::RenderSettings) -> Result<(), lensray::gpu::GpuError> {
//! let mut gpu = GpuRenderer::new(&GpuOptions::default())?;
//! gpu.load_scene(scene)?; // BLAS per mesh (compacted) + TLAS and/or BVH, scene arrays uploaded
//! println!("tracing with {} of {:?}", gpu.traversal(), gpu.traversals());
//! let image = gpu.render(camera, settings, &mut |done, total| eprint!("\r{done}/{total}"))?;
//! let gbuffer = gpu.render_gbuffer(camera, settings.background)?;
//! let focus = lensray::gpu::focus_distance_at(&gbuffer, camera.width / 2, camera.height / 2);
//! println!("{} rays/s", gpu.timings().rays_per_second().unwrap_or(0.0));
//! # let _ = (image, focus); Ok(()) }
//! ```

#![deny(clippy::undocumented_unsafe_blocks)]

mod core;
mod passes;
mod present;
#[cfg(feature = "probes")]
mod probes;
mod scene;
mod traversal;

use std::sync::Arc;

use glam::Vec3;

use crate::camera::Camera;
use crate::film::{Accumulation, Image};
use crate::interface::TraceParams;
use crate::scene::Scene;
use crate::settings::{RenderSettings, Shading};

pub use core::device::DeviceReport;
pub use core::error::GpuError;
pub use core::instance::ValidationLog;
pub use passes::gbuffer::{focus_distance_at, GBuffer};
pub use passes::trace::Timings;
pub use present::overlay::OverlayFrame;
pub use present::viewer::{
    FrameRequest, FrameResult, FrameTimes, HostSamples, PresentMode, Viewer, ViewerOptions,
};
#[cfg(feature = "probes")]
pub use probes::layouts::LayoutReport;
#[cfg(feature = "probes")]
pub use probes::mirrors::{ProbeQuery, ProbeResult};
#[cfg(feature = "probes")]
pub use probes::timing::{bench, bench_renderer, BenchOptions, BenchReport, BenchedPass};
#[cfg(feature = "probes")]
pub use probes::view_routes::ViewRoutes;
pub use scene::bvh::BvhParams;
pub use traversal::Traversal;

use ash::vk;
use core::device::Context;
use core::error::vk_err;
use core::instance::Instance;
use passes::gbuffer::GBufferPass;
use passes::hybrid_plan::HybridPlanPass;
use passes::trace::TracePass;
use passes::visibility::VisibilityPass;
use present::surface::Surface;
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
    Ok(core::device::enumerate(&instance.instance)?
        .into_iter()
        .map(|(_, r)| r)
        .collect())
}

/// The Vulkan renderer. Fields drop in order; everything holds an `Arc` to the device context,
/// which is destroyed last, then the instance.
pub struct GpuRenderer {
    trace: TracePass,
    gbuffer: GBufferPass,
    /// The raster path's pass, made on its first use.
    visibility: Option<VisibilityPass>,
    /// The hybrid path's plan on the device (the render path's and the preview's).
    hybrid_plan: HybridPlanPass,
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
    ) -> Result<(Self, Option<Surface>), GpuError> {
        let window_extensions = match window {
            Some((display, _)) => ash_window::enumerate_required_extensions(display)
                .map_err(vk_err("vkEnumerateInstanceExtensionProperties"))?,
            None => &[],
        };
        let instance = Arc::new(Instance::new(options.validate, window_extensions)?);
        let log = instance.log.clone();
        let surface = window
            .map(|(display, window)| Surface::new(&instance, display, window))
            .transpose()?;
        let ctx = Arc::new(Context::new(instance, options, surface.as_ref())?);
        let gbuffer = GBufferPass::new(&ctx)?;
        let trace = TracePass::new(&ctx)?;
        let hybrid_plan = HybridPlanPass::new(&ctx)?;
        let renderer = Self {
            trace,
            gbuffer,
            visibility: None,
            hybrid_plan,
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
        self.gbuffer.bind_scene(&buffers);
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
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        check_size(camera)?;
        let gbuffer = self.gbuffer.render(scene, camera, background)?;
        self.timings.gbuffer_passes += 1;
        self.timings.gbuffer_gpu_ms += self.gbuffer.last_gpu_ms;
        Ok(gbuffer)
    }

    /// Renders `settings.shading`: `Unlit` and `Lit` through the thin lens with the compute
    /// pass; `Depth`, `Normal` and `Albedo` from the G-buffer. `progress(done, total)` counts
    /// pixel-samples.
    pub fn render(
        &mut self,
        camera: &Camera,
        settings: &RenderSettings,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<Image, GpuError> {
        check_size(camera)?;
        if settings.spp == 0 {
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
        let (image, ()) = crate::film::whole_image(
            &mut (self, progress),
            (camera.width, camera.height),
            settings,
            |(this, progress)| {
                progress(0, 1);
                let image = this.aov(camera, settings)?;
                progress(1, 1);
                Ok((image, ()))
            },
            |(this, progress), samples, accumulation| {
                this.accumulate(camera, settings, samples, accumulation, *progress)
            },
        )?;
        Ok(image)
    }

    /// An AOV of `settings.shading` (`Depth`, `Normal`, `Albedo`) read from the G-buffer.
    pub fn aov(&mut self, camera: &Camera, settings: &RenderSettings) -> Result<Image, GpuError> {
        let aov = settings.shading;
        if !aov.is_aov() {
            return Err(GpuError::Invalid(format!(
                "{aov:?} is traced: it is not an AOV of the G-buffer"
            )));
        }
        let g = self.render_gbuffer(camera, settings.background)?;
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

    /// Traces samples `samples` (thin lens, `Unlit` or `Lit`) of every pixel and adds them to
    /// `accumulation`, which has the camera's size. `progress(done, total)` counts
    /// pixel-samples.
    pub fn accumulate(
        &mut self,
        camera: &Camera,
        settings: &RenderSettings,
        samples: std::ops::Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(), GpuError> {
        check_samples(camera, settings)?;
        if self.scene.is_none() {
            return Err(GpuError::NoScene);
        }
        self.trace.accumulate(
            (camera, settings),
            samples,
            accumulation,
            &mut self.timings,
            None,
            progress,
        )
    }

    /// The raster path (accumulation-buffer depth of field, docs/raster.md): adds samples
    /// `samples` of every pixel as `accumulate` does, but each sample is one camera sample
    /// shared by every pixel (`settings.shared_samples` is implied): the scene is rasterized
    /// through that sample's lens point (`Camera::clip_from_world_through_lens`), and the
    /// shading pass shades what each pixel sees along its lens ray (lit: with a shadow ray of
    /// the traversal in use).
    pub fn accumulate_rasterized(
        &mut self,
        camera: &Camera,
        settings: &RenderSettings,
        samples: std::ops::Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(), GpuError> {
        check_samples(camera, settings)?;
        self.prepare_raster(camera.width, camera.height)?;
        let settings = RenderSettings {
            shared_samples: true,
            ..*settings
        };
        let raster_camera = camera.for_rasterizing_rays();
        let visibility = self.visibility.as_ref().expect("prepared");
        let scene = self.scene.as_ref().expect("prepared");
        let record = |cmd, sample| {
            visibility.record_sample(cmd, scene, &raster_camera, &settings, sample);
        };
        self.trace.accumulate(
            (camera, &settings),
            samples,
            accumulation,
            &mut self.timings,
            Some(&record),
            progress,
        )
    }

    /// Makes the raster path's visibility pass (on first use) and its targets for a `width` x
    /// `height` image, bound to the trace pass (the hybrid's lit pre-pass uses it too).
    fn prepare_raster(&mut self, width: u32, height: u32) -> Result<(), GpuError> {
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        if self.visibility.is_none() {
            let pass = VisibilityPass::new(&self.ctx)?;
            pass.bind_scene(scene);
            self.visibility = Some(pass);
        }
        let visibility = self.visibility.as_mut().expect("made above");
        if visibility.ensure_targets(width, height)? {
            let targets = visibility.targets.as_ref().expect("just made");
            self.trace.bind_visibility(&targets.buffer);
        }
        Ok(())
    }

    /// Sets the hybrid path's plan for later `accumulate` calls (one entry per pixel, row-major;
    /// see `interface::TRACE_BINDING_PLAN`), or `None` to trace every sample again.
    pub fn set_plan(&mut self, plan: Option<&[[f32; 4]]>) -> Result<(), GpuError> {
        self.trace.set_plan(plan)
    }

    /// The hybrid path's plan made on the device (shaders/hybrid_plan.comp) for later
    /// `accumulate` calls: one submission draws the G-buffer of `planning` (the camera whose
    /// raster the plan reads, `Camera::for_rasterizing_rays`), lit runs the pre-pass (each
    /// pixel's shortcut value and shadow state), and plans `settings.spp` samples seen by
    /// `camera` from them. Nothing is read back; `read_plan` can.
    pub fn plan_on_device(
        &mut self,
        camera: &Camera,
        planning: &Camera,
        settings: &RenderSettings,
    ) -> Result<(), GpuError> {
        check_size(camera)?;
        if (planning.width, planning.height) != (camera.width, camera.height) {
            return Err(GpuError::Invalid(
                "the planning camera's size differs from the camera's".into(),
            ));
        }
        let lit = settings.shading == Shading::Lit;
        if lit {
            self.prepare_raster(camera.width, camera.height)?;
        }
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let pixels = u64::from(camera.width) * u64::from(camera.height);
        self.gbuffer.ensure_targets(camera.width, camera.height)?;
        self.trace.ensure_plan_capacity(pixels)?;
        let targets = self.gbuffer.targets.as_ref().expect("ensured above");
        self.hybrid_plan.bind(
            targets,
            self.trace.plan_buffer_ref(),
            self.trace.surface_depth_ref(),
        )?;
        let ctx = &self.ctx;
        let (gbuffer, plan, trace) = (&self.gbuffer, &self.hybrid_plan, &self.trace);
        let visibility = self.visibility.as_ref();
        ctx.submit_and_wait(|cmd| {
            gbuffer.record(cmd, scene, planning, settings.background, None);
            if let Some(visibility) = visibility.filter(|_| lit) {
                record_lit_prepass((trace, visibility, scene), cmd, camera, settings);
            }
            plan.record(cmd, targets, camera, settings.shading, settings.spp);
            core::buffer::barrier_to_host(
                ctx,
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_WRITE,
            );
            Ok(())
        })?;
        if lit {
            self.timings.rays_traced += self.trace.rays_counted()?;
        }
        self.timings.gbuffer_passes += 1;
        self.trace.use_device_plan(pixels);
        Ok(())
    }

    /// The hybrid's lit pre-pass alone (the host plan's input, `paths::hybrid::host_plan`): per
    /// pixel the shortcut value (xyz) and whether its shadow ray was blocked (w, 1 or 0).
    pub fn lit_prepass(
        &mut self,
        camera: &Camera,
        settings: &RenderSettings,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        check_size(camera)?;
        self.prepare_raster(camera.width, camera.height)?;
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let visibility = self.visibility.as_ref().expect("prepared above");
        let pixels = u64::from(camera.width) * u64::from(camera.height);
        self.trace.ensure_plan_capacity(pixels)?;
        let (ctx, trace) = (&self.ctx, &self.trace);
        ctx.submit_and_wait(|cmd| {
            record_lit_prepass((trace, visibility, scene), cmd, camera, settings);
            core::buffer::barrier_to_host(
                ctx,
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_WRITE,
            );
            Ok(())
        })?;
        self.trace.read_plan(pixels)
    }

    /// The entries of the plan last made by `plan_on_device` (`pixels` of them).
    pub fn read_plan(&self, pixels: u64) -> Result<Vec<[f32; 4]>, GpuError> {
        self.trace.read_plan(pixels)
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

    /// Bytes of device memory allocated now (every buffer and image of the renderer).
    pub fn allocated_bytes(&self) -> u64 {
        self.ctx.allocator().generate_report().total_allocated_bytes
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

/// What accumulating samples needs: an image the device can hold, a traced shading.
fn check_samples(camera: &Camera, settings: &RenderSettings) -> Result<(), GpuError> {
    check_size(camera)?;
    if settings.shading.is_aov() {
        return Err(GpuError::Invalid(format!(
            "{:?} is read from the G-buffer: it has no samples to accumulate",
            settings.shading
        )));
    }
    Ok(())
}

/// The hybrid's lit pre-pass with the parameters of `camera` and `settings`, its rays counted
/// from zero (the render path's plan and the host plan's input record it alike): the
/// visibility pass through the lens centre, then the shading of what it saw.
fn record_lit_prepass(
    (trace, visibility, scene): (&TracePass, &VisibilityPass, &SceneBuffers),
    cmd: vk::CommandBuffer,
    camera: &Camera,
    settings: &RenderSettings,
) {
    trace.record_params(cmd, &TraceParams::new(camera, settings));
    trace.record_clear_ray_counter(cmd);
    visibility.record_aperture_centre(cmd, scene, camera);
    trace.record_lit_prepass(cmd, camera.width, camera.height);
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
