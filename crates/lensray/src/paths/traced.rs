//! The traced paths, `rayquery` and `software`: the thin-lens compute pass traces every sample
//! of every pixel, finding closest hits with the renderer's traversal (Vulkan ray queries, or
//! lensray's BVH traversed in the shader).

use std::ops::Range;

use anyhow::Result;

use super::gpu::{GpuEstimator, GpuPath};
use crate::paths::PathKind;
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Progress};
use lensray_core::settings::RenderSettings;
use lensray_vulkan::GpuRenderer;

/// Every sample traced.
pub struct Traced;

/// `rayquery` or `software`, as the renderer's traversal is.
pub type TracedPath = GpuPath<Traced>;

impl GpuEstimator for Traced {
    fn kind(&self, renderer: &GpuRenderer) -> PathKind {
        PathKind::of_traversal(renderer.traversal())
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
        Ok(renderer.accumulate(camera, settings, samples, accumulation, progress)?)
    }
}
