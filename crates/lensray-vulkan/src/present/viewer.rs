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
//!
//! The viewer, its construction and its swapchain's and images' (re)creation live here;
//! `request` holds what a frame is asked and answers, `draw` the frame's phases, `record` the
//! recording of its command buffer.

mod draw;
mod record;
mod request;
mod rounds;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::core::buffer::Buffer;
use crate::core::error::GpuError;
use crate::core::surface::WindowSurface;
use crate::core::swapchain::Swapchain;
use crate::present::frames::{Frames, FRAMES_IN_FLIGHT};
use crate::present::overlay::Overlay;
use crate::present::resolve::ResolvePass;
use crate::present::view_pass::ViewPass;
use crate::renderer::check_validation_log;
use crate::{Estimator, GpuRenderer, ValidationLog};
use lensray_core::film::progressive::ProgressiveSchedule;
use lensray_core::film::Image;
use lensray_core::interface::TRACE_GROUP_SIZE;
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::Scene;

pub use request::{FrameRequest, FrameResult, FrameTimes, HostSamples, PresentMode, ViewerOptions};

const INITIAL_SAMPLES_PER_FRAME: u64 = 1 << 15;

/// The accumulation of the current image size.
struct WindowAccumulation {
    buffer: Buffer,
    schedule: ProgressiveSchedule,
    /// Adaptive sampling's rounds (`rounds`), when the frames sample adaptively.
    rounds: Option<rounds::Rounds>,
}

pub struct Viewer {
    // Fields drop in order, after `Drop` waited for the device: frame slots, the panel, the
    // passes' images, the swapchain, its surface, then the renderer (device, instance).
    frames: Frames,
    overlay: Option<Overlay>,
    /// Draws the non-final views straight into the window image (made with the swapchain).
    view_pass: Option<ViewPass>,
    resolve: ResolvePass,
    accum: Option<WindowAccumulation>,
    swapchain: Option<Swapchain>,
    surface: WindowSurface,
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
        let ctx = gpu.ctx().clone();
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

    /// Replaces the scene the window draws (an animated file's pose of another frame), the
    /// meshes `motion` names moving over the frame's shutter (the software traversal alone
    /// meets them: `GpuRenderer::load_moving_scene`): waits for the frames in flight, then
    /// uploads it and points every pass at it.
    pub fn load_scene(
        &mut self,
        scene: &Scene,
        motion: Option<&ObjectMotion>,
    ) -> Result<(), GpuError> {
        self.wait_idle()?;
        self.gpu.load_moving_scene(scene, motion)?;
        if let Some(view_pass) = &self.view_pass {
            view_pass.rebind(self.gpu.scene_buffers()?);
        }
        Ok(())
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
        let ctx = self.gpu.ctx().clone();
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
        }
        let overlay = match &mut self.overlay {
            Some(overlay) => overlay,
            empty => empty.insert(Overlay::new(&ctx, swapchain.format, FRAMES_IN_FLIGHT)?),
        };
        overlay.attach(&swapchain)?;
        if self
            .view_pass
            .as_ref()
            .is_none_or(|v| v.format() != swapchain.format)
        {
            self.view_pass = None;
        }
        let view_pass = match &mut self.view_pass {
            Some(pass) => pass,
            // Left as the copy into the window leaves it, for the panel's pass.
            empty => empty.insert(ViewPass::new(
                &ctx,
                swapchain.format,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            )?),
        };
        view_pass.attach(
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
        let ctx = self.gpu.ctx().clone();
        let bytes = u64::from(width) * u64::from(height) * 16;
        if bytes > u64::from(ctx.report.max_storage_buffer_range) {
            return Err(GpuError::Invalid(format!(
                "a {width}x{height} preview needs a {bytes}-byte accumulation buffer, more than \
                 the device's storage buffer range ({})",
                ctx.report.max_storage_buffer_range
            )));
        }
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
        let targets = self
            .gpu
            .prepare_frames((width, height), self.estimator, &buffer)?;
        // A new size restarts the accumulation: the hybrid's plan is made again.
        self.plan_spp = None;
        self.resolve.bind(&buffer, targets, width, height)?;
        self.accum = Some(WindowAccumulation {
            buffer,
            schedule: ProgressiveSchedule::new(width, height, TRACE_GROUP_SIZE, target),
            rounds: None,
        });
        Ok(())
    }

    /// The accumulation so far (sum / samples per pixel; black where none yet), for
    /// screenshots. Waits for the device.
    pub fn read_accumulation(&mut self) -> Result<Option<Image>, GpuError> {
        let Some(accum) = self.accum.as_ref() else {
            return Ok(None);
        };
        let Ok(targets) = self.gpu.gbuffer_targets() else {
            return Ok(None);
        };
        let (width, height) = (targets.width, targets.height);
        self.wait_idle()?;
        let pixels = u64::from(width) * u64::from(height);
        let sums = rounds::read_sums(self.gpu.ctx(), &accum.buffer, pixels)?;
        Ok(Some(Image {
            width,
            height,
            pixels: sums
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

    /// The lens's own light (`--flare`, `--starburst`) the final view adds to the accumulation
    /// from the next frame on (`None`: none), an image of the current size. Waits for the
    /// device.
    pub fn set_flare(&mut self, light: Option<&Image>) -> Result<(), GpuError> {
        self.wait_idle()?;
        self.resolve
            .set_flare(light.map(|image| image.pixels.as_slice()))
    }

    fn wait_idle(&self) -> Result<(), GpuError> {
        self.gpu.ctx().wait_idle()
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
