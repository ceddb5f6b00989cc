//! The GPU paths: the Vulkan renderer with one traversal (ray queries or lensray's BVH), or
//! the raster path (accumulation-buffer depth of field, docs/raster.md: each camera sample
//! shared by every pixel, rasterized through its lens point with
//! `Camera::clip_from_world_through_lens`, then shaded, lit with shadow rays of the device's
//! fastest traversal; with the same shared samples `rayquery` computes the same estimator);
//! the hybrid path (`super::hybrid`) wraps one.

use std::ops::Range;

use anyhow::Result;
use glam::Vec3;

use crate::camera::Camera;
use crate::film::{Accumulation, Image};
use crate::gpu::{focus_distance_at, GpuRenderer, Traversal};
use crate::paths::{Clock, PathKind, PathReport, RenderPath};
use crate::scene::Scene;
use crate::settings::RenderSettings;

pub struct GpuPath {
    renderer: GpuRenderer,
    kind: PathKind,
    peak_device_bytes: u64,
}

impl GpuPath {
    /// `renderer` must be able to run `kind`'s traversal.
    pub fn new(renderer: GpuRenderer, kind: PathKind) -> Result<Self> {
        debug_assert!(kind.is_gpu());
        Ok(Self {
            peak_device_bytes: renderer.allocated_bytes(),
            renderer,
            kind,
        })
    }

    /// The renderer (the hybrid path drives it with a plan).
    pub(super) fn renderer_mut(&mut self) -> &mut GpuRenderer {
        &mut self.renderer
    }

    pub(super) fn note_memory(&mut self) {
        self.peak_device_bytes = self.peak_device_bytes.max(self.renderer.allocated_bytes());
    }
}

impl RenderPath for GpuPath {
    fn kind(&self) -> PathKind {
        self.kind
    }

    fn device_name(&self) -> String {
        self.renderer.device_name()
    }

    fn load_scene(&mut self, scene: &Scene) -> Result<()> {
        self.renderer.load_scene(scene)?;
        self.note_memory();
        Ok(())
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
        if self.kind == PathKind::Raster {
            // Accumulation-buffer depth of field (docs/raster.md): every pixel shares each
            // camera sample, rasterized through its lens point, then shaded.
            self.renderer.accumulate_rasterized(
                camera,
                settings,
                samples,
                accumulation,
                progress,
            )?;
        } else {
            self.renderer
                .accumulate(camera, settings, samples, accumulation, progress)?;
        }
        self.note_memory();
        Ok(())
    }

    fn aov(&mut self, camera: &Camera, settings: &RenderSettings) -> Result<Image> {
        let image = self.renderer.render(camera, settings, &mut |_, _| {})?;
        self.note_memory();
        Ok(image)
    }

    fn focus_depth_at(&mut self, camera: &Camera, pixel: [u32; 2]) -> Result<Option<f32>> {
        let gbuffer = self.renderer.render_gbuffer(camera, Vec3::ZERO)?;
        self.note_memory();
        Ok(focus_distance_at(&gbuffer, pixel[0], pixel[1]))
    }

    fn report(&self) -> PathReport {
        let t = self.renderer.timings();
        let traversal = self.renderer.traversal();
        // The pipeline's first dispatch is timed apart (lazy compilation); its rays and time
        // count here so that a render's report covers all of it.
        PathReport {
            rays: t.rays_traced + t.first_dispatch_rays,
            trace_seconds: (t.trace_gpu_ms + t.first_dispatch_ms.unwrap_or(0.0)) * 1e-3,
            clock: Clock::GpuTimestamps,
            build_seconds: match traversal {
                Traversal::RayQuery => t.accel_build_wall_ms * 1e-3,
                Traversal::Software => t.bvh_build_ms * 1e-3,
            },
            accel_bytes: t.traversal_bytes(traversal),
            peak_device_bytes: self.peak_device_bytes,
            aov_passes: t.gbuffer_passes,
            aov_seconds: t.gbuffer_gpu_ms * 1e-3,
        }
    }

    fn close(self: Box<Self>) -> Result<()> {
        Ok(self.renderer.close()?)
    }
}
