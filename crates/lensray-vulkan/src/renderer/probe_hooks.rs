//! The hooks the probes (feature `probes`: tests and benchmarks) reach into the renderer
//! through: knobs that force bands and submissions, the GLSL mirrors, the shared layouts, the
//! preview's view routes, the sampler's cost, and the hybrid plan's inputs and entries.

use glam::Vec3;

use super::batch::SampleBatch;
use super::{check_size, GpuRenderer};
use crate::probes::layouts::{self, LayoutReport};
use crate::probes::mirrors::{self, ProbeQuery, ProbeResult};
use crate::probes::sampler_cost;
use crate::probes::view_routes::{self, ViewRoutes};
use crate::scene::bvh::BvhParams;
use crate::{Estimator, GpuError};
use lensray_core::camera::Camera;
use lensray_core::settings::Shot;

/// What tests and benchmarks reach into the renderer for.
impl GpuRenderer {
    /// How the software traversal's BVH of later `load_scene` calls is built (benchmarks).
    pub fn set_bvh_params(&mut self, params: BvhParams) {
        self.bvh_params = params;
    }
    /// Creates a sampler that nothing destroys, so tests can check that [`Self::close`] fails
    /// on the validation layer's leak report.
    pub fn leak_an_object_for_tests(&self) -> Result<(), GpuError> {
        self.ctx.leak_sampler()
    }
    /// Evaluates the GLSL sampler and camera mirrors for `queries` with `camera` (tests).
    pub fn probe_mirrors(
        &mut self,
        camera: &Camera,
        queries: &[ProbeQuery],
    ) -> Result<Vec<ProbeResult>, GpuError> {
        mirrors::run(&self.ctx, camera, queries)
    }
    /// Preview view `view` (VIEW_*, not the final one) of `camera` by both of the preview's
    /// routes: G-buffer and resolve, and the view pass (tests).
    pub fn probe_view_routes(
        &mut self,
        camera: &Camera,
        background: Vec3,
        view: u32,
    ) -> Result<ViewRoutes, GpuError> {
        check_size(camera)?;
        let gbuffer = self.raster.gbuffer_pass(self.scene.as_ref())?;
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        view_routes::run(&self.ctx, gbuffer, scene, camera, background, view)
    }
    /// Reads every field of the shared structs back through the shaders' blocks (tests).
    pub fn probe_layouts(&mut self) -> Result<LayoutReport, GpuError> {
        layouts::run(&self.ctx)
    }
    /// GPU milliseconds that generating the camera samples of a render of `shot` (its camera's
    /// size and its settings) takes on its own (the compute pass's sample loop without
    /// tracing), to compare with [`Timings::trace_gpu_ms`].
    pub fn sample_generation_ms(&mut self, shot: &Shot) -> Result<f64, GpuError> {
        let camera = &shot.camera;
        check_size(camera)?;
        sampler_cost::run(&self.ctx, camera.width, camera.height, &shot.render)
    }
    /// Caps the pixel-samples per dispatch of the compute pass (tests use it to force several
    /// submissions). By default dispatches are sized from the measured speed to last
    /// `TARGET_DISPATCH_MS`.
    pub fn set_samples_per_dispatch(&mut self, samples: u64) {
        self.trace.sizing.samples_per_dispatch = samples.max(1);
    }
    /// Starts the ray counter of later calls at `low` (tests start near 2^32 to see the carry
    /// into the count's high word); the reports subtract it.
    pub fn set_ray_counter_start(&mut self, low: u32) {
        self.trace.rays.start = low;
    }
    /// Most pixels whose sums the compute pass holds at once (tests use it to force bands).
    pub fn set_max_band_pixels(&mut self, pixels: u64) {
        self.trace.films.max_band_pixels = pixels.max(1);
    }
}

/// What the plan's probes read back from the renderer.
impl GpuRenderer {
    /// The hybrid's lit pre-pass of `shot` alone (the input of `host_plan`): per pixel the
    /// shortcut value (xyz) and whether its shadow ray was blocked (w, 1 or 0).
    pub(crate) fn lit_prepass(&mut self, shot: &Shot) -> Result<Vec<[f32; 4]>, GpuError> {
        let camera = &shot.camera;
        check_size(camera)?;
        self.prepare_raster(camera.width, camera.height)?;
        let pixels = u64::from(camera.width) * u64::from(camera.height);
        self.trace.ensure_plan_capacity(pixels)?;
        self.trace.ensure_camera_tables(camera)?;
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let batch = SampleBatch::new(Estimator::Hybrid, shot, self.raster.visibility(), scene)?;
        let (ctx, trace) = (&self.ctx, &self.trace);
        ctx.submit_and_wait(|rec| {
            trace.record_params(rec, &crate::upload::trace_params(batch.shot()));
            trace.rays.record_clear(rec);
            batch.record_lit_prepass(&trace.pipelines, rec)?;
            Ok(())
        })?;
        self.trace.plan.read(pixels)
    }

    /// The entries of the plan last made by `plan_on_device` (`pixels` of them), once it is
    /// made.
    pub(crate) fn read_plan_entries(&self, pixels: u64) -> Result<Vec<[f32; 4]>, GpuError> {
        self.ctx.wait_all()?;
        self.trace.plan.read(pixels)
    }
}
