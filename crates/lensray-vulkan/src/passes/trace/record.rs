//! What the trace pass records: parameter updates, dispatches, the hybrid's lit pre-pass, the
//! ray counter's copies, and one step of an `accumulate` call with the copies of its band's
//! sums. Each command names the buffers it reads and writes; the recorder puts the barriers.

use ash::vk;

use super::accumulate::RecordSamples;
use super::steps::Step;
use super::TracePass;
use crate::core::recorder::{Access, Recorder};
use lensray_core::interface::{
    TraceParams, TracePush, TRACE_GROUP_SIZE as GROUP, TRACE_MODE_SHORTCUT,
};

impl TracePass {
    /// Records an update of the uniform parameters (frames in flight share the buffer; the
    /// queue orders the updates).
    pub(crate) fn record_params(&self, rec: &mut Recorder<'_>, params: &TraceParams) {
        rec.update_buffer(&self.params, bytemuck::bytes_of(params));
    }

    /// Records the hybrid's lit pre-pass over a `width` x `height` image (TRACE_MODE_SHORTCUT:
    /// each pixel's shortcut value and shadow state into the plan buffer, which must hold the
    /// image), after the parameters of the camera and settings; the plan's steps follow it.
    pub(crate) fn record_lit_prepass(&self, rec: &mut Recorder<'_>, width: u32, height: u32) {
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
        self.record_dispatch(rec, push, width);
    }

    /// Records a clear of the ray counter (words 0 and 1: all rays, the first dispatch's);
    /// word 2 keeps the hybrid's lit pre-pass until the next render reads it.
    pub(crate) fn record_clear_ray_counter(&self, rec: &mut Recorder<'_>) {
        rec.fill_buffer(&self.counters, 0, 8, 0);
    }

    /// Records a copy of the rays counted so far (the hybrid's lit pre-pass) into word 2, which
    /// the next `accumulate` adds to its report: the plan is not waited for.
    pub(crate) fn record_keep_prepass_rays(&mut self, rec: &mut Recorder<'_>) {
        self.record_copy_counter(rec, 8);
        self.prepass_rays_pending = true;
    }

    /// What a dispatch of the pass reads and writes: the parameters, the ray counter, the
    /// accumulation bound, the hybrid's plan (the lit pre-pass writes it) and surface depths, and
    /// the raster path's visibility.
    fn dispatch_uses(&self) -> [(vk::Buffer, Access); 6] {
        [
            (self.params.buffer, Access::Uniform),
            (self.counters.buffer, Access::ComputeWrite),
            (self.bound_accum, Access::ComputeWrite),
            (self.plan.buffer, Access::ComputeWrite),
            (self.surface_depth.buffer, Access::ComputeRead),
            (self.bound_visibility, Access::ComputeRead),
        ]
    }

    /// Records one dispatch of the blocks and samples `push` names, over an image `width`
    /// pixels wide, after what it reads was written.
    pub(crate) fn record_dispatch(&self, rec: &mut Recorder<'_>, push: TracePush, width: u32) {
        let groups = [width.div_ceil(GROUP), push.block_count, 1];
        rec.dispatch(
            self.pipeline_in_use(),
            bytemuck::bytes_of(&push),
            groups,
            &self.dispatch_uses(),
        );
    }

    /// Records the pipeline's first dispatch, one that traces nothing (its push names no blocks:
    /// every invocation leaves at once), between timestamps `query` and `query + 1`. A driver
    /// that compiles lazily (lavapipe's llvmpipe) compiles the shaders in a pipeline's first
    /// dispatch, half a minute on a device's first use: timed apart here, that stays out of the
    /// render's tracing time and rays per second (`Timings::compile_ms`).
    pub(super) fn record_compile(&self, rec: &mut Recorder<'_>, mode: u32, query: u32) {
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
        rec.timestamp(&self.timestamps, vk::PipelineStageFlags::TOP_OF_PIPE, query);
        rec.dispatch(
            self.pipeline_in_use(),
            bytemuck::bytes_of(&push),
            [1, 1, 1],
            &self.dispatch_uses(),
        );
        rec.timestamp(
            &self.timestamps,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            query + 1,
        );
    }

    /// Keeps the rays counted so far (the pipeline's first dispatch) in the counter's second
    /// word.
    pub(super) fn record_copy_first_rays(&self, rec: &mut Recorder<'_>) {
        self.record_copy_counter(rec, 4);
    }

    /// Copies the counter's word 0 (rays so far) to the byte offset `to` (4 or 8: the words do
    /// not overlap).
    fn record_copy_counter(&self, rec: &mut Recorder<'_>, to: u64) {
        let copy = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(to)
            .size(4);
        rec.copy_buffer(&self.counters, &self.counters, &[copy]);
    }

    /// Records one step: the band's sums in from film `film` first (`load`), then the
    /// estimator's dispatch (`batch`, with the raster path's pass before it) between
    /// timestamps `2 index` and `2 index + 1`, then the band's sums back to the film
    /// (`copy_out`).
    /// The dispatch covers the blocks of GROUP rows `block_first + i * block_stride`,
    /// i < block_count, of the band.
    pub(super) fn record_step(
        &self,
        rec: &mut Recorder<'_>,
        step: &Step,
        (film, width): (usize, u32),
        index: u32,
        batch: &dyn RecordSamples,
    ) {
        let band_sums = &self.accum.as_ref().expect("band buffer").buffer;
        let film = self.films.sums(film);
        let push = step.push;
        let band = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(u64::from(push.band_origin) * u64::from(width) * 16)
            .size(u64::from(push.band_height) * u64::from(width) * 16);
        if step.load {
            let up = vk::BufferCopy::default()
                .src_offset(band.dst_offset)
                .dst_offset(0)
                .size(band.size);
            rec.copy_buffer(film, band_sums, &[up]);
        }
        rec.timestamp(
            &self.timestamps,
            vk::PipelineStageFlags::TOP_OF_PIPE,
            2 * index,
        );
        batch.record(self, rec, push, width);
        rec.timestamp(
            &self.timestamps,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            2 * index + 1,
        );
        if let Some(bytes) = step.copy_out {
            rec.copy_buffer(band_sums, film, &[band.size(bytes)]);
        }
    }
}
