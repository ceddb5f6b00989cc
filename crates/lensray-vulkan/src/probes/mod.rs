//! Probes for tests and benchmarks (feature `probes`, which the crate's own tests and benches
//! turn on): the GLSL mirrors of the camera and sampler (`mirrors`), the hybrid plan's host
//! reference (`hybrid_plan`), the shared structs as the shaders read them (`layouts`), the
//! preview's two view routes (`view_routes`), the sample generation's cost (`sampler_cost`) and
//! pass timings (`timing`).

pub(crate) mod hybrid_plan;
pub(crate) mod layouts;
pub(crate) mod mirrors;
pub(crate) mod sampler_cost;
pub(crate) mod timing;
pub(crate) mod view_routes;

use glam::Vec3;

use crate::scene::bvh::BvhParams;
use crate::{check_size, GpuError, GpuRenderer};
use layouts::LayoutReport;
use lensray_core::camera::Camera;
use lensray_core::settings::Shot;
use mirrors::{ProbeQuery, ProbeResult};
use view_routes::ViewRoutes;

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
        self.gbuffer_pass()?;
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        view_routes::run(
            &self.ctx,
            self.gbuffer.as_mut().expect("made above"),
            scene,
            camera,
            background,
            view,
        )
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
        self.trace.samples_per_dispatch = samples.max(1);
    }
    /// Most pixels whose sums the compute pass holds at once (tests use it to force bands).
    pub fn set_max_band_pixels(&mut self, pixels: u64) {
        self.trace.max_band_pixels = pixels.max(1);
    }
}
