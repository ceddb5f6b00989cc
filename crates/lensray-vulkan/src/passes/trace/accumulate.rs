//! The renderer's entry of the traced path: `accumulate` plans a call's steps, records and
//! submits them in batches without waiting, and reports progress from the device's timeline.
//! Each step records its band's copies from and to the film around the estimator's dispatch.

use std::ops::Range;

use ash::vk;

use super::pipelines::TracePipelines;
use super::steps::Step;
use super::{Timings, TracePass};
use crate::core::error::GpuError;
use crate::core::recorder::Recorder;
use crate::passes::films::Start;
use lensray_core::film::{Accumulation, Progress};
use lensray_core::interface::{TraceParams, TracePush, TRACE_MODE_RASTER};
use lensray_core::settings::Shot;

/// Steps (dispatches) recorded per command buffer: each submission signals the timeline, whose
/// value the progress reads; none is waited for until the last.
const STEPS_PER_SUBMIT: usize = 8;
/// How often the progress reads the timeline while a render runs.
const PROGRESS_POLL: std::time::Duration = std::time::Duration::from_millis(2);

impl TracePass {
    /// Adds samples `samples` of every pixel of `shot` to `accumulation` (of the camera's size),
    /// with the scene last bound by `bind_scene`. The sums stay on the device (`films`); the
    /// shader adds sample after sample to them, so any split of a range gives the same sums.
    pub(crate) fn accumulate(
        &mut self,
        shot: &Shot,
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        timings: &mut Timings,
        batch: &dyn RecordSamples,
        progress: &mut Progress,
    ) -> Result<(), GpuError> {
        let camera = &shot.camera;
        let (width, height) = (camera.width, camera.height);
        let pixels = u64::from(width) * u64::from(height);
        if (accumulation.width, accumulation.height) != (width, height) {
            return Err(GpuError::Invalid(format!(
                "accumulation {}x{} does not match the {width}x{height} image",
                accumulation.width, accumulation.height
            )));
        }
        if samples.is_empty() {
            return Ok(());
        }
        let mode = batch.mode();
        self.plan.check(pixels, mode)?;
        let band_rows = self.ensure_accumulation(width, height)?;
        self.ensure_camera_tables(camera)?;
        let (film, start) = self.films.take(accumulation)?;
        self.films.prepare_finish(film)?;
        // The parameters go up in the first submission (a pending one may still read them).
        let params = crate::upload::trace_params(shot);

        let raster = mode == TRACE_MODE_RASTER;
        let steps = self
            .sizing
            .steps(width, height, band_rows, &samples, mode, raster);
        let total: u64 = steps.iter().map(|s| s.work).sum();
        progress(0, total);
        // Two timestamps per step, and two for the pipeline's empty first dispatch.
        self.ensure_timestamps(2 * steps.len() as u32 + 2)?;

        let first_dispatch = !self.pipelines.first_dispatch_done();
        let batches =
            self.submit_steps(&steps, &params, (film, start), width, first_dispatch, batch)?;
        self.wait_reporting(&batches, total, progress)?;
        self.films.finished(film);
        self.record_timings(&steps, first_dispatch, timings)
    }

    /// Records and submits every step before any wait: batches of steps per command buffer,
    /// each signalling the device's timeline, which the progress reads. Returns each batch's
    /// timeline value and pixel-samples.
    fn submit_steps(
        &self,
        steps: &[Step],
        params: &TraceParams,
        (film, start): (usize, Start),
        width: u32,
        first_dispatch: bool,
        batch: &dyn RecordSamples,
    ) -> Result<Vec<(u64, u64)>, GpuError> {
        let mut batches = Vec::new();
        for (submission, chunk) in steps.chunks(STEPS_PER_SUBMIT).enumerate() {
            let first = submission * STEPS_PER_SUBMIT;
            let value = self.ctx.submit(|rec| {
                if first == 0 {
                    rec.reset_queries(&self.timestamps);
                    self.record_params(rec, params);
                    self.rays.record_clear(rec);
                    self.films.record_start(rec, film, start);
                    if first_dispatch {
                        let query = 2 * steps.len() as u32;
                        let timestamps = (&self.timestamps, query);
                        self.pipelines.record_compile(rec, batch.mode(), timestamps);
                    }
                }
                for (i, step) in chunk.iter().enumerate() {
                    let index = (first + i) as u32;
                    self.record_step(rec, step, (film, width), index, batch);
                    if index == 0 && first_dispatch {
                        // The pipeline's first dispatch is reported apart: its rays too.
                        self.rays.record_copy_first(rec);
                    }
                }
                if first + chunk.len() == steps.len() {
                    let transfer = self.films.record_finish(rec, film);
                    rec.read_on_host(&[transfer, self.rays.buffer()]);
                }
                Ok(())
            })?;
            let work: u64 = chunk.iter().map(|s| s.work).sum();
            batches.push((value, work));
        }
        Ok(batches)
    }

    /// Reports the progress of `batches` (timeline value, pixel-samples) as the device
    /// completes them, then waits for the last one.
    fn wait_reporting(
        &self,
        batches: &[(u64, u64)],
        total: u64,
        progress: &mut Progress,
    ) -> Result<(), GpuError> {
        let last = batches.last().map_or(0, |b| b.0);
        let mut reported = 0;
        loop {
            let completed = self.ctx.completed()?;
            let done: u64 = batches
                .iter()
                .filter(|(value, _)| *value <= completed)
                .map(|(_, work)| work)
                .sum();
            if done > reported {
                reported = done;
                progress(done, total);
            }
            // One batch has no progress to show before its end.
            if completed >= last || batches.len() <= 1 {
                break;
            }
            std::thread::sleep(PROGRESS_POLL);
        }
        self.ctx.wait_until(last)?;
        if reported < total {
            progress(total, total);
        }
        Ok(())
    }

    /// Records one step: the band's sums in from film `film` first (`load`), then the
    /// estimator's dispatch (`batch`, with the raster path's pass before it) between
    /// timestamps `2 index` and `2 index + 1`, then the band's sums back to the film
    /// (`copy_out`).
    /// The dispatch covers the blocks of GROUP rows `block_first + i * block_stride`,
    /// i < block_count, of the band.
    fn record_step(
        &self,
        rec: &mut Recorder<'_>,
        step: &Step,
        (film, width): (usize, u32),
        index: u32,
        batch: &dyn RecordSamples,
    ) {
        let push = step.push;
        let band = (push.band_origin, push.band_height);
        let copy = self.films.band_copy(film, band, width);
        if step.load {
            copy.record_in(rec);
        }
        let stamps = &self.timestamps;
        rec.timestamp(stamps, vk::PipelineStageFlags::TOP_OF_PIPE, 2 * index);
        batch.record(&self.pipelines, rec, push, width);
        rec.timestamp(
            stamps,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            2 * index + 1,
        );
        if let Some(bytes) = step.copy_out {
            copy.record_out(rec, bytes);
        }
    }
}

/// What records an estimator's dispatches into the steps of `accumulate`: the renderer's
/// `SampleBatch`, the one recording of a batch of samples, which the preview's frames use too.
pub(crate) trait RecordSamples {
    /// The shader's mode (`TRACE_MODE_*`) of the dispatches.
    fn mode(&self) -> u32;
    /// Records the blocks and samples `push` names (its mode replaced by [`Self::mode`]) over
    /// an image `width` pixels wide with `pipelines`, each dispatch after what the estimator
    /// records before it (the raster path: its sample's raster pass).
    fn record(
        &self,
        pipelines: &TracePipelines,
        rec: &mut Recorder<'_>,
        push: TracePush,
        width: u32,
    );
}
