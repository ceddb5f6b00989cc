//! The recording of a frame's command buffer, in this order: the G-buffer (or the view pass
//! straight into the window image) and a pick, the accumulation's restart and host samples,
//! the hybrid's plan, the trace dispatches, the resolve, the copy into the window image and
//! the panel. Timestamps 0..7 of the slot bracket the phases (see `read_times`).

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::draw::{Frame, FramePlan};
use super::FrameRequest;
use crate::core::buffer::{barrier, barrier_to_host, Buffer};
use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};
use crate::core::image::{record_copy_to_buffer, transition, Transition};
use crate::passes::gbuffer::GBufferTargets;
use crate::present::frames::FrameSlot;
use crate::renderer::SampleBatch;
use lensray_core::interface::{TracePush, TRACE_MODE_ALL};

impl Frame<'_> {
    /// Records the frame's command buffer, phase after phase, ending it.
    pub(super) fn record(
        &mut self,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
    ) -> Result<(), GpuError> {
        let cmd = self.slot.cmd;
        self.begin_commands()?;
        let gpu = self.gpu;
        let batch = gpu.sample_batch(request.shot, self.estimator)?;
        self.record_raster(request, plan, &batch)?;
        let targets = gpu.gbuffer_targets().expect("made in resize_images");
        if let Some([x, y]) = request.pick {
            record_pick(&self.ctx, cmd, targets.view_depth.image, &*self.slot, x, y);
        }

        self.slot
            .timestamps
            .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 2);
        if plan.restart {
            self.record_restart(&batch);
        }
        if let Some(sums) = request.host.as_ref().and_then(|h| h.sums) {
            self.record_host_sums(sums)?;
        }
        self.slot
            .timestamps
            .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 6);
        if plan.make_plan {
            gpu.record_plan(cmd, &batch, request.target_spp)?;
            *self.plan_spp = Some(request.target_spp);
        }
        self.slot.made_plan = plan.make_plan;
        self.slot
            .timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 7);
        self.record_dispatches(plan, &batch);
        self.slot
            .timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 3);
        self.record_resolve(request, plan, targets);
        self.record_window(request, plan)
    }

    /// Resets the slot's fence and command buffer and begins recording, after the previous
    /// frame's work; resets the slot's timestamps.
    fn begin_commands(&self) -> Result<(), GpuError> {
        let device = &self.ctx.device;
        let cmd = self.slot.cmd;
        // SAFETY: the slot's previous frame finished (fence waited): its command buffer may be
        // reset and re-recorded, its fence reset.
        unsafe {
            device
                .reset_fences(&[self.slot.fence])
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
            &self.ctx,
            cmd,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_WRITE,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        self.slot.timestamps.reset(cmd);
        Ok(())
    }

    /// Records the G-buffer pass, or the view pass into the window image, between timestamps
    /// 0 and 1 (only the timestamps when the final view skips the G-buffer). Both draw with the
    /// batch's G-buffer camera: the hybrid plans from the G-buffer of its planning camera,
    /// which the views show as well.
    fn record_raster(
        &mut self,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
        batch: &SampleBatch<'_>,
    ) -> Result<(), GpuError> {
        let cmd = self.slot.cmd;
        let view_pass = self.view_pass.filter(|_| plan.direct);
        self.slot.drew_gbuffer = !plan.skip_gbuffer;
        let slot = &*self.slot;
        match view_pass {
            None if plan.skip_gbuffer => {
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
                    self.gpu.scene_buffers()?,
                    batch.gbuffer_camera(),
                    request.shot.render.background,
                    crate::upload::view_params(&request.shot.camera, request.view),
                    plan.image_index as usize,
                );
                slot.timestamps
                    .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
            }
            None => self.gpu.record_gbuffer(cmd, batch, (&slot.timestamps, 0))?,
        }
        Ok(())
    }

    /// Records the restart of the accumulation: cleared, then the trace parameters of the
    /// batch's shot.
    fn record_restart(&self, batch: &SampleBatch<'_>) {
        let cmd = self.slot.cmd;
        // SAFETY: recording state; the buffer has TRANSFER_DST usage.
        unsafe {
            self.ctx
                .device
                .cmd_fill_buffer(cmd, self.accum.buffer.buffer, 0, vk::WHOLE_SIZE, 0)
        };
        self.gpu.record_trace_params(cmd, batch);
    }

    /// Records the copy of samples traced on the host into the accumulation, through the
    /// slot's staging buffer (made larger when they do not fit).
    fn record_host_sums(&mut self, sums: &[[f32; 4]]) -> Result<(), GpuError> {
        let ctx = &self.ctx;
        let cmd = self.slot.cmd;
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
            slot.upload = Some(Buffer::new(
                ctx,
                "preview host samples",
                bytes.len() as u64,
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::CpuToGpu,
            )?);
        }
        let upload = slot.upload.as_mut().expect("created above");
        upload.write(bytes)?;
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_READ,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        let region = vk::BufferCopy::default().size(bytes.len() as u64);
        // SAFETY: recording state; the slot's upload buffer is not in use (its fence was
        // waited) and the region fits both buffers (checked above).
        unsafe {
            ctx.device
                .cmd_copy_buffer(cmd, upload.buffer, accum.buffer.buffer, &[region])
        };
        Ok(())
    }

    /// Records the frame's samples, each work item over the whole image through the batch
    /// (the estimator's passes with them).
    fn record_dispatches(&self, plan: &FramePlan, batch: &SampleBatch<'_>) {
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
            self.gpu.record_samples(self.slot.cmd, batch, push);
        }
    }

    /// Records the resolve of the accumulation into the display image (not in a frame of the
    /// view pass), after the dispatches, up to timestamp 4.
    fn record_resolve(
        &self,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
        targets: &GBufferTargets,
    ) {
        let cmd = self.slot.cmd;
        barrier(
            &self.ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ,
        );
        if !plan.direct {
            self.resolve.record(
                cmd,
                targets,
                &crate::upload::resolve_push(&request.shot.camera, request.view),
            );
        }
        self.slot
            .timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 4);
    }

    /// Records the display image's copy into the window image (not in a frame of the view
    /// pass) and the panel over it, up to timestamp 5, and ends the command buffer.
    fn record_window(
        &mut self,
        request: &FrameRequest<'_>,
        plan: &FramePlan,
    ) -> Result<(), GpuError> {
        let cmd = self.slot.cmd;
        let image_index = plan.image_index;
        if !plan.direct {
            let window_image = self.swapchain.images[image_index as usize];
            let display = self.resolve.display.as_ref().expect("bound in prepare");
            let extent = self.swapchain.extent;
            record_copy_to_window(&self.ctx, cmd, display.image, window_image, extent);
        }
        if let Some(overlay) = &mut self.overlay {
            overlay.record(cmd, image_index, request.overlay.as_ref())?;
        }
        self.slot
            .timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 5);
        // SAFETY: recording began in `begin_commands`.
        unsafe { self.ctx.device.end_command_buffer(cmd) }.map_err(vk_err("vkEndCommandBuffer"))
    }
}

/// Copies the view depth at (x, y) (G-buffer in TRANSFER_SRC_OPTIMAL) to the slot's pick buffer.
fn record_pick(
    ctx: &Context,
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
    ctx: &Context,
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
