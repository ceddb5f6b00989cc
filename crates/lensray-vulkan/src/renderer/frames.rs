//! What the preview's frames ask of the renderer: the passes and bindings for frames of a size
//! and an estimator, and the recording of a frame's G-buffer, trace parameters, hybrid plan and
//! samples into the frame's own command buffer. Samples are recorded by [`SampleBatch`], as a
//! headless render records them; the preview decides only which samples a frame adds.

use std::sync::Arc;

use super::batch::SampleBatch;
use super::GpuRenderer;
use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::query::QueryPool;
use crate::core::recorder::Recorder;
use crate::passes::gbuffer::GBufferTargets;
use crate::passes::trace::RecordSamples;
use crate::scene::SceneBuffers;
use crate::Estimator;
use lensray_core::camera::Camera;
use lensray_core::interface::TracePush;
use lensray_core::settings::Shot;

impl GpuRenderer {
    /// The device context (the window's objects are made with it).
    pub(crate) fn ctx(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// The loaded scene on the device.
    pub(crate) fn scene_buffers(&self) -> Result<&SceneBuffers, GpuError> {
        self.scene.as_ref().ok_or(GpuError::NoScene)
    }

    /// The G-buffer's images, once `prepare_frames` made them.
    pub(crate) fn gbuffer_targets(&self) -> Result<&GBufferTargets, GpuError> {
        self.raster.gbuffer_targets().ok_or_else(not_prepared)
    }

    /// Makes what frames of `width` x `height` adding samples with `estimator` to
    /// `accumulation` (one sum per pixel) need: the trace pass bound to the accumulation, the
    /// raster path's visibility pass (which the hybrid's lit pre-pass uses too: the shading can
    /// turn lit at any frame), the hybrid's plan (`prepare_hybrid_plan`) and the G-buffer's
    /// images, which it returns. No frame may be in flight.
    pub(crate) fn prepare_frames(
        &mut self,
        (width, height): (u32, u32),
        estimator: Estimator,
        accumulation: &Buffer,
    ) -> Result<&GBufferTargets, GpuError> {
        self.trace.bind_accumulation(accumulation);
        if estimator != Estimator::Traced {
            self.prepare_raster(width, height)?;
        }
        if estimator == Estimator::Hybrid {
            self.prepare_hybrid_plan(width, height)?;
        }
        let gbuffer = self.raster.gbuffer_pass(self.scene.as_ref())?;
        gbuffer.ensure_targets(width, height)
    }

    /// Whether `camera`'s aperture and lens tables differ from those bound (frames in flight
    /// read the bound ones).
    pub(crate) fn camera_tables_differ(&self, camera: &Camera) -> bool {
        self.trace.tables.differ(camera)
    }

    /// Binds `camera`'s aperture and lens tables (no frame reading the old ones in flight).
    pub(crate) fn ensure_camera_tables(&mut self, camera: &Camera) -> Result<(), GpuError> {
        self.trace.ensure_camera_tables(camera)
    }

    /// The batch of `shot`'s samples with `estimator` that frames record.
    pub(crate) fn sample_batch(
        &self,
        shot: &Shot,
        estimator: Estimator,
    ) -> Result<SampleBatch<'_>, GpuError> {
        SampleBatch::new(
            estimator,
            shot,
            self.raster.visibility(),
            self.scene_buffers()?,
        )
    }

    /// Records the G-buffer of `batch`'s G-buffer camera, its timestamps at `timestamps`.
    pub(crate) fn record_gbuffer(
        &self,
        rec: &mut Recorder<'_>,
        batch: &SampleBatch<'_>,
        timestamps: (&QueryPool, u32),
    ) -> Result<(), GpuError> {
        let gbuffer = self.raster.gbuffer().ok_or_else(not_prepared)?;
        let scene = self.scene_buffers()?;
        let background = batch.shot().render.background;
        gbuffer.record(
            rec,
            scene,
            batch.gbuffer_camera(),
            background,
            Some(timestamps),
        );
        Ok(())
    }

    /// Records the trace parameters of `batch`'s shot (ordered between earlier and later
    /// dispatches).
    pub(crate) fn record_trace_params(&self, rec: &mut Recorder<'_>, batch: &SampleBatch<'_>) {
        let params = crate::upload::trace_params(batch.shot());
        self.trace.record_params(rec, &params);
    }

    /// Records the hybrid's plan of `target_spp` samples from the G-buffer recorded before it
    /// (`SampleBatch::record_plan`).
    pub(crate) fn record_plan(
        &self,
        rec: &mut Recorder<'_>,
        batch: &SampleBatch<'_>,
        target_spp: u32,
    ) -> Result<(), GpuError> {
        let passes = self.raster.plan_passes().map_err(|_| not_prepared())?;
        let pipelines = &self.trace.pipelines;
        batch.record_plan((pipelines, passes.plan), rec, passes.targets, target_spp)
    }

    /// Records the blocks and samples `push` names over the whole image (`SampleBatch`).
    pub(crate) fn record_samples(
        &self,
        rec: &mut Recorder<'_>,
        batch: &SampleBatch<'_>,
        push: TracePush,
    ) {
        batch.record(&self.trace.pipelines, rec, push, batch.shot().camera.width);
    }
}

fn not_prepared() -> GpuError {
    GpuError::Invalid("the preview's frames are not prepared (prepare_frames)".into())
}
