//! The recording of a frame's command buffer, in this order: the G-buffer (or the view pass
//! straight into the window image) and a pick, the accumulation's restart and host samples,
//! the hybrid's plan, the trace dispatches, the resolve, the copy into the window image and
//! the panel. Timestamps 0..7 of the slot bracket the phases (see `read_times`).

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::draw::{Frame, FramePlan};
use super::FrameRequest;
use crate::core::buffer::Buffer;
use crate::core::error::GpuError;
use crate::core::image::Transition;
use crate::core::recorder::Recorder;
use crate::passes::gbuffer::GBufferTargets;
use crate::renderer::SampleBatch;
use lensray_core::interface::{TracePush, TRACE_MODE_ALL};

impl Frame<'_> {
    /// Records the frame's command buffer, phase after phase, ending it.
    pub(super) fn record(
        &mut self,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
    ) -> Result<(), GpuError> {
        // The slot's previous frame finished (its fence was waited for). What the frames
        // share (the G-buffer, the accumulation) orders itself after the frames before: the
        // recorder knows nothing of them, so each one's first use waits for earlier writes.
        let ctx = self.ctx.clone();
        let mut rec = Recorder::begin_again(&ctx, &self.slot.cmd, &self.slot.fence)?;
        rec.reset_queries(&self.slot.timestamps);
        let gpu = self.gpu;
        let batch = gpu.sample_batch(request.shot, self.estimator)?;
        let adaptive = self.accum.rounds.is_some();
        let batch = if adaptive { batch.adaptive()? } else { batch };
        self.record_raster(&mut rec, request, plan, &batch)?;
        let targets = gpu.gbuffer_targets()?;
        if let Some([x, y]) = request.pick {
            // The G-buffer pass left the image in TRANSFER_SRC_OPTIMAL with its writes ordered
            // before transfers; (x, y) lies inside it (checked by the caller).
            let pick = &self.slot.pick;
            rec.copy_image_to_buffer(targets.view_depth.image, pick, [x, y], [1, 1]);
            rec.read_on_host(&[pick]);
        }
        let stamps = &self.slot.timestamps;
        rec.timestamp(stamps, vk::PipelineStageFlags::TOP_OF_PIPE, 2);
        if plan.restart {
            rec.fill_buffer(&self.accum.buffer, 0, vk::WHOLE_SIZE, 0);
            if adaptive {
                gpu.record_adaptive_start(&mut rec);
            }
            gpu.record_trace_params(&mut rec, &batch);
        }
        if let Some(sums) = request.host.as_ref().and_then(|h| h.sums) {
            self.record_host_sums(&mut rec, sums)?;
        }
        let stamps = &self.slot.timestamps;
        rec.timestamp(stamps, vk::PipelineStageFlags::TOP_OF_PIPE, 6);
        if plan.make_plan {
            gpu.record_plan(&mut rec, &batch, request.target_spp)?;
            *self.plan_spp = Some(request.target_spp);
        }
        self.slot.made_plan = plan.make_plan;
        let stamps = &self.slot.timestamps;
        rec.timestamp(stamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 7);
        self.record_dispatches(&mut rec, plan, &batch);
        rec.timestamp(stamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 3);
        self.record_resolve(&mut rec, request, plan, targets);
        self.record_window(&mut rec, request, plan)?;
        rec.finish()
    }

    /// Records the G-buffer pass, or the view pass into the window image, between timestamps
    /// 0 and 1 (only the timestamps when the final view skips the G-buffer). Both draw with the
    /// batch's G-buffer camera: the hybrid plans from the G-buffer of its planning camera,
    /// which the views show as well.
    fn record_raster(
        &mut self,
        rec: &mut Recorder<'_>,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
        batch: &SampleBatch<'_>,
    ) -> Result<(), GpuError> {
        let view_pass = self.view_pass.filter(|_| plan.direct);
        self.slot.drew_gbuffer = !plan.skip_gbuffer;
        let slot = &*self.slot;
        match view_pass {
            None if plan.skip_gbuffer => {
                rec.timestamp(&slot.timestamps, vk::PipelineStageFlags::TOP_OF_PIPE, 0);
                rec.timestamp(&slot.timestamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
            }
            Some(pass) => {
                rec.timestamp(&slot.timestamps, vk::PipelineStageFlags::TOP_OF_PIPE, 0);
                pass.record(
                    rec,
                    self.gpu.scene_buffers()?,
                    batch.gbuffer_camera(),
                    request.shot.render.background,
                    crate::upload::view_params(&request.shot.camera, request.view),
                    plan.image_index as usize,
                );
                rec.timestamp(&slot.timestamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
            }
            None => self.gpu.record_gbuffer(rec, batch, (&slot.timestamps, 0))?,
        }
        Ok(())
    }

    /// Records the copy of samples traced on the host into the accumulation, through the
    /// slot's staging buffer (made larger when they do not fit).
    fn record_host_sums(
        &mut self,
        rec: &mut Recorder<'_>,
        sums: &[[f32; 4]],
    ) -> Result<(), GpuError> {
        let ctx = &self.ctx;
        let accum = &*self.accum;
        let bytes: &[u8] = bytemuck::cast_slice(sums);
        if bytes.len() as u64 > accum.buffer.size {
            return Err(GpuError::Invalid(format!(
                "{} bytes of host samples for a {}-byte accumulation",
                bytes.len(),
                accum.buffer.size
            )));
        }
        let slot = &mut *self.slot;
        if slot
            .upload
            .as_ref()
            .is_none_or(|b| b.size < bytes.len() as u64)
        {
            slot.upload = None;
        }
        let upload = match &mut slot.upload {
            Some(upload) => upload,
            empty => empty.insert(Buffer::new(
                ctx,
                "preview host samples",
                bytes.len() as u64,
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::CpuToGpu,
            )?),
        };
        upload.write(bytes)?;
        // The slot's upload buffer is not in use (its fence was waited for) and the region fits
        // both buffers (checked above).
        let region = vk::BufferCopy::default().size(bytes.len() as u64);
        rec.copy_buffer(upload, &accum.buffer, &[region]);
        Ok(())
    }

    /// Records the frame's samples, each work item over the whole image through the batch
    /// (the estimator's passes with them).
    fn record_dispatches(&self, rec: &mut Recorder<'_>, plan: &FramePlan, batch: &SampleBatch<'_>) {
        let height = batch.shot().camera.height;
        for item in &plan.work {
            let push = TracePush {
                band_origin: 0,
                band_height: height,
                block_first: item.block_first,
                block_stride: item.block_stride,
                block_count: item.block_count,
                sample_begin: item.sample_begin,
                sample_end: item.sample_end,
                // The batch sets its estimator's mode.
                mode: TRACE_MODE_ALL,
            };
            self.gpu.record_samples(rec, batch, push);
        }
    }

    /// Records the resolve of the accumulation into the display image (not in a frame of the
    /// view pass), after the dispatches, up to timestamp 4.
    fn record_resolve(
        &self,
        rec: &mut Recorder<'_>,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
        targets: &GBufferTargets,
    ) {
        if !plan.direct {
            self.resolve.record(
                rec,
                targets,
                &crate::upload::resolve_push(&request.shot.camera, request.view, &request.display),
            );
        }
        rec.timestamp(
            &self.slot.timestamps,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            4,
        );
    }

    /// Records the display image's copy into the window image (not in a frame of the view
    /// pass) and the panel over it, up to timestamp 5.
    fn record_window(
        &mut self,
        rec: &mut Recorder<'_>,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
    ) -> Result<(), GpuError> {
        let image_index = plan.image_index;
        if !plan.direct {
            let window_image = self.swapchain.images[image_index as usize];
            let display = self.resolve.display.as_ref().expect("bound in prepare");
            let extent = self.swapchain.extent;
            record_copy_to_window(rec, display.image, window_image, extent);
        }
        if let Some(overlay) = &mut self.overlay {
            overlay.record(rec, image_index, request.overlay.as_ref())?;
        }
        rec.timestamp(
            &self.slot.timestamps,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            5,
        );
        Ok(())
    }
}

/// Blits the display image (TRANSFER_SRC_OPTIMAL) onto the window image, which ends in
/// TRANSFER_DST_OPTIMAL for the overlay's render pass.
fn record_copy_to_window(
    rec: &mut Recorder<'_>,
    display: vk::Image,
    window: vk::Image,
    extent: vk::Extent2D,
) {
    rec.transition(
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
    rec.blit(display, window, extent);
}
