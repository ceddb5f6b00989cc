//! A frame's phases: wait for the slot and apply the panel's textures, read the slot's last
//! times, acquire the window image, decide the frame's work, record (`record`), submit and
//! present, then read back a pick and report the accumulation's progress.

use std::sync::Arc;

use ash::vk;

use super::{FrameRequest, FrameResult, FrameTimes, Viewer, WindowAccumulation};
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::swapchain::{Acquired, Swapchain};
use crate::present::frames::FrameSlot;
use crate::present::overlay::Overlay;
use crate::present::resolve::ResolvePass;
use crate::present::view_pass::ViewPass;
use crate::{Estimator, GpuRenderer};
use lensray_core::camera::Camera;
use lensray_core::film::progressive::WorkItem;
use lensray_core::interface::VIEW_FINAL;

/// Trace time aimed at per frame: the G-buffer view stays responsive while samples accumulate.
const TRACE_MS_PER_FRAME: f64 = 20.0;
/// Dispatches per frame, at most (each is one group of rows of one sample, or whole samples).
const MAX_DISPATCHES_PER_FRAME: usize = 64;

/// The parts of the viewer one frame uses, borrowed apart so that its phases can share them.
pub(super) struct Frame<'v> {
    pub(super) ctx: Arc<Context>,
    /// The slot the frame records into (its previous frame finished).
    pub(super) slot: &'v mut FrameSlot,
    pub(super) swapchain: &'v Swapchain,
    pub(super) accum: &'v mut WindowAccumulation,
    pub(super) gpu: &'v GpuRenderer,
    pub(super) view_pass: Option<&'v ViewPass>,
    pub(super) resolve: &'v ResolvePass,
    pub(super) overlay: Option<&'v mut Overlay>,
    pub(super) estimator: Estimator,
    pub(super) plan_spp: &'v mut Option<u32>,
    pub(super) samples_per_frame: &'v mut u64,
    pub(super) recreate: &'v mut bool,
}

/// What one frame does, decided before its commands are recorded.
pub(super) struct FramePlan {
    /// The window image it draws into.
    pub(super) image_index: u32,
    /// The accumulation starts again: cleared, with new trace parameters.
    pub(super) restart: bool,
    /// The trace dispatches' samples and rows (empty: the frame traces nothing).
    pub(super) work: Vec<WorkItem>,
    /// The frame makes the hybrid's plan before its dispatches.
    pub(super) make_plan: bool,
    /// The final view needs no G-buffer this frame.
    pub(super) skip_gbuffer: bool,
    /// The view pass draws straight into the window image: no G-buffer, resolve or copy.
    pub(super) direct: bool,
}

impl Viewer {
    /// Draws one frame (after [`Self::prepare`], with a camera of the size it returned).
    pub fn draw(&mut self, mut request: FrameRequest<'_>) -> Result<FrameResult, GpuError> {
        let mut result = FrameResult::default();
        self.start_frame(&mut request)?;
        self.adaptive_step(&mut request)?;
        let Some(mut frame) = self.frame() else {
            return Ok(result);
        };
        frame.check_size(&request.shot.camera)?;
        frame.read_last_times(&mut result)?;
        let Some(image_index) = frame.acquire()? else {
            return Ok(result);
        };
        let plan = frame.plan(&request, image_index);
        frame.record(&request, &plan)?;
        frame.submit_and_present(&plan)?;
        if request.pick.is_some() {
            frame.read_pick(&mut result)?;
        }
        frame.report(&request, &mut result);
        self.frames.advance();
        result.drawn = true;
        Ok(result)
    }

    /// Waits for the current slot's previous frame, applies egui's texture changes, makes the
    /// view pass's pipeline of the request's view if it is new, and makes the trace pass's
    /// camera tables those of the request.
    fn start_frame(&mut self, request: &mut FrameRequest<'_>) -> Result<(), GpuError> {
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
        // A view's pipeline is made when the view is first shown.
        if let Some(pass) = self
            .view_pass
            .as_mut()
            .filter(|_| request.view != VIEW_FINAL)
        {
            pass.ensure_view(request.view, self.gpu.scene_buffers()?)?;
        }
        if self.gpu.camera_tables_differ(&request.shot.camera) {
            // Frames in flight bind the old tables (a new aperture image: rare).
            self.wait_idle()?;
            self.gpu.ensure_camera_tables(&request.shot.camera)?;
        }
        Ok(())
    }

    /// The parts of the viewer the current frame uses; `None` while there is nothing to draw
    /// into (no swapchain or accumulation: minimised).
    fn frame(&mut self) -> Option<Frame<'_>> {
        let (Some(swapchain), Some(accum)) = (self.swapchain.as_ref(), self.accum.as_mut()) else {
            return None;
        };
        Some(Frame {
            ctx: self.gpu.ctx().clone(),
            slot: &mut self.frames.slots[self.frames.current],
            swapchain,
            accum,
            gpu: &self.gpu,
            view_pass: self.view_pass.as_ref(),
            resolve: &self.resolve,
            overlay: self.overlay.as_mut(),
            estimator: self.estimator,
            plan_spp: &mut self.plan_spp,
            samples_per_frame: &mut self.samples_per_frame,
            recreate: &mut self.recreate,
        })
    }
}

impl Frame<'_> {
    /// An error when `camera` is not of the window image's size.
    fn check_size(&self, camera: &Camera) -> Result<(), GpuError> {
        let swapchain = self.swapchain;
        if [camera.width, camera.height] != [swapchain.extent.width, swapchain.extent.height] {
            return Err(GpuError::Invalid(format!(
                "the camera is {}x{} but the window image {}x{}",
                camera.width, camera.height, swapchain.extent.width, swapchain.extent.height
            )));
        }
        Ok(())
    }

    /// The times of the slot's previous frame, if it had one, into `result`; the samples of
    /// the next frames are sized from its trace speed.
    fn read_last_times(&mut self, result: &mut FrameResult) -> Result<(), GpuError> {
        if self.slot.submitted {
            result.times = Some(read_times(self.gpu, self.slot)?);
            if let Some(t) = result.times.filter(|t| t.trace_ms > 0.0) {
                // Shrinks at once, grows at most 2x per frame.
                let rate = t.trace_work as f64 / t.trace_ms;
                *self.samples_per_frame = ((rate * TRACE_MS_PER_FRAME) as u64)
                    .min(2 * *self.samples_per_frame)
                    .clamp(1024, 1 << 26);
            }
        }
        Ok(())
    }

    /// The window image to draw into; `None` when the swapchain is out of date (made again
    /// before the next frame).
    fn acquire(&mut self) -> Result<Option<u32>, GpuError> {
        match self.swapchain.acquire(&self.slot.image_acquired)? {
            Acquired::Image(i) => Ok(Some(i)),
            Acquired::OutOfDate => {
                *self.recreate = true;
                Ok(None)
            }
        }
    }

    /// Decides the frame's work: a restart, the samples to trace, whether it makes the
    /// hybrid's plan, draws the G-buffer, or draws the view pass straight into the window.
    fn plan(&mut self, request: &FrameRequest<'_>, image_index: u32) -> FramePlan {
        // The hybrid's plan depends on the target spp (sample counts grow with it): a new
        // target restarts its accumulation.
        let restart = request.restart
            || (self.estimator == Estimator::Hybrid
                && self.plan_spp.is_some_and(|spp| spp != request.target_spp));
        let accum = &mut *self.accum;
        if restart {
            accum.schedule.restart();
            *self.plan_spp = None;
        }
        // Adaptive sampling's frames go as far as the round's end (`rounds`).
        let target = accum.rounds.as_ref().map_or(request.target_spp, |r| r.end);
        accum.schedule.set_target(target);
        let work = if request.view == VIEW_FINAL && request.host.is_none() {
            accum
                .schedule
                .plan(*self.samples_per_frame, MAX_DISPATCHES_PER_FRAME)
        } else {
            Vec::new()
        };
        self.slot.trace_work = work.iter().map(|w| w.pixel_samples).sum();
        // A view other than the final one, without a pick (which reads the G-buffer), is drawn
        // by the view pass straight into the window image: no G-buffer, resolve or copy.
        let direct =
            self.view_pass.is_some() && request.view != VIEW_FINAL && request.pick.is_none();
        let make_plan =
            self.estimator == Estimator::Hybrid && !work.is_empty() && self.plan_spp.is_none();
        // The final view shows the G-buffer only where the accumulation has no sample yet: once
        // every pixel has one, a frame that neither picks nor plans from it skips the pass.
        let skip_gbuffer = request.view == VIEW_FINAL
            && request.pick.is_none()
            && !make_plan
            && request.host.is_none()
            && accum.schedule.samples_complete() > 0;
        FramePlan {
            image_index,
            restart,
            work,
            make_plan,
            skip_gbuffer,
            direct,
        }
    }

    /// Submits the recorded command buffer (after the window image's acquire, signalling its
    /// rendering) and presents the image; an out-of-date swapchain is made again later.
    fn submit_and_present(&mut self, plan: &FramePlan) -> Result<(), GpuError> {
        let image_index = plan.image_index;
        // The first use of the window image is the view pass or the copy into it.
        let wait_stage = if plan.direct {
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
        } else {
            vk::PipelineStageFlags::TRANSFER
        };
        self.ctx.submit_frame(
            &self.slot.cmd,
            (&self.slot.image_acquired, wait_stage),
            &self.swapchain.rendered[image_index as usize],
            &self.slot.fence,
        )?;
        self.slot.submitted = true;
        if !self.swapchain.present(image_index)? {
            *self.recreate = true;
        }
        Ok(())
    }

    /// Waits for this frame and reads the view depth it picked into `result`.
    fn read_pick(&mut self, result: &mut FrameResult) -> Result<(), GpuError> {
        // A rare event: wait for this frame so the focus applies to the next one.
        self.slot.wait()?;
        let depth = bytemuck::cast_slice::<u8, f32>(self.slot.pick.read()?)[0];
        result.picked_depth = Some((depth > 0.0).then_some(depth));
        Ok(())
    }

    /// The samples every pixel has, and whether that is the target: the host's with host
    /// samples, else the accumulation's.
    fn report(&self, request: &FrameRequest<'_>, result: &mut FrameResult) {
        match &request.host {
            Some(host) => {
                result.spp = host.spp;
                result.converged = host.converged;
                result.adaptive_active = host.adaptive_active;
            }
            None => match &self.accum.rounds {
                // The samples of the pixels that go on, and how many there are.
                Some(rounds) => {
                    result.spp = rounds.end;
                    result.converged = rounds.done;
                    result.adaptive_active = Some(rounds.active);
                }
                None => {
                    result.spp = self.accum.schedule.samples_complete();
                    result.converged = self.accum.schedule.converged();
                }
            },
        }
    }
}

/// The GPU times of `slot`'s finished frame, from its timestamps.
fn read_times(gpu: &GpuRenderer, slot: &FrameSlot) -> Result<FrameTimes, GpuError> {
    let t = slot.timestamps.results()?;
    let ms = |a: usize, b: usize| gpu.ctx().elapsed_ns(t[a], t[b]) * 1e-6;
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
