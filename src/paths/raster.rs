//! The raster path (issue 10, docs/raster.md): accumulation-buffer depth of field. Each camera
//! sample is shared by every pixel: the scene is rasterized through that sample's lens point
//! with a sheared projection whose focal plane stays fixed (`Camera::clip_from_world_through_lens`,
//! perspective and orthographic alike), and a shading pass shades what each pixel sees along
//! its lens ray (lit: one shadow ray with the device's fastest traversal). The average over
//! passes is the thin-lens image: with the same (shared) camera samples, `rayquery` computes
//! the same estimator (`RenderSettings::shared_samples`).

use std::ops::Range;

use anyhow::Result;

use super::gpu::GpuPath;
use crate::camera::Camera;
use crate::gpu::GpuRenderer;
use crate::render::path::{PathKind, PathReport, RenderPath};
use crate::render::{Accumulation, Image, RenderSettings};
use crate::scene::Scene;

pub struct RasterPath {
    inner: GpuPath,
}

impl RasterPath {
    pub fn new(renderer: GpuRenderer) -> Result<Self> {
        Ok(Self {
            inner: GpuPath::new(renderer, PathKind::Raster)?,
        })
    }
}

impl RenderPath for RasterPath {
    fn kind(&self) -> PathKind {
        PathKind::Raster
    }

    fn device_name(&self) -> String {
        self.inner.device_name()
    }

    fn load_scene(&mut self, scene: &Scene) -> Result<()> {
        self.inner.load_scene(scene)
    }

    fn add_samples(
        &mut self,
        camera: &Camera,
        settings: &RenderSettings,
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<()> {
        super::check_accumulation(camera, settings, accumulation)?;
        self.inner.renderer_mut().accumulate_rasterized(
            camera,
            settings,
            samples,
            accumulation,
            progress,
        )?;
        self.inner.note_memory();
        Ok(())
    }

    fn aov(&mut self, camera: &Camera, settings: &RenderSettings) -> Result<Image> {
        self.inner.aov(camera, settings)
    }

    fn focus_depth_at(&mut self, camera: &Camera, pixel: [u32; 2]) -> Result<Option<f32>> {
        self.inner.focus_depth_at(camera, pixel)
    }

    fn report(&self) -> PathReport {
        self.inner.report()
    }

    fn close(self: Box<Self>) -> Result<()> {
        Box::new(self.inner).close()
    }
}
