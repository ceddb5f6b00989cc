//! What the trace pass records into a command buffer: parameter updates, dispatches, the
//! hybrid's lit pre-pass, the ray counter's copies, and one step of an `accumulate` call with
//! the copies of its band's sums.

use ash::vk;

use super::accumulate::RecordSamples;
use super::steps::Step;
use super::TracePass;
use crate::core::buffer::barrier;
use lensray_core::interface::{
    TraceParams, TracePush, TRACE_GROUP_SIZE as GROUP, TRACE_MODE_SHORTCUT,
};

impl TracePass {
    /// Records an update of the uniform parameters, ordered before later dispatches and after
    /// earlier ones (frames in flight share the buffer; the queue orders the updates).
    pub(crate) fn record_params(&self, cmd: vk::CommandBuffer, params: &TraceParams) {
        let ctx = &self.ctx;
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::UNIFORM_READ,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        // SAFETY: recording state; the buffer has TRANSFER_DST usage and the data is a
        // multiple of 4 bytes under 64 KiB.
        unsafe {
            ctx.device
                .cmd_update_buffer(cmd, self.params.buffer, 0, bytemuck::bytes_of(params))
        };
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::UNIFORM_READ,
        );
    }

    /// Records the hybrid's lit pre-pass over a `width` x `height` image (TRACE_MODE_SHORTCUT:
    /// each pixel's shortcut value and shadow state into the plan buffer, which must hold the
    /// image), after the parameters of the camera and settings; the plan's steps follow it.
    /// Ordered after earlier transfers and dispatches (parameter updates, clears).
    pub(crate) fn record_lit_prepass(&self, cmd: vk::CommandBuffer, width: u32, height: u32) {
        let push = TracePush {
            band_origin: 0,
            band_height: height,
            block_first: 0,
            block_stride: 1,
            block_count: height.div_ceil(GROUP),
            sample_begin: 0,
            sample_end: 0,
            mode: TRACE_MODE_SHORTCUT,
        };
        self.record_ordered_dispatch(cmd, push, width);
    }

    /// Records one dispatch as `record_dispatch` does, ordered after earlier transfers and
    /// dispatches (parameter updates, clears, copies, the previous dispatch, a raster pass).
    pub(crate) fn record_ordered_dispatch(
        &self,
        cmd: vk::CommandBuffer,
        push: TracePush,
        width: u32,
    ) {
        barrier(
            &self.ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        self.record_dispatch(cmd, push, width);
    }

    /// Records a clear of the ray counter (words 0 and 1: all rays, the first dispatch's);
    /// word 2 keeps the hybrid's lit pre-pass until the next render reads it.
    pub(crate) fn record_clear_ray_counter(&self, cmd: vk::CommandBuffer) {
        // SAFETY: recording state; the counters buffer has TRANSFER_DST usage.
        unsafe {
            self.ctx
                .device
                .cmd_fill_buffer(cmd, self.counters.buffer, 0, 8, 0)
        };
    }

    /// Records a copy of the rays counted so far (the hybrid's lit pre-pass) into word 2, which
    /// the next `accumulate` adds to its report: the plan is not waited for.
    pub(crate) fn record_keep_prepass_rays(&mut self, cmd: vk::CommandBuffer) {
        self.record_copy_counter(cmd, 8);
        self.prepass_rays_pending = true;
    }

    /// Records one dispatch of the blocks and samples `push` names, over an image `width`
    /// pixels wide (parameters and accumulation bound and ordered by the caller).
    fn record_dispatch(&self, cmd: vk::CommandBuffer, push: TracePush, width: u32) {
        self.pipeline_in_use().bind(cmd, bytemuck::bytes_of(&push));
        // SAFETY: compute pipeline and its complete descriptor set are bound.
        unsafe {
            self.ctx
                .device
                .cmd_dispatch(cmd, width.div_ceil(GROUP), push.block_count, 1)
        };
    }

    /// Records the pipeline's first dispatch, one that traces nothing (its push names no blocks:
    /// every invocation leaves at once), between timestamps `query` and `query + 1`. A driver
    /// that compiles lazily (lavapipe's llvmpipe) compiles the shaders in a pipeline's first
    /// dispatch, half a minute on a device's first use: timed apart here, that stays out of the
    /// render's tracing time and rays per second (`Timings::compile_ms`).
    pub(super) fn record_compile(&self, cmd: vk::CommandBuffer, mode: u32, query: u32) {
        let push = TracePush {
            band_origin: 0,
            band_height: 0,
            block_first: 0,
            block_stride: 1,
            block_count: 0,
            sample_begin: 0,
            sample_end: 0,
            mode,
        };
        self.timestamps
            .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, query);
        self.pipeline_in_use().bind(cmd, bytemuck::bytes_of(&push));
        // SAFETY: compute pipeline and its complete descriptor set are bound.
        unsafe { self.ctx.device.cmd_dispatch(cmd, 1, 1, 1) };
        self.timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, query + 1);
    }

    /// Keeps the rays counted so far (the pipeline's first dispatch) in the counter's second
    /// word.
    pub(super) fn record_copy_first_rays(&self, cmd: vk::CommandBuffer) {
        self.record_copy_counter(cmd, 4);
    }

    /// Copies the counter's word 0 (rays so far) to the byte offset `to`.
    fn record_copy_counter(&self, cmd: vk::CommandBuffer, to: u64) {
        let ctx = &self.ctx;
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_READ,
        );
        let copy = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(to)
            .size(4);
        // SAFETY: recording state; the counters buffer (16 bytes, TRANSFER usages) holds both
        // words (`to` is 4 or 8), which do not overlap.
        unsafe {
            ctx.device
                .cmd_copy_buffer(cmd, self.counters.buffer, self.counters.buffer, &[copy])
        };
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
    }

    /// Records one step: the band's sums in from film `film` first (`load`), then the
    /// estimator's dispatch (`batch`, with the raster path's pass before it) between
    /// timestamps `2 index` and `2 index + 1`, then the band's sums back to the film
    /// (`copy_out`).
    /// The dispatch covers the blocks of GROUP rows `block_first + i * block_stride`,
    /// i < block_count, of the band.
    pub(super) fn record_step(
        &self,
        cmd: vk::CommandBuffer,
        step: &Step,
        (film, width): (usize, u32),
        index: u32,
        batch: &dyn RecordSamples,
    ) {
        let ctx = &self.ctx;
        let band_sums = &self.accum.as_ref().expect("band buffer").buffer;
        let film = self.films.sums(film);
        let push = step.push;
        // Earlier steps and submissions (the previous dispatch, copies, clears) first.
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_WRITE,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        let band = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(u64::from(push.band_origin) * u64::from(width) * 16)
            .size(u64::from(push.band_height) * u64::from(width) * 16);
        if step.load {
            let up = vk::BufferCopy::default()
                .src_offset(band.dst_offset)
                .dst_offset(0)
                .size(band.size);
            // SAFETY: recording state; the buffers have the TRANSFER usages used and the
            // band's sums fit both (sizes computed in `accumulate`).
            unsafe {
                ctx.device
                    .cmd_copy_buffer(cmd, film.buffer, band_sums.buffer, &[up])
            };
            barrier(
                ctx,
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
            );
        }
        self.timestamps
            .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 2 * index);
        batch.record(self, cmd, push, width);
        self.timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 2 * index + 1);
        if let Some(bytes) = step.copy_out {
            barrier(
                ctx,
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_WRITE,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_READ,
            );
            // SAFETY: the band's sums fit both buffers (sizes computed in `accumulate`).
            unsafe {
                ctx.device
                    .cmd_copy_buffer(cmd, band_sums.buffer, film.buffer, &[band.size(bytes)])
            };
        }
    }
}
