//! The renderer's entry of the traced path: `accumulate` plans a call's steps as it goes,
//! records and submits them in batches, a few batches in flight, and reports progress and
//! takes each batch's timestamps from the device's timeline as batches finish: the dispatches
//! still to plan are sized by the speed measured so far, so a sample pass costs the host a
//! few dispatches whatever the image's size. Only the last batch is waited for.
//! Each step records its band's copies from and to the film around the estimator's dispatch.

use std::ops::Range;

use ash::vk;

use super::pipelines::TracePipelines;
use super::steps::{Step, StepPlan};
use super::{Timings, TracePass};
use crate::core::error::GpuError;
use crate::core::recorder::Recorder;
use crate::passes::films::Start;
use lensray_core::film::{Accumulation, Progress};
use lensray_core::interface::{TraceParams, TracePush, TRACE_MODE_RASTER};
use lensray_core::settings::Shot;

/// Steps (dispatches) recorded per command buffer: each submission signals the timeline, whose
/// value the progress reads.
const STEPS_PER_SUBMIT: usize = 8;
/// Submissions pending at once: the host plans the next ones once earlier ones finish, with
/// the speed they measured, and keeps the device busy meanwhile.
const IN_FLIGHT: usize = 4;
/// How often the host reads the timeline while a render runs.
const PROGRESS_POLL: std::time::Duration = std::time::Duration::from_millis(2);
/// Timestamps 0 and 1 time the pipeline's empty first dispatch; step `i` writes `2 + 2 i` and
/// `3 + 2 i`.
pub(super) const FIRST_STEP_QUERY: u32 = 2;

/// One submitted batch of steps: its timeline value and its steps' indices.
pub(super) struct Batch {
    pub(super) value: u64,
    pub(super) steps: Range<usize>,
}

/// What one `accumulate` call has submitted and taken back so far.
pub(super) struct Submitted {
    pub(super) steps: Vec<Step>,
    pub(super) batches: Vec<Batch>,
    /// Batches whose timestamps are taken (they finished), and their pixel-samples.
    pub(super) finished: usize,
    pub(super) done: u64,
    /// Pixel-samples reported to the progress, and the call's total.
    reported: u64,
    total: u64,
    pub(super) first_dispatch: bool,
}

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
        let mut plan = StepPlan::new((width, height), band_rows, samples, mode, raster);
        // Within a call the dispatches only grow: the timestamp pool holds the steps of the
        // call's first size.
        let floor = self.sizing.budget();
        let most_steps = plan.count(floor) as u32;
        self.ensure_timestamps(FIRST_STEP_QUERY + 2 * most_steps)?;
        let mut submitted = Submitted {
            steps: Vec::new(),
            batches: Vec::new(),
            finished: 0,
            done: 0,
            reported: 0,
            total: plan.work(),
            first_dispatch: !self.pipelines.first_dispatch_done(),
        };
        progress(0, submitted.total);
        while !plan.is_done() {
            self.poll(&mut submitted, IN_FLIGHT - 1, timings, progress)?;
            let first = submitted.steps.len();
            let budget = self.sizing.budget().max(floor);
            submitted
                .steps
                .extend(std::iter::from_fn(|| plan.next(budget)).take(STEPS_PER_SUBMIT));
            let last = plan.is_done();
            let value = self.submit_batch(
                &submitted,
                first,
                last,
                &params,
                (film, start),
                width,
                batch,
            )?;
            let steps = first..submitted.steps.len();
            submitted.batches.push(Batch { value, steps });
        }
        self.poll(&mut submitted, 1, timings, progress)?;
        let last = submitted.batches.last().map_or(0, |b| b.value);
        self.ctx.wait_until(last)?;
        self.take_timings(&mut submitted, last, timings)?;
        if submitted.reported < submitted.total {
            progress(submitted.total, submitted.total);
        }
        self.films.finished(film);
        self.finish_timings(submitted.first_dispatch, timings)
    }

    /// Reads the timeline until at most `pending` batches are unfinished, taking the finished
    /// ones' timestamps and reporting their progress.
    fn poll(
        &mut self,
        submitted: &mut Submitted,
        pending: usize,
        timings: &mut Timings,
        progress: &mut Progress,
    ) -> Result<(), GpuError> {
        loop {
            let completed = self.ctx.completed()?;
            self.take_timings(submitted, completed, timings)?;
            if submitted.done > submitted.reported {
                submitted.reported = submitted.done;
                progress(submitted.done, submitted.total);
            }
            if submitted.batches.len() - submitted.finished <= pending {
                return Ok(());
            }
            std::thread::sleep(PROGRESS_POLL);
        }
    }

    /// Records and submits the steps of `submitted` from `first` on as one batch: the call's
    /// set-up at the head of the first, the film's copy out at the end of the `last`.
    #[expect(
        clippy::too_many_arguments,
        reason = "one batch of one call's recording"
    )]
    fn submit_batch(
        &self,
        submitted: &Submitted,
        first: usize,
        last: bool,
        params: &TraceParams,
        (film, start): (usize, Start),
        width: u32,
        batch: &dyn RecordSamples,
    ) -> Result<u64, GpuError> {
        let first_dispatch = submitted.first_dispatch;
        self.ctx.submit(|rec| {
            if first == 0 {
                rec.reset_queries(&self.timestamps);
                self.record_params(rec, params);
                self.rays.record_clear(rec);
                self.films.record_start(rec, film, start);
                if first_dispatch {
                    self.pipelines
                        .record_compile(rec, batch.mode(), (&self.timestamps, 0));
                }
            }
            for (index, step) in submitted.steps.iter().enumerate().skip(first) {
                self.record_step(rec, step, (film, width), index as u32, batch);
                if index == 0 && first_dispatch {
                    // The pipeline's first dispatch is reported apart: its rays too.
                    self.rays.record_copy_first(rec);
                }
            }
            if last {
                let transfer = self.films.record_finish(rec, film);
                let counts = self.rays.record_read_back(rec);
                rec.read_on_host(&[transfer, counts]);
            }
            Ok(())
        })
    }

    /// Records one step: the band's sums in from film `film` first (`load`), then the
    /// estimator's dispatch (`batch`, with the raster path's pass before it) between the
    /// step's two timestamps, then the band's sums back to the film
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
        let query = FIRST_STEP_QUERY + 2 * index;
        rec.timestamp(stamps, vk::PipelineStageFlags::TOP_OF_PIPE, query);
        batch.record(&self.pipelines, rec, push, width);
        rec.timestamp(stamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, query + 1);
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
