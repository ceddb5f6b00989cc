//! [`SampleBatch`]: the one recording of a batch of samples of a shot with an [`Estimator`],
//! into a command buffer someone else submits. Headless renders record it step by step through
//! the trace pass's `accumulate` (bands, timestamps, progress); the preview's frames record it
//! into their own command buffer. What each estimator records:
//! - traced: one trace dispatch (`TRACE_MODE_ALL`; adaptive sampling's rounds:
//!   `TRACE_MODE_ADAPTIVE`, `SampleBatch::adaptive`);
//! - raster: per sample, the visibility pass through that sample's lens point (every pixel shares
//!   the sample), then the dispatch that shades what each pixel sees (`TRACE_MODE_RASTER`);
//! - hybrid: once per plan, the lit pre-pass under lit shading and the plan pass from the
//!   G-buffer of the planning camera; then dispatches that follow the plan
//!   (`TRACE_MODE_HYBRID`).

use crate::core::error::GpuError;
use crate::core::recorder::Recorder;
use crate::passes::gbuffer::GBufferTargets;
use crate::passes::hybrid_plan::HybridPlanPass;
use crate::passes::trace::{RecordSamples, TracePipelines};
use crate::passes::visibility::VisibilityPass;
use crate::scene::SceneBuffers;
use crate::Estimator;
use lensray_core::camera::Camera;
use lensray_core::interface::{
    TracePush, TRACE_GROUP_SIZE, TRACE_MODE_ADAPTIVE, TRACE_MODE_ALL, TRACE_MODE_HYBRID,
    TRACE_MODE_RASTER, TRACE_MODE_SHORTCUT,
};
use lensray_core::settings::{RenderSettings, Shading, Shot};

/// A batch of samples of one shot with one estimator, borrowing the passes it records with.
pub(crate) struct SampleBatch<'r> {
    estimator: Estimator,
    /// The shot as traced: on the raster path every pixel shares each camera sample.
    shot: Shot,
    /// The camera whose raster the estimator reads (`Camera::for_rasterizing_rays`): the raster
    /// path's visibility and the hybrid's G-buffer; `None` on the traced path.
    raster_camera: Option<Camera>,
    /// The visibility pass (the raster path's, and the hybrid's lit pre-pass).
    visibility: Option<&'r VisibilityPass>,
    scene: &'r SceneBuffers,
    /// The traced estimator in adaptive sampling's mode: each pixel from its own count, as
    /// the plan buffer's entries say (`renderer::adaptive`).
    adaptive: bool,
}

impl<'r> SampleBatch<'r> {
    /// The batch of `shot` with `estimator`; the raster path needs the visibility pass
    /// (`GpuRenderer::prepare_raster`).
    pub(crate) fn new(
        estimator: Estimator,
        shot: &Shot,
        visibility: Option<&'r VisibilityPass>,
        scene: &'r SceneBuffers,
    ) -> Result<Self, GpuError> {
        if estimator == Estimator::Raster && visibility.is_none() {
            return Err(GpuError::Invalid(
                "the raster path's visibility pass is not prepared".into(),
            ));
        }
        let shot = Shot {
            camera: shot.camera.clone(),
            render: RenderSettings {
                shared_samples: estimator == Estimator::Raster || shot.render.shared_samples,
                ..shot.render
            },
        };
        let raster_camera =
            (estimator != Estimator::Traced).then(|| shot.camera.for_rasterizing_rays());
        Ok(Self {
            estimator,
            shot,
            raster_camera,
            visibility,
            scene,
            adaptive: false,
        })
    }

    /// The batch in adaptive sampling's mode (`TRACE_MODE_ADAPTIVE`); only the traced
    /// estimator has it.
    pub(crate) fn adaptive(self) -> Result<Self, GpuError> {
        if self.estimator != Estimator::Traced {
            return Err(GpuError::Invalid(format!(
                "the {:?} estimator does not sample adaptively",
                self.estimator
            )));
        }
        Ok(Self {
            adaptive: true,
            ..self
        })
    }

    /// The shot as traced (the trace parameters are made from it).
    pub(crate) fn shot(&self) -> &Shot {
        &self.shot
    }

    /// The camera the G-buffer is drawn with: the hybrid's planning camera (same rays and
    /// pixels, the raster's clipping planes moved out), else the shot's.
    pub(crate) fn gbuffer_camera(&self) -> &Camera {
        match (self.estimator, &self.raster_camera) {
            (Estimator::Hybrid, Some(planning)) => planning,
            _ => &self.shot.camera,
        }
    }

    /// Records the hybrid's plan of `target_spp` samples into the trace pass's plan buffer,
    /// from `targets`, the G-buffer of [`Self::gbuffer_camera`] drawn before it; lit, after the
    /// pre-pass (`record_lit_prepass`). The trace parameters of [`Self::shot`] are recorded
    /// before it.
    pub(crate) fn record_plan(
        &self,
        (trace, plan): (&TracePipelines, &HybridPlanPass),
        rec: &mut Recorder<'_>,
        targets: &GBufferTargets,
        target_spp: u32,
    ) -> Result<(), GpuError> {
        let camera = &self.shot.camera;
        if self.shot.render.shading == Shading::Lit {
            self.record_lit_prepass(trace, rec)?;
        }
        plan.record(rec, targets, camera, self.shot.render.shading, target_spp);
        Ok(())
    }

    /// Records the hybrid's lit pre-pass: the visibility pass along each pixel's aperture-centre
    /// ray, then one dispatch over the image (TRACE_MODE_SHORTCUT: each pixel's shortcut value
    /// and shadow state into the plan buffer, which must hold the image), in which the plan's
    /// steps order themselves after it. The trace parameters of [`Self::shot`] are recorded
    /// before it.
    pub(crate) fn record_lit_prepass(
        &self,
        trace: &TracePipelines,
        rec: &mut Recorder<'_>,
    ) -> Result<(), GpuError> {
        let visibility = self.visibility.ok_or_else(|| {
            GpuError::Invalid("the lit pre-pass's visibility pass is not prepared".into())
        })?;
        let camera = &self.shot.camera;
        visibility.record_aperture_centre(rec, self.scene, camera);
        let push = TracePush {
            band_origin: 0,
            band_height: camera.height,
            block_first: 0,
            block_stride: 1,
            block_count: camera.height.div_ceil(TRACE_GROUP_SIZE),
            sample_begin: 0,
            sample_end: 0,
            mode: TRACE_MODE_SHORTCUT,
        };
        trace.record_dispatch(rec, push, camera.width);
        Ok(())
    }
}

impl RecordSamples for SampleBatch<'_> {
    fn mode(&self) -> u32 {
        match self.estimator {
            Estimator::Traced if self.adaptive => TRACE_MODE_ADAPTIVE,
            Estimator::Traced => TRACE_MODE_ALL,
            Estimator::Raster => TRACE_MODE_RASTER,
            Estimator::Hybrid => TRACE_MODE_HYBRID,
        }
    }

    fn record(&self, trace: &TracePipelines, rec: &mut Recorder<'_>, push: TracePush, width: u32) {
        let push = TracePush {
            mode: self.mode(),
            ..push
        };
        let raster = self.visibility.zip(self.raster_camera.as_ref());
        let Some((visibility, camera)) = raster.filter(|_| self.estimator == Estimator::Raster)
        else {
            trace.record_dispatch(rec, push, width);
            return;
        };
        for sample in push.sample_begin..push.sample_end {
            // A sample whose rows are split over several dispatches (the preview's frames) is
            // rasterized with its first group (group 0); the later groups read that visibility
            // (the queue keeps them in order, and nothing else writes it until the next sample).
            if push.block_first == 0 {
                visibility.record_sample(rec, self.scene, camera, &self.shot.render, sample);
            }
            let one = TracePush {
                sample_begin: sample,
                sample_end: sample + 1,
                ..push
            };
            trace.record_dispatch(rec, one, width);
        }
    }
}
