//! The renderer's entry of the traced path: `accumulate` plans a call's steps, records and
//! submits them in batches without waiting, reports progress from the device's timeline, and
//! keeps the band of sums the shader adds to.

use std::ops::Range;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::steps::Step;
use super::{Timings, TracePass};
use crate::core::buffer::Buffer;
use crate::core::error::GpuError;
use crate::core::recorder::Recorder;
use crate::passes::films::Start;
use lensray_core::film::{Accumulation, Progress};
use lensray_core::interface::{TraceParams, TracePush, TRACE_MODE_HYBRID, TRACE_MODE_RASTER};
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
        self.check_plan(pixels, mode)?;
        let band_rows = self.ensure_accumulation(width, height)?;
        self.ensure_camera_tables(camera)?;
        let (film, start) = self.films.take(accumulation)?;
        self.films.prepare_finish(film)?;
        // The parameters go up in the first submission (a pending one may still read them).
        let params = crate::upload::trace_params(shot);

        let raster = mode == TRACE_MODE_RASTER;
        let steps = self.plan_steps(width, height, band_rows, &samples, mode, raster);
        let total: u64 = steps.iter().map(|s| s.work).sum();
        progress(0, total);
        // Two timestamps per step, and two for the pipeline's empty first dispatch.
        self.ensure_timestamps(2 * steps.len() as u32 + 2)?;

        let first_dispatch = !self.pipelines[self.current].first_dispatch_done;
        let batches =
            self.submit_steps(&steps, &params, (film, start), width, first_dispatch, batch)?;
        self.wait_reporting(&batches, total, progress)?;
        self.films.finished(film);
        self.record_timings(&steps, first_dispatch, timings)
    }

    /// An error when the shader's `mode` cannot run on an image of `pixels` pixels: the
    /// hybrid's needs a plan covering the image.
    fn check_plan(&self, pixels: u64, mode: u32) -> Result<(), GpuError> {
        match self.plan_pixels {
            _ if mode != TRACE_MODE_HYBRID => Ok(()),
            Some(n) if n == pixels => Ok(()),
            Some(n) => Err(GpuError::Invalid(format!(
                "the hybrid plan has {n} pixels, the image {pixels}"
            ))),
            None => Err(GpuError::Invalid("the hybrid's plan is not made".into())),
        }
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
                    self.record_clear_ray_counter(rec);
                    self.films.record_start(rec, film, start);
                    if first_dispatch {
                        self.record_compile(rec, batch.mode(), 2 * steps.len() as u32);
                    }
                }
                for (i, step) in chunk.iter().enumerate() {
                    let index = (first + i) as u32;
                    self.record_step(rec, step, (film, width), index, batch);
                    if index == 0 && first_dispatch {
                        // The pipeline's first dispatch is reported apart: its rays too.
                        self.record_copy_first_rays(rec);
                    }
                }
                if first + chunk.len() == steps.len() {
                    let transfer = self.films.record_finish(rec, film);
                    rec.read_on_host(&[transfer, &self.counters]);
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

    /// The band buffer for a `width` x `height` image (made anew, and bound, when the size
    /// changes), and the rows of a band. The shader adds to a storage buffer covering a band of
    /// rows, bounded by the device's storage-buffer range (128 MiB on lavapipe); each band is
    /// copied in from the film and back.
    pub(crate) fn ensure_accumulation(&mut self, width: u32, height: u32) -> Result<u32, GpuError> {
        let max_band_pixels = (u64::from(self.ctx.report.max_storage_buffer_range) / 16)
            .min(self.max_band_pixels)
            .max(u64::from(width));
        let band_rows = (max_band_pixels / u64::from(width)).clamp(1, u64::from(height)) as u32;
        let bytes = u64::from(band_rows) * u64::from(width) * 16;
        if self.accum.as_ref().is_none_or(|a| a.bytes != bytes) {
            // A pending submission (the hybrid's plan) binds the old buffer: it finishes first.
            self.ctx.wait_all()?;
            self.accum = None;
            let buffer = Buffer::new(
                &self.ctx,
                "trace band sums",
                bytes,
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )?;
            self.bind_accum_buffer(&buffer);
            self.accum = Some(BandSums { buffer, bytes });
        }
        Ok(band_rows)
    }
}

/// What records an estimator's dispatches into the steps of `accumulate`: the renderer's
/// `SampleBatch`, the one recording of a batch of samples, which the preview's frames use too.
pub(crate) trait RecordSamples {
    /// The shader's mode (`TRACE_MODE_*`) of the dispatches.
    fn mode(&self) -> u32;
    /// Records the blocks and samples `push` names (its mode replaced by [`Self::mode`]) over
    /// an image `width` pixels wide with `trace`, each dispatch after what the estimator
    /// records before it (the raster path: its sample's raster pass).
    fn record(&self, trace: &TracePass, rec: &mut Recorder<'_>, push: TracePush, width: u32);
}

/// The sums of one band of rows.
pub(super) struct BandSums {
    pub(super) buffer: Buffer,
    pub(super) bytes: u64,
}
