//! The preview window's renderer. Every frame of the final view: the raster G-buffer of the
//! current camera (until every pixel has a sample: the resolve shows it where none is yet), some
//! thin-lens samples added to an accumulation that stays on the device (sized from the measured
//! speed), the resolve into a display image, its copy into the window image, the egui panel over
//! it, present. The other views (albedo, normal, depth, circle of
//! confusion) trace nothing: their frames draw the view with the view pass straight into the
//! window image (`ViewPass`: the G-buffer's vertex stage, one 8-bit target; the same bytes as
//! G-buffer and resolve), then the panel. The hybrid path (`ViewerOptions::hybrid`) draws the
//! G-buffer with its planning camera and, in the first frame that traces after a restart, makes
//! its plan on the device from that G-buffer (`HybridPlanPass`, plus the lit shortcut
//! pre-pass) before the trace dispatches, which then run in TRACE_MODE_HYBRID; the plan stays
//! until the next restart. Frames in flight (`frames`) overlap host and device; the only waits
//! are for a frame slot's own earlier frame, and, on rare events (resize, pick, screenshot),
//! for the device.

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::core::buffer::{barrier, barrier_to_host, Buffer};
use crate::core::error::{vk_err, GpuError};
use crate::core::image::{record_copy_to_buffer, transition, Transition};
use crate::present::frames::{FrameSlot, Frames, FRAMES_IN_FLIGHT};
use crate::present::overlay::{Overlay, OverlayFrame};
use crate::present::resolve::ResolvePass;
use crate::present::surface::Surface;
use crate::present::swapchain::{Acquired, Swapchain};
use crate::present::view_pass::ViewPass;
use crate::{check_validation_log, Estimator, GpuOptions, GpuRenderer, ValidationLog};
use lensray_core::camera::Camera;
use lensray_core::film::progressive::ProgressiveSchedule;
use lensray_core::film::Image;
use lensray_core::interface::{
    TracePush, TRACE_GROUP_SIZE, TRACE_MODE_ALL, TRACE_MODE_HYBRID, TRACE_MODE_RASTER, VIEW_FINAL,
};
use lensray_core::scene::Scene;
use lensray_core::settings::{RenderSettings, Shading};

/// How the window waits for the display (VkPresentModeKHR).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum PresentMode {
    /// Wait for vertical blank, never tear (always available).
    #[default]
    Fifo,
    /// Replace the queued image with the newest: no tearing, no waiting.
    Mailbox,
    /// Present at once; may tear.
    Immediate,
}

/// Trace time aimed at per frame: the G-buffer view stays responsive while samples accumulate.
const TRACE_MS_PER_FRAME: f64 = 20.0;
const INITIAL_SAMPLES_PER_FRAME: u64 = 1 << 15;
/// Dispatches per frame, at most (each is one group of rows of one sample, or whole samples).
const MAX_DISPATCHES_PER_FRAME: usize = 64;

/// What the next frame shows.
pub struct FrameRequest<'a> {
    pub camera: &'a Camera,
    pub settings: &'a RenderSettings,
    /// `lensray_core::interface::VIEW_*`. Samples are added only in the final view.
    pub view: u32,
    /// The camera, lens or shading changed: the accumulation starts again.
    pub restart: bool,
    pub target_spp: u32,
    /// Read the G-buffer's view depth at this pixel (answered in this frame's result).
    pub pick: Option<[u32; 2]>,
    pub overlay: Option<OverlayFrame>,
    /// The samples come from the host (the CPU path) instead of the trace pass.
    pub host: Option<HostSamples<'a>>,
}

/// Samples traced on the host for the frame's camera.
pub struct HostSamples<'a> {
    /// New sums and counts of the whole image (`[r, g, b, n]` per pixel, row-major) to show
    /// from this frame on; `None` keeps what the accumulation holds.
    pub sums: Option<&'a [[f32; 4]]>,
    /// Samples every pixel has, and whether that is the target.
    pub spp: u32,
    pub converged: bool,
}

/// GPU times of one finished frame, ms (timestamps).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameTimes {
    /// The G-buffer pass, or the view pass in the frames of a non-final view.
    pub gbuffer_ms: f64,
    /// Whether the frame drew either (the final view skips the G-buffer once every pixel has
    /// a sample).
    pub gbuffer_drawn: bool,
    /// The trace dispatches (and a restart's clear), the plan excluded.
    pub trace_ms: f64,
    pub resolve_ms: f64,
    /// The hybrid's plan (and lit shortcut pre-pass), in the frames that make one; else 0.
    pub plan_ms: f64,
    /// Copy to the window and the panel.
    pub present_ms: f64,
    pub total_ms: f64,
    /// Pixel-samples the frame traced.
    pub trace_work: u64,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameResult {
    /// False when nothing was drawn (window minimised or being resized).
    pub drawn: bool,
    /// Samples every pixel has.
    pub spp: u32,
    pub converged: bool,
    /// With a pick: the view depth there, `None` where no surface covers the pixel.
    pub picked_depth: Option<Option<f32>>,
    /// Times of the latest finished frame.
    pub times: Option<FrameTimes>,
}

pub struct ViewerOptions {
    pub gpu: GpuOptions,
    pub present_mode: PresentMode,
    /// How the window adds samples: traced, as the raster path (per sample a visibility pass
    /// through its lens point, then the shading pass: docs/raster.md) or as the hybrid
    /// (docs/hybrid.md, "In the preview").
    pub estimator: Estimator,
}

/// The accumulation of the current image size.
struct Accumulation {
    buffer: Buffer,
    schedule: ProgressiveSchedule,
}

pub struct Viewer {
    // Fields drop in order, after `Drop` waited for the device: frame slots, the panel, the
    // passes' images, the swapchain, its surface, then the renderer (device, instance).
    frames: Frames,
    overlay: Option<Overlay>,
    /// Draws the non-final views straight into the window image (made with the swapchain).
    view_pass: Option<ViewPass>,
    resolve: ResolvePass,
    accum: Option<Accumulation>,
    swapchain: Option<Swapchain>,
    surface: Surface,
    gpu: GpuRenderer,
    present_mode: PresentMode,
    recreate: bool,
    samples_per_frame: u64,
    /// How samples are added (the hybrid's plan, the raster's visibility pass).
    estimator: Estimator,
    /// The spp of the hybrid plan in the plan buffer for the current accumulation; `None`
    /// until the first frame after a restart that traces makes it.
    plan_spp: Option<u32>,
    log: ValidationLog,
}

impl Viewer {
    /// Opens the device for the window, uploads `scene` and builds its acceleration
    /// structures.
    pub fn new(
        options: &ViewerOptions,
        display: RawDisplayHandle,
        window: RawWindowHandle,
        scene: &Scene,
    ) -> Result<Self, GpuError> {
        let (mut gpu, surface) = GpuRenderer::open(&options.gpu, Some((display, window)))?;
        let surface = surface.expect("opened with a window");
        gpu.load_scene(scene)?;
        let ctx = gpu.ctx.clone();
        Ok(Self {
            frames: Frames::new(&ctx)?,
            overlay: None,
            view_pass: None,
            resolve: ResolvePass::new(&ctx)?,
            accum: None,
            swapchain: None,
            surface,
            log: gpu.validation_log(),
            gpu,
            present_mode: options.present_mode,
            recreate: true,
            samples_per_frame: INITIAL_SAMPLES_PER_FRAME,
            estimator: options.estimator,
            plan_spp: None,
        })
    }

    /// Adds samples with `estimator` from now on (`--path auto` picks after the window opened,
    /// before its first frame; a real lens switches to the traced estimator and back).
    pub fn use_estimator(&mut self, estimator: Estimator) {
        self.estimator = estimator;
        self.plan_spp = None;
        // The passes' images are made again for the path (plan buffer, visibility targets).
        self.recreate = true;
    }

    pub fn device_name(&self) -> String {
        self.gpu.device_name()
    }

    /// The renderer behind the window (to pick its traversal before the first frame).
    pub fn renderer_mut(&mut self) -> &mut GpuRenderer {
        &mut self.gpu
    }

    pub fn present_mode(&self) -> Option<PresentMode> {
        let mode = self.swapchain.as_ref()?.present_mode;
        Some(match mode {
            vk::PresentModeKHR::MAILBOX => PresentMode::Mailbox,
            vk::PresentModeKHR::IMMEDIATE => PresentMode::Immediate,
            _ => PresentMode::Fifo,
        })
    }

    /// Call before building the frame's camera: (re)creates the swapchain when the window
    /// changed and returns the image size to render, `None` while the window has no area.
    pub fn prepare(&mut self, window_size: [u32; 2]) -> Result<Option<[u32; 2]>, GpuError> {
        let current = self
            .swapchain
            .as_ref()
            .map(|s| [s.extent.width, s.extent.height]);
        if self.recreate || current.is_none() || current != Some(window_size) {
            self.recreate_swapchain(window_size)?;
        }
        Ok(self
            .swapchain
            .as_ref()
            .map(|s| [s.extent.width, s.extent.height]))
    }

    fn recreate_swapchain(&mut self, window_size: [u32; 2]) -> Result<(), GpuError> {
        self.wait_idle()?;
        let ctx = self.gpu.ctx.clone();
        let old = self.swapchain.take();
        let new = Swapchain::new(
            &ctx,
            &self.surface,
            window_size,
            present_mode_vk(self.present_mode),
            old.as_ref(),
        )?;
        drop(old);
        self.recreate = false;
        let Some(swapchain) = new else {
            return Ok(()); // minimised: nothing to draw into
        };
        if self
            .overlay
            .as_ref()
            .is_none_or(|o| o.format() != swapchain.format)
        {
            self.overlay = None;
            self.overlay = Some(Overlay::new(&ctx, swapchain.format, FRAMES_IN_FLIGHT)?);
        }
        self.overlay
            .as_mut()
            .expect("created above")
            .attach(&swapchain)?;
        if self
            .view_pass
            .as_ref()
            .is_none_or(|v| v.format() != swapchain.format)
        {
            self.view_pass = None;
            // Left as the copy into the window leaves it, for the panel's pass.
            let pass = ViewPass::new(
                &ctx,
                swapchain.format,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            )?;
            pass.bind_scene(self.gpu.scene.as_ref().ok_or(GpuError::NoScene)?);
            self.view_pass = Some(pass);
        }
        self.view_pass.as_mut().expect("created above").attach(
            &swapchain.views,
            swapchain.extent.width,
            swapchain.extent.height,
        )?;
        let (width, height) = (swapchain.extent.width, swapchain.extent.height);
        self.swapchain = Some(swapchain);
        self.resize_images(width, height)
    }

    /// The G-buffer, accumulation and display images of a new size. No frame is in flight.
    fn resize_images(&mut self, width: u32, height: u32) -> Result<(), GpuError> {
        let ctx = self.gpu.ctx.clone();
        let bytes = u64::from(width) * u64::from(height) * 16;
        if bytes > u64::from(ctx.report.max_storage_buffer_range) {
            return Err(GpuError::Invalid(format!(
                "a {width}x{height} preview needs a {bytes}-byte accumulation buffer, more than \
                 the device's storage buffer range ({})",
                ctx.report.max_storage_buffer_range
            )));
        }
        self.gpu.gbuffer_pass()?.ensure_targets(width, height)?;
        let target = self.accum.as_ref().map_or(0, |a| a.schedule.target());
        self.accum = None;
        let buffer = Buffer::new(
            &ctx,
            "preview accumulation",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        self.gpu.trace.bind_accumulation(&buffer);
        // The hybrid's lit pre-pass rasterizes through the lens centre (the shading can turn
        // lit at any frame).
        if self.estimator != Estimator::Traced {
            self.gpu.prepare_raster(width, height)?;
        }
        if self.estimator == Estimator::Hybrid {
            self.gpu.ensure_hybrid_plan()?;
        }
        let gbuffer = self.gpu.gbuffer.as_ref().expect("made above");
        let targets = gbuffer.targets.as_ref().expect("ensured above");
        if let Some(hybrid_plan) = self
            .gpu
            .hybrid_plan
            .as_mut()
            .filter(|_| self.estimator == Estimator::Hybrid)
        {
            self.gpu
                .trace
                .ensure_plan_capacity(u64::from(width) * u64::from(height))?;
            hybrid_plan.bind(
                targets,
                self.gpu.trace.plan_buffer_ref(),
                self.gpu.trace.surface_depth_ref(),
            )?;
            // A new size restarts the accumulation: the plan is made again.
            self.plan_spp = None;
        }
        self.resolve.bind(&buffer, targets, width, height)?;
        self.accum = Some(Accumulation {
            buffer,
            schedule: ProgressiveSchedule::new(width, height, TRACE_GROUP_SIZE, target),
        });
        Ok(())
    }

    /// Draws one frame (after [`Self::prepare`], with a camera of the size it returned).
    pub fn draw(&mut self, mut request: FrameRequest<'_>) -> Result<FrameResult, GpuError> {
        let mut result = FrameResult::default();
        // This slot's previous frame must be finished before anything of it is reused.
        let slot = &mut self.frames.slots[self.frames.current];
        slot.wait()?;
        // egui's texture changes apply whether or not this frame is drawn (uploads wait for
        // the queue themselves). What egui frees goes after the frame that last drew with it:
        // textures queued on this slot two frames ago can go now.
        let done = std::mem::take(&mut slot.textures_to_free);
        if let Some(overlay) = self.overlay.as_mut() {
            overlay.free_textures(&done)?;
            if let Some(frame) = request.overlay.as_mut() {
                overlay.set_textures(&frame.textures)?;
                slot.textures_to_free
                    .extend(frame.textures.free.iter().copied());
                frame.textures.clear();
            }
        }
        if self.gpu.trace.camera_tables_differ(request.camera) {
            // Frames in flight bind the old tables (a new aperture image: rare).
            self.wait_idle()?;
            self.gpu.trace.ensure_camera_tables(request.camera)?;
        }
        let (Some(swapchain), Some(accum)) = (self.swapchain.as_ref(), self.accum.as_mut()) else {
            return Ok(result);
        };
        let camera = request.camera;
        if [camera.width, camera.height] != [swapchain.extent.width, swapchain.extent.height] {
            return Err(GpuError::Invalid(format!(
                "the camera is {}x{} but the window image {}x{}",
                camera.width, camera.height, swapchain.extent.width, swapchain.extent.height
            )));
        }
        let slot = &mut self.frames.slots[self.frames.current];
        if slot.submitted {
            result.times = Some(read_times(&self.gpu, slot)?);
            if let Some(t) = result.times.filter(|t| t.trace_ms > 0.0) {
                // Shrinks at once, grows at most 2x per frame.
                let rate = t.trace_work as f64 / t.trace_ms;
                self.samples_per_frame = ((rate * TRACE_MS_PER_FRAME) as u64)
                    .min(2 * self.samples_per_frame)
                    .clamp(1024, 1 << 26);
            }
        }
        let image_index = match swapchain.acquire(slot.image_acquired)? {
            Acquired::Image(i) => i,
            Acquired::OutOfDate => {
                self.recreate = true;
                return Ok(result);
            }
        };

        // The hybrid's plan depends on the target spp (sample counts grow with it): a new
        // target restarts its accumulation.
        let restart = request.restart
            || (self.estimator == Estimator::Hybrid
                && self.plan_spp.is_some_and(|spp| spp != request.target_spp));
        if restart {
            accum.schedule.restart();
            self.plan_spp = None;
        }
        accum.schedule.set_target(request.target_spp);
        let work = if request.view == VIEW_FINAL && request.host.is_none() {
            accum
                .schedule
                .plan(self.samples_per_frame, MAX_DISPATCHES_PER_FRAME)
        } else {
            Vec::new()
        };
        slot.trace_work = work.iter().map(|w| w.pixel_samples).sum();

        let ctx = self.gpu.ctx.clone();
        let device = &ctx.device;
        let cmd = slot.cmd;
        // SAFETY: the slot's previous frame finished (fence waited): its command buffer may be
        // reset and re-recorded, its fence reset.
        unsafe {
            device
                .reset_fences(&[slot.fence])
                .map_err(vk_err("vkResetFences"))?;
            device
                .reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .map_err(vk_err("vkResetCommandBuffer"))?;
            device
                .begin_command_buffer(
                    cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .map_err(vk_err("vkBeginCommandBuffer"))?;
        }
        // The previous frame's work on the shared images and buffers comes first.
        barrier(
            &ctx,
            cmd,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_WRITE,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        slot.timestamps.reset(cmd);
        let scene = self.gpu.scene.as_ref().ok_or(GpuError::NoScene)?;
        let gbuffer = self.gpu.gbuffer.as_ref().expect("made in resize_images");
        // The hybrid plans from the G-buffer of its planning camera (same rays and pixels, the
        // raster's clipping planes moved out), which the views show as well.
        let planning = (self.estimator == Estimator::Hybrid).then(|| camera.for_rasterizing_rays());
        let raster_camera = planning.as_ref().unwrap_or(camera);
        // A view other than the final one, without a pick (which reads the G-buffer), is drawn
        // by the view pass straight into the window image: no G-buffer, resolve or copy.
        let view_pass = self
            .view_pass
            .as_ref()
            .filter(|_| request.view != VIEW_FINAL && request.pick.is_none());
        let make_plan =
            self.estimator == Estimator::Hybrid && !work.is_empty() && self.plan_spp.is_none();
        // The final view shows the G-buffer only where the accumulation has no sample yet: once
        // every pixel has one, a frame that neither picks nor plans from it skips the pass.
        let skip_gbuffer = request.view == VIEW_FINAL
            && request.pick.is_none()
            && !make_plan
            && request.host.is_none()
            && accum.schedule.samples_complete() > 0;
        slot.drew_gbuffer = !skip_gbuffer;
        match view_pass {
            None if skip_gbuffer => {
                slot.timestamps
                    .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 0);
                slot.timestamps
                    .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
            }
            Some(pass) => {
                slot.timestamps
                    .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 0);
                pass.record(
                    cmd,
                    scene,
                    raster_camera,
                    request.settings.background,
                    crate::upload::view_params(camera, request.view),
                    image_index as usize,
                );
                slot.timestamps
                    .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
            }
            None => gbuffer.record(
                cmd,
                scene,
                raster_camera,
                request.settings.background,
                Some((&slot.timestamps, 0)),
            ),
        }
        let direct = view_pass.is_some();
        let targets = gbuffer.targets.as_ref().expect("sized in prepare");
        if let Some([x, y]) = request.pick {
            record_pick(&ctx, cmd, targets.view_depth.image, slot, x, y);
        }

        slot.timestamps
            .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 2);
        // The raster path's estimator: every pixel draws the same camera samples.
        let traced_settings = RenderSettings {
            shared_samples: self.estimator == Estimator::Raster || request.settings.shared_samples,
            ..*request.settings
        };
        if restart {
            // SAFETY: recording state; the buffer has TRANSFER_DST usage.
            unsafe { device.cmd_fill_buffer(cmd, accum.buffer.buffer, 0, vk::WHOLE_SIZE, 0) };
            self.gpu
                .trace
                .record_params(cmd, &crate::upload::trace_params(camera, &traced_settings));
        }
        if let Some(sums) = request.host.as_ref().and_then(|h| h.sums) {
            let bytes: &[u8] = bytemuck::cast_slice(sums);
            if bytes.len() as u64 > accum.buffer.size {
                return Err(GpuError::Invalid(format!(
                    "{} bytes of host samples for a {}-byte accumulation",
                    bytes.len(),
                    accum.buffer.size
                )));
            }
            if slot
                .upload
                .as_ref()
                .is_none_or(|b| b.size < bytes.len() as u64)
            {
                slot.upload = None;
                slot.upload = Some(Buffer::new(
                    &ctx,
                    "preview host samples",
                    bytes.len() as u64,
                    vk::BufferUsageFlags::TRANSFER_SRC,
                    MemoryLocation::CpuToGpu,
                )?);
            }
            let upload = slot.upload.as_mut().expect("created above");
            upload.write(bytes)?;
            barrier(
                &ctx,
                cmd,
                vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_READ,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            );
            let region = vk::BufferCopy::default().size(bytes.len() as u64);
            // SAFETY: recording state; the slot's upload buffer is not in use (its fence was
            // waited) and the region fits both buffers (checked above).
            unsafe { device.cmd_copy_buffer(cmd, upload.buffer, accum.buffer.buffer, &[region]) };
        }
        slot.timestamps
            .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 6);
        if make_plan {
            // The plan of the current camera and settings, from the G-buffer drawn above,
            // into the trace pass's plan buffer; lit, after the pre-pass that leaves each
            // pixel's shortcut value and shadow state there (with the parameters recorded
            // above at the restart; the plan's steps order themselves after it).
            if request.settings.shading == Shading::Lit {
                let visibility = self.gpu.visibility.as_ref().expect("prepared in resize");
                visibility.record_aperture_centre(cmd, scene, camera);
                self.gpu
                    .trace
                    .record_lit_prepass(cmd, camera.width, camera.height);
            }
            let hybrid_plan = self.gpu.hybrid_plan.as_ref().expect("made in resize");
            hybrid_plan.record(
                cmd,
                targets,
                camera,
                request.settings.shading,
                request.target_spp,
            );
            self.plan_spp = Some(request.target_spp);
        }
        slot.made_plan = make_plan;
        slot.timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 7);
        let mode = if self.estimator == Estimator::Hybrid {
            TRACE_MODE_HYBRID
        } else {
            TRACE_MODE_ALL
        };
        let raster_camera =
            (self.estimator == Estimator::Raster).then(|| camera.for_rasterizing_rays());
        for item in &work {
            // The raster path shades one sample per dispatch, after that sample's raster pass
            // through its lens point. A sample split into groups of rows over several frames is
            // rasterized with its first group (group 0); the later groups read that visibility
            // (the queue keeps the frames in order, and nothing else writes it until the next
            // sample).
            let (dispatches, mode) = match raster_camera {
                Some(_) => (
                    (item.sample_begin..item.sample_end)
                        .map(|s| (s, s + 1))
                        .collect::<Vec<_>>(),
                    TRACE_MODE_RASTER,
                ),
                None => (vec![(item.sample_begin, item.sample_end)], mode),
            };
            for (sample_begin, sample_end) in dispatches {
                if let (Some(raster_camera), 0) = (&raster_camera, item.block_first) {
                    let visibility = self.gpu.visibility.as_ref().expect("prepared in resize");
                    visibility.record_sample(
                        cmd,
                        scene,
                        raster_camera,
                        &traced_settings,
                        sample_begin,
                    );
                }
                barrier(
                    &ctx,
                    cmd,
                    vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
                    vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE,
                    vk::PipelineStageFlags::COMPUTE_SHADER,
                    vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
                );
                let push = TracePush {
                    band_origin: 0,
                    band_height: camera.height,
                    block_first: item.block_first,
                    block_stride: item.block_stride,
                    block_count: item.block_count,
                    sample_begin,
                    sample_end,
                    mode,
                };
                self.gpu.trace.record_dispatch(cmd, push, camera.width);
            }
        }
        slot.timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 3);
        barrier(
            &ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ,
        );
        if !direct {
            self.resolve.record(
                cmd,
                targets,
                &crate::upload::resolve_push(camera, request.view),
            );
        }
        slot.timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 4);

        if !direct {
            let window_image = swapchain.images[image_index as usize];
            let display = self.resolve.display.as_ref().expect("bound in prepare");
            record_copy_to_window(&ctx, cmd, display.image, window_image, swapchain.extent);
        }
        if let Some(overlay) = self.overlay.as_mut() {
            overlay.record(cmd, image_index, request.overlay.as_ref())?;
        }
        slot.timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 5);
        // SAFETY: recording began above.
        unsafe { device.end_command_buffer(cmd) }.map_err(vk_err("vkEndCommandBuffer"))?;

        let waits = [slot.image_acquired];
        // The first use of the window image is the view pass or the copy into it.
        let wait_stages = [if direct {
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
        } else {
            vk::PipelineStageFlags::TRANSFER
        }];
        let signals = [swapchain.rendered[image_index as usize]];
        let cmds = [cmd];
        let submit = vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&wait_stages)
            .command_buffers(&cmds)
            .signal_semaphores(&signals);
        // SAFETY: the command buffer is recorded; the semaphores and fence are the slot's and
        // the image's, unsignalled and not waited on by anything pending.
        unsafe { device.queue_submit(ctx.queue, &[submit], slot.fence) }
            .map_err(vk_err("vkQueueSubmit"))?;
        ctx.counters.submitted();
        slot.submitted = true;
        if !swapchain.present(image_index)? {
            self.recreate = true;
        }
        if request.pick.is_some() {
            // A rare event: wait for this frame so the focus applies to the next one.
            slot.wait()?;
            let depth = bytemuck::cast_slice::<u8, f32>(slot.pick.read()?)[0];
            result.picked_depth = Some((depth > 0.0).then_some(depth));
        }
        self.frames.advance();
        result.drawn = true;
        match &request.host {
            Some(host) => {
                result.spp = host.spp;
                result.converged = host.converged;
            }
            None => {
                result.spp = accum.schedule.samples_complete();
                result.converged = accum.schedule.converged();
            }
        }
        Ok(result)
    }

    /// The accumulation so far (sum / samples per pixel; black where none yet), for
    /// screenshots. Waits for the device.
    pub fn read_accumulation(&mut self) -> Result<Option<Image>, GpuError> {
        let Some(accum) = self.accum.as_ref() else {
            return Ok(None);
        };
        let Some(targets) = self.gpu.gbuffer.as_ref().and_then(|g| g.targets.as_ref()) else {
            return Ok(None);
        };
        let (width, height) = (targets.width, targets.height);
        self.wait_idle()?;
        let ctx = self.gpu.ctx.clone();
        let readback = Buffer::new(
            &ctx,
            "preview screenshot readback",
            accum.buffer.size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        ctx.submit_and_wait(|cmd| {
            let region = vk::BufferCopy::default().size(accum.buffer.size);
            // SAFETY: recording state; the preview's frames finished (waited above).
            unsafe {
                ctx.device
                    .cmd_copy_buffer(cmd, accum.buffer.buffer, readback.buffer, &[region])
            };
            barrier_to_host(
                &ctx,
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            );
            Ok(())
        })?;
        let sums: &[[f32; 4]] = bytemuck::cast_slice(readback.read()?);
        let pixels = (width * height) as usize;
        Ok(Some(Image {
            width,
            height,
            pixels: sums[..pixels]
                .iter()
                .map(|s| {
                    if s[3] > 0.0 {
                        Vec3::new(s[0], s[1], s[2]) / s[3]
                    } else {
                        Vec3::ZERO
                    }
                })
                .collect(),
        }))
    }

    fn wait_idle(&self) -> Result<(), GpuError> {
        // SAFETY: a live device; used on rare events only (resize, screenshot, exit).
        unsafe { self.gpu.ctx.device.device_wait_idle() }.map_err(vk_err("vkDeviceWaitIdle"))
    }

    /// Destroys every Vulkan object; with validation on, fails on any message, the leak report
    /// of the device's and instance's destruction included.
    pub fn close(self) -> Result<(), GpuError> {
        let log = self.log.clone();
        drop(self);
        check_validation_log(&log)
    }

    pub fn validation_log(&self) -> ValidationLog {
        self.log.clone()
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        // Nothing may be in use when the fields are destroyed.
        let _ = self.wait_idle();
    }
}

fn present_mode_vk(mode: PresentMode) -> vk::PresentModeKHR {
    match mode {
        PresentMode::Fifo => vk::PresentModeKHR::FIFO,
        PresentMode::Mailbox => vk::PresentModeKHR::MAILBOX,
        PresentMode::Immediate => vk::PresentModeKHR::IMMEDIATE,
    }
}

fn read_times(gpu: &GpuRenderer, slot: &FrameSlot) -> Result<FrameTimes, GpuError> {
    let t = slot.timestamps.results()?;
    let ms = |a: usize, b: usize| gpu.ctx.elapsed_ns(t[a], t[b]) * 1e-6;
    Ok(FrameTimes {
        gbuffer_ms: ms(0, 1),
        gbuffer_drawn: slot.drew_gbuffer,
        // The plan (timed apart) is recorded inside the trace span.
        trace_ms: ms(2, 3) - ms(6, 7),
        resolve_ms: ms(3, 4),
        plan_ms: if slot.made_plan { ms(6, 7) } else { 0.0 },
        present_ms: ms(4, 5),
        total_ms: ms(0, 5),
        trace_work: slot.trace_work,
    })
}

/// Copies the view depth at (x, y) (G-buffer in TRANSFER_SRC_OPTIMAL) to the slot's pick buffer.
fn record_pick(
    ctx: &crate::core::device::Context,
    cmd: vk::CommandBuffer,
    view_depth: vk::Image,
    slot: &FrameSlot,
    x: u32,
    y: u32,
) {
    // The G-buffer pass left the image in TRANSFER_SRC_OPTIMAL with its writes ordered before
    // transfers; (x, y) lies inside it (checked by the caller).
    record_copy_to_buffer(ctx, cmd, view_depth, slot.pick.buffer, [x, y], [1, 1]);
    barrier_to_host(
        ctx,
        cmd,
        vk::PipelineStageFlags::TRANSFER,
        vk::AccessFlags::TRANSFER_WRITE,
    );
}

/// Blits the display image (TRANSFER_SRC_OPTIMAL) onto the window image, which ends in
/// TRANSFER_DST_OPTIMAL for the overlay's render pass.
fn record_copy_to_window(
    ctx: &crate::core::device::Context,
    cmd: vk::CommandBuffer,
    display: vk::Image,
    window: vk::Image,
    extent: vk::Extent2D,
) {
    transition(
        ctx,
        cmd,
        window,
        &Transition {
            old: vk::ImageLayout::UNDEFINED,
            new: vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            // Chained to the acquire semaphore's wait at the transfer stage.
            src_stage: vk::PipelineStageFlags::TRANSFER,
            src_access: vk::AccessFlags::empty(),
            dst_stage: vk::PipelineStageFlags::TRANSFER,
            dst_access: vk::AccessFlags::TRANSFER_WRITE,
        },
    );
    let layers = vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    let corner = vk::Offset3D {
        x: extent.width as i32,
        y: extent.height as i32,
        z: 1,
    };
    let region = vk::ImageBlit::default()
        .src_subresource(layers)
        .src_offsets([vk::Offset3D::default(), corner])
        .dst_subresource(layers)
        .dst_offsets([vk::Offset3D::default(), corner]);
    // SAFETY: both images are live, of the same size, in the layouts named; a 1:1 blit only
    // reorders channels (RGBA8 -> the window's BGRA8/RGBA8 UNORM).
    unsafe {
        ctx.device.cmd_blit_image(
            cmd,
            display,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            window,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
            vk::Filter::NEAREST,
        )
    };
}
