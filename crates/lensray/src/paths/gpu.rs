//! The GPU paths: the Vulkan renderer with a scene loaded, its AOVs (the raster G-buffer),
//! focus picking, report and close. A path differs only in how it adds samples, its
//! [`Estimator`] (`PathKind::estimator`): traced (rayquery, software), raster, hybrid.

use std::ops::Range;

use anyhow::Result;
use glam::Vec3;

use crate::paths::{Clock, PathKind, PathReport, RenderPath};
use lensray_core::camera::flare::ghosts::{FilmLight, FlareLens};
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Image, Progress};
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;
use lensray_vulkan::{focus_distance_at, Estimator, GhostRequest, GpuRenderer, Traversal};

/// A GPU path: the renderer and the estimator that adds its samples.
pub struct GpuPath {
    renderer: GpuRenderer,
    estimator: Estimator,
    peak_device_bytes: u64,
    /// Wall-clock seconds of the hybrid's plans (G-buffer draw and plan on the device),
    /// counted in the report's trace time: they are part of what the path costs.
    plan_seconds: f64,
    /// Wall-clock seconds of `read_sums`.
    readback_seconds: f64,
    /// Samples the adaptive renders took (`PathReport::adaptive_samples`).
    adaptive_samples: u64,
}

impl GpuPath {
    /// The path of `kind` on `renderer`, which must trace with the traversal the path needs
    /// (set by `paths::open`).
    pub fn new(renderer: GpuRenderer, kind: PathKind) -> Result<Self> {
        if !kind.is_gpu() {
            anyhow::bail!("the {kind} path has no Vulkan renderer");
        }
        Ok(Self {
            peak_device_bytes: renderer.allocated_bytes(),
            renderer,
            estimator: kind.estimator(),
            plan_seconds: 0.0,
            readback_seconds: 0.0,
            adaptive_samples: 0,
        })
    }

    /// The renderer the path adds samples with.
    pub fn renderer(&self) -> &GpuRenderer {
        &self.renderer
    }

    fn note_memory(&mut self) {
        self.peak_device_bytes = self.peak_device_bytes.max(self.renderer.allocated_bytes());
    }
}

impl RenderPath for GpuPath {
    fn kind(&self) -> PathKind {
        match self.estimator {
            Estimator::Traced => PathKind::of_traversal(self.renderer.traversal()),
            Estimator::Raster => PathKind::Raster,
            Estimator::Hybrid => PathKind::Hybrid,
        }
    }

    fn device_name(&self) -> String {
        self.renderer.device_name()
    }

    fn load_scene(&mut self, scene: &Scene) -> Result<()> {
        self.renderer.load_scene(scene)?;
        self.note_memory();
        Ok(())
    }

    fn load_moving_scene(&mut self, scene: &Scene, motion: &ObjectMotion) -> Result<()> {
        if self.kind() != PathKind::Software {
            return Err(super::moving_objects_refusal(self.kind()));
        }
        self.renderer.load_moving_scene(scene, Some(motion))?;
        self.note_memory();
        Ok(())
    }

    fn add_samples(
        &mut self,
        shot: &Shot,
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()> {
        super::check_accumulation(shot, accumulation)?;
        if shot.camera.motion.is_some() {
            super::refuse_motion(self.kind())?;
        }
        let added =
            self.renderer
                .add_samples(shot, self.estimator, samples, accumulation, progress);
        self.note_memory();
        self.plan_seconds += added?.plan_seconds;
        Ok(())
    }

    fn add_adaptive(
        &mut self,
        shot: &Shot,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()> {
        super::check_accumulation(shot, accumulation)?;
        if let Some(why) = self.kind().adaptive_refusal() {
            anyhow::bail!(
                "--path {} does not sample adaptively (--noise-threshold): {why}",
                self.kind()
            );
        }
        let report = self.renderer.add_adaptive(shot, accumulation, progress);
        self.note_memory();
        self.adaptive_samples += report?.samples;
        Ok(())
    }

    fn read_sums(&mut self, accumulation: &mut Accumulation) -> Result<()> {
        let start = std::time::Instant::now();
        let read = self.renderer.read_sums(accumulation);
        self.readback_seconds += start.elapsed().as_secs_f64();
        Ok(read?)
    }

    fn aov(&mut self, shot: &Shot) -> Result<Image> {
        let image = self.renderer.aov(shot)?;
        self.note_memory();
        Ok(image)
    }

    fn focus_depth_at(&mut self, camera: &Camera, pixel: [u32; 2]) -> Result<Option<f32>> {
        let gbuffer = self.renderer.render_gbuffer(camera, Vec3::ZERO)?;
        self.note_memory();
        Ok(focus_distance_at(&gbuffer, pixel[0], pixel[1]))
    }

    fn ghost_light(
        &mut self,
        camera: &Camera,
        lens: &FlareLens,
        request: &GhostRequest,
    ) -> Option<Result<FilmLight>> {
        Some(
            self.renderer
                .ghost_light(camera, lens, request)
                .map_err(Into::into),
        )
    }

    fn report(&self) -> PathReport {
        let t = self.renderer.timings();
        let counters = self.renderer.counters();
        let traversal = self.renderer.traversal();
        // The pipeline's first dispatch is timed apart; its rays and time count here so that a
        // render's report covers all of it. The shaders' compilation is not in it: it happens
        // when the pipeline is made, or in an empty dispatch before (`compile_seconds`).
        PathReport {
            rays: t.rays_traced + t.first_dispatch_rays,
            trace_seconds: (t.trace_gpu_ms + t.first_dispatch_ms.unwrap_or(0.0)) * 1e-3
                + self.plan_seconds,
            clock: Clock::GpuTimestamps,
            build_seconds: match traversal {
                Traversal::RayQuery | Traversal::RtPipeline => t.accel_build_wall_ms * 1e-3,
                Traversal::Software => t.bvh_build_ms * 1e-3,
            },
            accel_bytes: t.traversal_bytes(traversal),
            peak_device_bytes: self.peak_device_bytes,
            aov_passes: t.gbuffer_passes,
            aov_seconds: t.gbuffer_gpu_ms * 1e-3,
            submits: counters.submits,
            cpu_waits: counters.cpu_waits,
            readback_bytes: counters.readback_bytes,
            readback_seconds: self.readback_seconds,
            compile_seconds: counters.compile_seconds() + t.compile_ms * 1e-3,
            adaptive_samples: self.adaptive_samples,
        }
    }

    fn close(self: Box<Self>) -> Result<()> {
        Ok(self.renderer.close()?)
    }
}
