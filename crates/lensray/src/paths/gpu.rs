//! What the GPU paths share: the Vulkan renderer with a scene loaded, its AOVs (the raster
//! G-buffer), focus picking, report and close. A path differs only in how it adds samples, its
//! [`GpuEstimator`]: `traced` (rayquery, software), `raster`, `hybrid`.

use std::ops::Range;

use anyhow::Result;
use glam::Vec3;

use crate::paths::{Clock, PathKind, PathReport, RenderPath};
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Image, Progress};
use lensray_core::scene::Scene;
use lensray_core::settings::RenderSettings;
use lensray_vulkan::{focus_distance_at, GpuRenderer, Traversal};

/// How a GPU path adds samples to an accumulation.
pub trait GpuEstimator {
    /// The path it makes of `renderer` (the traced path is the traversal in use).
    fn kind(&self, renderer: &GpuRenderer) -> PathKind;

    /// Adds samples `samples` of every pixel to `accumulation` (checked by the caller: the
    /// camera's size, a traced shading), as `RenderPath::add_samples`.
    fn add_samples(
        &mut self,
        renderer: &mut GpuRenderer,
        camera: &Camera,
        settings: &RenderSettings,
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()>;

    /// Host time spent tracing besides the renderer's GPU timestamps (the hybrid's plan).
    fn host_seconds(&self) -> f64 {
        0.0
    }
}

/// The estimator of a GPU path `kind`; `None` for the CPU.
pub fn estimator(kind: PathKind) -> Option<Box<dyn GpuEstimator>> {
    Some(match kind {
        PathKind::RayQuery | PathKind::Software => Box::new(super::traced::Traced),
        PathKind::Raster => Box::new(super::raster::Raster),
        PathKind::Hybrid => Box::new(super::hybrid::Hybrid::default()),
        PathKind::Cpu => return None,
    })
}

/// A GPU path: the renderer and the estimator that adds its samples.
pub struct GpuPath<E> {
    renderer: GpuRenderer,
    pub(super) estimator: E,
    peak_device_bytes: u64,
}

impl<E: GpuEstimator> GpuPath<E> {
    /// `renderer` must trace with the traversal the path needs (set by `paths::open`).
    pub fn with(renderer: GpuRenderer, estimator: E) -> Self {
        Self {
            peak_device_bytes: renderer.allocated_bytes(),
            renderer,
            estimator,
        }
    }

    /// The renderer (the hybrid path reads its plan back on request).
    pub(super) fn renderer(&self) -> &GpuRenderer {
        &self.renderer
    }

    fn note_memory(&mut self) {
        self.peak_device_bytes = self.peak_device_bytes.max(self.renderer.allocated_bytes());
    }
}

impl<E: GpuEstimator> RenderPath for GpuPath<E> {
    fn kind(&self) -> PathKind {
        self.estimator.kind(&self.renderer)
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
        progress: &mut Progress,
    ) -> Result<()> {
        super::check_accumulation(camera, settings, accumulation)?;
        let added = self.estimator.add_samples(
            &mut self.renderer,
            camera,
            settings,
            samples,
            accumulation,
            progress,
        );
        self.note_memory();
        added
    }

    fn read_sums(&mut self, accumulation: &mut Accumulation) -> Result<()> {
        Ok(self.renderer.read_sums(accumulation)?)
    }

    fn aov(&mut self, camera: &Camera, settings: &RenderSettings) -> Result<Image> {
        let image = self.renderer.aov(camera, settings)?;
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
        let counters = self.renderer.counters();
        let traversal = self.renderer.traversal();
        // The pipeline's first dispatch is timed apart (lazy compilation); its rays and time
        // count here so that a render's report covers all of it.
        PathReport {
            rays: t.rays_traced + t.first_dispatch_rays,
            trace_seconds: (t.trace_gpu_ms + t.first_dispatch_ms.unwrap_or(0.0)) * 1e-3
                + self.estimator.host_seconds(),
            clock: Clock::GpuTimestamps,
            build_seconds: match traversal {
                Traversal::RayQuery => t.accel_build_wall_ms * 1e-3,
                Traversal::Software => t.bvh_build_ms * 1e-3,
            },
            accel_bytes: t.traversal_bytes(traversal),
            peak_device_bytes: self.peak_device_bytes,
            aov_passes: t.gbuffer_passes,
            aov_seconds: t.gbuffer_gpu_ms * 1e-3,
            submits: counters.submits,
            cpu_waits: counters.cpu_waits,
            readback_bytes: counters.readback_bytes,
        }
    }

    fn close(self: Box<Self>) -> Result<()> {
        Ok(self.renderer.close()?)
    }
}
