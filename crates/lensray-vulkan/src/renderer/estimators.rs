//! How the renderer adds samples to an accumulation: [`GpuRenderer::add_samples`] with an
//! [`Estimator`], the one entry the app's render paths and `auto`'s timing call. What each
//! estimator records is `SampleBatch`'s (`batch`): traced (the trace pass alone), raster (the
//! visibility pass through each shared lens sample, then the trace pass's shading) and hybrid
//! (the plan made on the device from the G-buffer, then the trace pass following it).
//!
//! The hybrid (docs/hybrid.md): the raster G-buffer decides where rays are needed. Per call of
//! `add_samples`, one submission on the device (`GpuRenderer::plan_on_device`): the G-buffer of
//! the shot, the lit pre-pass under lit shading, then the plan pass (`passes::hybrid_plan`,
//! shaders/passes/hybrid_plan.comp: circle of confusion from the G-buffer depth, maximum over
//! 8x8 tiles, dilated by each tile's maximum over the tiles it reaches; edge marks in a
//! summed-area table; one entry per pixel) written straight into the trace pass's plan buffer,
//! with no readback; then the trace pass in its hybrid mode (shaders/passes/trace.comp) with the
//! device's fastest traversal. Per pixel:
//! - no G-buffer edge within the pixel's dilated CoC (at least one pixel; so in particular a
//!   dilated CoC under half a pixel with a uniform neighbourhood; lit, a shadow boundary found
//!   by the lit pre-pass counts as an edge): the *shortcut*. Unlit its value is the G-buffer's
//!   albedo; lit, per sample, the pre-pass's image (each pixel's surface shaded along its
//!   aperture-centre ray, with one shadow ray) interpolated where the sample's lens ray meets
//!   the pixel's surface depth. Each sample is traced too with probability
//!   1 / HYBRID_CHECK_INVERSE (a hash of the 8x8 tile and the sample) and adds
//!   (traced - shortcut) * HYBRID_CHECK_INVERSE: unbiased;
//! - otherwise every sample is traced. So the samples a pixel costs grow with its dilated CoC
//!   through the window it must see uniform: from the shortcut's checks (spp / 32) to spp. (A
//!   plan entry may stop a pixel's count at `n` < spp; fewer samples where the CoC is small
//!   measured worse at equal error, docs/hybrid.md, so the plan does not);
//! - the 8 pixels of a tile row share one decision (they run in lockstep).
//!
//! The probe `probes::hybrid_plan` holds the same rules on the host: its `Plan::new` is the
//! reference the device plan is checked against (tests/hybrid.rs). A render reads none of the
//! plan back (the probes copy it out).
//!
//! Whether a pixel traces sample `i` depends on the plan (camera, settings, scene) only, never on
//! the range asked for, so any split of a range gives the same sums, as for every path.

use std::time::Instant;

use lensray_core::film::{Accumulation, Progress};
use lensray_core::settings::{Shading, Shot};

use super::batch::SampleBatch;
use super::raster::PlanPasses;
use super::{check_samples, check_size, GpuRenderer};
use crate::core::error::GpuError;
use crate::Estimator;

/// What adding a batch of samples cost besides the trace pass's GPU timestamps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SamplesAdded {
    /// Wall-clock seconds of the hybrid's plan (G-buffer draw and plan pass on the device).
    pub plan_seconds: f64,
}

impl GpuRenderer {
    /// Adds samples `samples` of every pixel of `shot` (`Unlit` or `Lit`) to `accumulation`,
    /// which has the camera's size, with `estimator`. The sums stay on the device until
    /// [`read_sums`](Self::read_sums): continuing a render uploads and reads back nothing.
    /// `progress(done, total)` counts pixel-samples.
    pub fn add_samples(
        &mut self,
        shot: &Shot,
        estimator: Estimator,
        samples: std::ops::Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<SamplesAdded, GpuError> {
        check_samples(shot)?;
        if self.scene.is_none() {
            return Err(GpuError::NoScene);
        }
        let mut added = SamplesAdded::default();
        match estimator {
            Estimator::Traced => {}
            // Accumulation-buffer depth of field (docs/raster.md): each sample is one camera
            // sample shared by every pixel, rasterized through its lens point
            // (`Camera::clip_from_world_through_lens`); the shading pass shades what each pixel
            // sees along its lens ray (lit: with a shadow ray of the traversal in use).
            Estimator::Raster => {
                self.prepare_raster(shot.camera.width, shot.camera.height)?;
            }
            Estimator::Hybrid => {
                let start = Instant::now();
                self.plan_on_device(shot)?;
                added.plan_seconds = start.elapsed().as_secs_f64();
            }
        }
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let batch = SampleBatch::new(estimator, shot, self.raster.visibility(), scene)?;
        let traced = self.trace.accumulate(
            batch.shot(),
            samples,
            accumulation,
            &mut self.timings,
            &batch,
            progress,
        );
        if estimator == Estimator::Hybrid {
            self.trace.plan.clear();
        }
        traced.map(|()| added)
    }

    /// Makes the raster path's visibility pass (on first use) and its targets for a `width` x
    /// `height` image, bound to the trace pass (the hybrid's lit pre-pass uses it too).
    pub(crate) fn prepare_raster(&mut self, width: u32, height: u32) -> Result<(), GpuError> {
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        self.raster
            .prepare_visibility(scene, &mut self.trace, (width, height))
    }

    /// Makes the hybrid's plan pass (on first use: only the hybrid path compiles its pipeline),
    /// the G-buffer's targets and the trace pass's plan buffers for a `width` x `height` image,
    /// bound together: the one set-up of the plan, the render path's and the preview's.
    pub(crate) fn prepare_hybrid_plan(&mut self, width: u32, height: u32) -> Result<(), GpuError> {
        let scene = self.scene.as_ref();
        self.raster
            .prepare_hybrid_plan(scene, &mut self.trace, (width, height))
    }

    /// The hybrid path's plan of `shot` made on the device (shaders/passes/hybrid_plan.comp) for
    /// later `accumulate` calls: one submission draws the G-buffer of the planning camera
    /// (`SampleBatch::gbuffer_camera`), lit runs the pre-pass (each pixel's shortcut value and
    /// shadow state), and plans the shot's spp samples seen by its camera from them. Nothing is
    /// read back (the plan's probes can).
    pub(crate) fn plan_on_device(&mut self, shot: &Shot) -> Result<(), GpuError> {
        let (camera, settings) = (&shot.camera, &shot.render);
        check_size(camera)?;
        let lit = settings.shading == Shading::Lit;
        if lit {
            self.prepare_raster(camera.width, camera.height)?;
        }
        let (width, height) = (camera.width, camera.height);
        self.prepare_hybrid_plan(width, height)?;
        // The render's buffers now, while nothing is pending: the plan is not waited for.
        self.trace.ensure_accumulation(width, height)?;
        self.trace.ensure_camera_tables(camera)?;
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let batch = SampleBatch::new(Estimator::Hybrid, shot, self.raster.visibility(), scene)?;
        let PlanPasses {
            gbuffer,
            targets,
            plan,
        } = self.raster.plan_passes()?;
        let trace = &mut self.trace;
        // Not waited for: the render's submissions follow on the queue, and the pre-pass's
        // rays reach the render's report through the counter (`RayCounter::record_keep_prepass`).
        self.ctx.submit(|rec| {
            let planning = batch.gbuffer_camera();
            gbuffer.record(rec, scene, planning, settings.background, None);
            if lit {
                trace.record_params(rec, &crate::upload::trace_params(batch.shot()));
                trace.rays.record_clear(rec);
            }
            batch.record_plan((&trace.pipelines, plan), rec, targets, settings.spp)?;
            if lit {
                trace.rays.record_keep_prepass(rec);
            }
            Ok(())
        })?;
        self.timings.gbuffer_passes += 1;
        self.trace
            .plan
            .use_device_plan(u64::from(width) * u64::from(height));
        Ok(())
    }
}
