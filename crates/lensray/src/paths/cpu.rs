//! The CPU reference as a render path.

use std::ops::Range;

use anyhow::Result;
use glam::{UVec2, Vec2};

use crate::paths::{Clock, PathKind, PathReport, RenderPath};
use lensray_core::camera::Camera;
use lensray_core::film::{Accumulation, Image, Progress};
use lensray_core::reference::{EmbreeSettings, Renderer};
use lensray_core::sampler::CameraSample;
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;

pub struct CpuPath {
    renderer: Option<Renderer>,
    report: PathReport,
}

impl CpuPath {
    pub fn new() -> Self {
        Self {
            renderer: None,
            report: PathReport {
                rays: 0,
                trace_seconds: 0.0,
                clock: Clock::WallClock,
                build_seconds: 0.0,
                accel_bytes: 0,
                peak_device_bytes: 0,
                aov_passes: 0,
                aov_seconds: 0.0,
                submits: 0,
                cpu_waits: 0,
                readback_bytes: 0,
                readback_seconds: 0.0,
                compile_seconds: 0.0,
                adaptive_samples: 0,
            },
        }
    }

    /// One round of adaptive sampling (`film::adaptive`): every pixel marked in `active` from
    /// its count to `end`, its class A samples added to `class_a` (the preview's rounds).
    pub fn add_round(
        &mut self,
        shot: &Shot,
        end: u32,
        active: &[bool],
        accumulation: &mut Accumulation,
        class_a: &mut [glam::Vec3],
    ) -> Result<()> {
        super::check_accumulation(shot, accumulation)?;
        let sums = accumulation.host_mut()?;
        let stats = self
            .renderer()?
            .accumulate_active(shot, end, active, sums, class_a);
        self.report.rays += stats.rays;
        self.report.trace_seconds += stats.elapsed.as_secs_f64();
        Ok(())
    }

    fn renderer(&self) -> Result<&Renderer> {
        self.renderer
            .as_ref()
            .ok_or_else(|| anyhow::anyhow!("no scene loaded"))
    }

    /// Builds the renderer of `scene`, its moving meshes through `motion`'s steps.
    fn load(&mut self, scene: &Scene, motion: Option<&ObjectMotion>) -> Result<()> {
        EmbreeSettings::from_env()?;
        let renderer = Renderer::with_motion(scene, motion);
        self.report.build_seconds += renderer.bvh_build_time().as_secs_f64();
        self.report.accel_bytes = renderer.accel_bytes();
        self.renderer = Some(renderer);
        Ok(())
    }
}

impl Default for CpuPath {
    fn default() -> Self {
        Self::new()
    }
}

impl RenderPath for CpuPath {
    fn kind(&self) -> PathKind {
        PathKind::Cpu
    }

    fn device_name(&self) -> String {
        // The instruction set Embree runs differs between CPUs, and so do its floats.
        let isa = EmbreeSettings::from_env().map_or_else(|_| "?".into(), |s| s.isa().to_string());
        format!(
            "CPU, {} threads, Embree {isa}",
            rayon::current_num_threads()
        )
    }

    fn load_scene(&mut self, scene: &Scene) -> Result<()> {
        self.load(scene, None)
    }

    fn load_moving_scene(&mut self, scene: &Scene, motion: &ObjectMotion) -> Result<()> {
        self.load(scene, Some(motion))
    }

    fn add_samples(
        &mut self,
        shot: &Shot,
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()> {
        super::check_accumulation(shot, accumulation)?;
        let sums = accumulation.host_mut()?;
        let stats = self.renderer()?.accumulate(shot, samples, sums, progress);
        self.report.rays += stats.rays;
        self.report.trace_seconds += stats.elapsed.as_secs_f64();
        Ok(())
    }

    fn add_adaptive(
        &mut self,
        shot: &Shot,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<()> {
        super::check_accumulation(shot, accumulation)?;
        let threshold = shot
            .render
            .noise_threshold
            .ok_or_else(|| anyhow::anyhow!("an adaptive render needs a noise threshold"))?;
        let sums = accumulation.host_mut()?;
        let (stats, adaptive) = self
            .renderer()?
            .render_adaptive(shot, threshold, sums, progress);
        self.report.rays += stats.rays;
        self.report.trace_seconds += stats.elapsed.as_secs_f64();
        self.report.adaptive_samples += adaptive.samples;
        Ok(())
    }

    /// The CPU keeps its sums on the host: nothing to read, unless a device holds them.
    fn read_sums(&mut self, accumulation: &mut Accumulation) -> Result<()> {
        accumulation.host()?;
        Ok(())
    }

    fn aov(&mut self, shot: &Shot) -> Result<Image> {
        let (image, stats) = self.renderer()?.render(shot, &mut |_, _| {});
        self.report.aov_passes += 1;
        self.report.aov_seconds += stats.elapsed.as_secs_f64();
        Ok(image)
    }

    fn focus_depth_at(&mut self, camera: &Camera, pixel: [u32; 2]) -> Result<Option<f32>> {
        let centre = UVec2::from(pixel).as_vec2() + Vec2::splat(0.5);
        let ray = camera.first_order_ray(CameraSample::new(centre, Vec2::splat(0.5)));
        Ok(self
            .renderer()?
            .intersect(&ray)
            .map(|hit| camera.view_depth(ray.at(hit.t))))
    }

    fn report(&self) -> PathReport {
        self.report
    }

    fn close(self: Box<Self>) -> Result<()> {
        Ok(())
    }
}
