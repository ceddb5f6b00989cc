//! The raster path (accumulation-buffer depth of field, docs/raster.md): each camera sample is
//! shared by every pixel; the scene is rasterized through its lens point with
//! `Camera::clip_from_world_through_lens` (the visibility pass, `gpu/passes/visibility.rs`),
//! then the compute pass shades what each pixel sees along its lens ray (`TRACE_MODE_RASTER`
//! of shaders/passes/trace.comp; lit, with shadow rays of the device's fastest traversal).
//! With the same shared samples (`RenderSettings::shared_samples`) `rayquery` computes the
//! same estimator (tests/raster.rs).

use std::ops::Range;

use anyhow::Result;

use super::gpu::{GpuEstimator, GpuPath};
use crate::paths::PathKind;
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Progress};
use lensray_core::settings::RenderSettings;
use lensray_vulkan::GpuRenderer;

/// Every sample rasterized through its lens point, then shaded.
pub struct Raster;

pub type RasterPath = GpuPath<Raster>;

impl GpuEstimator for Raster {
    fn kind(&self, _: &GpuRenderer) -> PathKind {
        PathKind::Raster
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
        Ok(renderer.accumulate_rasterized(camera, settings, samples, accumulation, progress)?)
    }
}
