//! The hybrid path (docs/hybrid.md): the raster G-buffer decides where rays are needed. Per
//! call of `add_samples`, one submission on the device (`GpuRenderer::plan_on_device`): the
//! G-buffer of the shot, the lit pre-pass under lit shading, then the plan pass (lensray-vulkan's
//! `passes::hybrid_plan`, shaders/passes/hybrid_plan.comp: circle of confusion from the
//! G-buffer depth, maximum over 8x8 tiles, dilated by each tile's maximum over the tiles it
//! reaches; edge marks in a summed-area table; one entry per pixel) written straight into the
//! trace pass's plan buffer, with no readback; then the trace pass in its hybrid mode
//! (shaders/passes/trace.comp) with the device's fastest traversal. Per pixel:
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
//! `plan` holds the same rules on the host: `Plan::new` is the reference the device plan is
//! checked against (`host_plan` reads the G-buffer back and plans on the host, `device_plan`
//! reads the device's entries back; tests/hybrid.rs compares them). A render reads none of the
//! plan back (`HybridPath::last_plan` does, when asked).
//!
//! Whether a pixel traces sample `i` depends on the plan (camera, settings, scene) only, never on
//! the range asked for, so any split of a range gives the same sums, as for every path.

mod plan;

use std::ops::Range;
use std::time::Instant;

use anyhow::Result;

use super::gpu::{GpuEstimator, GpuPath};
use crate::paths::PathKind;
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Progress};
use lensray_core::settings::RenderSettings;
use lensray_vulkan::GpuRenderer;

pub use plan::{device_plan, host_plan, window_radius, Plan, SEGMENT, SHORTCUT_COC, TILE};

/// The trace pass following a plan made from the G-buffer, per call of `add_samples`.
#[derive(Default)]
pub struct Hybrid {
    /// Wall-clock seconds of the plans (G-buffer draw and plan on the device, entries read),
    /// counted in the report's trace time: they are part of what the path costs.
    plan_seconds: f64,
    /// The size and spp of the last plan, which stays on the device (read back only when
    /// asked: `HybridPath::last_plan`).
    last_plan: Option<(u32, u32, u32)>,
}

/// The hybrid path: a GPU path (any traversal; `paths::open` picks the device's fastest) whose
/// trace pass follows a plan made from the G-buffer.
pub type HybridPath = GpuPath<Hybrid>;

impl HybridPath {
    pub fn new(renderer: GpuRenderer) -> Result<Self> {
        Ok(GpuPath::with(renderer, Hybrid::default()))
    }

    /// The plan of the last `add_samples` call, read back from the device (tests and
    /// measurements: a render reads back nothing of it).
    pub fn last_plan(&self) -> Result<Option<Plan>> {
        let Some((width, height, spp)) = self.estimator.last_plan else {
            return Ok(None);
        };
        let pixels = u64::from(width) * u64::from(height);
        let entries = self.renderer().read_plan(pixels)?;
        Ok(Some(Plan::from_entries(width, height, entries, spp)))
    }
}

impl GpuEstimator for Hybrid {
    fn kind(&self, _: &GpuRenderer) -> PathKind {
        PathKind::Hybrid
    }

    fn add_samples(
        &mut self,
        renderer: &mut GpuRenderer,
        camera: &Camera,
        settings: &RenderSettings,
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()> {
        let start = Instant::now();
        renderer.plan_on_device(camera, &camera.for_rasterizing_rays(), settings)?;
        self.plan_seconds += start.elapsed().as_secs_f64();
        let traced = renderer.accumulate(camera, settings, samples, accumulation, progress);
        let cleared = renderer.set_plan(None);
        self.last_plan = Some((camera.width, camera.height, settings.spp));
        traced?;
        cleared?;
        Ok(())
    }

    fn host_seconds(&self) -> f64 {
        self.plan_seconds
    }
}
