//! Timing of the GPU passes with timestamp queries, run by run (for `lensray bench` and
//! `benches/gpu.rs`): the thin-lens compute pass for `unlit` / `lit`, the G-buffer pass for the
//! AOVs (which are served from it).

use std::time::Instant;

use crate::{GpuError, GpuOptions, GpuRenderer};
use lensray_core::camera::Camera;
use lensray_core::scene::Scene;
use lensray_core::settings::{RenderSettings, Shot};
use lensray_core::stats::{median, range};

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassBenchOptions {
    pub gpu: GpuOptions,
    /// Timed renders after the warm-up (>= 1).
    pub repeats: u32,
}

/// Which pass a bench timed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BenchedPass {
    /// The thin-lens compute pass (`unlit`, `lit`): rays per second.
    Trace,
    /// The raster G-buffer pass (the AOVs): passes per second.
    GBuffer,
}

#[derive(Clone, Debug, PartialEq)]
pub struct PassBenchReport {
    pub device: String,
    pub triangles: usize,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub pass: BenchedPass,
    /// Acceleration-structure build: GPU timestamps and wall clock, ms.
    pub accel_build_gpu_ms: f64,
    pub accel_build_wall_ms: f64,
    /// The pipeline's first dispatch (a tiny warm-up render; drivers compile lazily), ms.
    pub first_dispatch_ms: f64,
    /// GPU time of each timed run (its dispatches, or its G-buffer draw), ms.
    pub run_gpu_ms: Vec<f64>,
    /// Wall-clock time of each timed run, ms (includes submission and readback).
    pub run_wall_ms: Vec<f64>,
    /// Rays (camera + shadow) of one run (0 for the G-buffer pass).
    pub rays_per_run: u64,
    /// Dispatches of one run, and the longest dispatch of all runs (ms).
    pub dispatches_per_run: u64,
    pub longest_dispatch_ms: f64,
}

impl PassBenchReport {
    pub fn median_gpu_ms(&self) -> f64 {
        median(&self.run_gpu_ms)
    }

    /// Rays per second at the median run's GPU time (trace pass).
    pub fn rays_per_second(&self) -> f64 {
        self.rays_per_run as f64 / (self.median_gpu_ms() * 1e-3).max(1e-12)
    }

    /// Runs per second at the median GPU time (G-buffer passes per second for the AOVs).
    pub fn runs_per_second(&self) -> f64 {
        1e3 / self.median_gpu_ms().max(1e-9)
    }
}

impl std::fmt::Display for PassBenchReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (lo, hi) = range(&self.run_gpu_ms);
        writeln!(f, "device:            {}", self.device)?;
        writeln!(
            f,
            "scene:             {} triangles, {}x{} at {} spp",
            self.triangles, self.width, self.height, self.spp
        )?;
        writeln!(
            f,
            "AS build:          {:.1} ms GPU, {:.1} ms wall",
            self.accel_build_gpu_ms, self.accel_build_wall_ms
        )?;
        let runs = self.run_gpu_ms.len();
        match self.pass {
            BenchedPass::Trace => {
                writeln!(f, "first dispatch:    {:.1} ms", self.first_dispatch_ms)?;
                writeln!(
                    f,
                    "dispatches:        {} per run (longest {:.1} ms)",
                    self.dispatches_per_run, self.longest_dispatch_ms
                )?;
                writeln!(
                    f,
                    "trace:             median {:.1} ms GPU (range {lo:.1}..{hi:.1}, {runs} runs; \
                     median {:.1} ms wall) for {} rays",
                    self.median_gpu_ms(),
                    median(&self.run_wall_ms),
                    self.rays_per_run
                )?;
                write!(
                    f,
                    "throughput:        {:.2} Mrays/s",
                    self.rays_per_second() * 1e-6
                )
            }
            BenchedPass::GBuffer => {
                writeln!(
                    f,
                    "G-buffer pass:     median {:.3} ms GPU (range {lo:.3}..{hi:.3}, {runs} runs; \
                     median {:.1} ms wall with readback)",
                    self.median_gpu_ms(),
                    median(&self.run_wall_ms)
                )?;
                write!(
                    f,
                    "throughput:        {:.1} G-buffer passes/s",
                    self.runs_per_second()
                )
            }
        }
    }
}

/// Opens the device, loads `scene` and runs [`bench_renderer`].
pub fn bench(
    scene: &Scene,
    shot: &Shot,
    options: &PassBenchOptions,
) -> Result<PassBenchReport, GpuError> {
    let mut renderer = GpuRenderer::new(&options.gpu)?;
    renderer.load_scene(scene)?;
    bench_renderer(&mut renderer, scene, shot, options.repeats)
}

/// Warms the pass up with a tiny render, then renders `shot` `repeats` times on a renderer
/// that has `scene` loaded, timing each run.
pub fn bench_renderer(
    renderer: &mut GpuRenderer,
    scene: &Scene,
    shot: &Shot,
    repeats: u32,
) -> Result<PassBenchReport, GpuError> {
    let (camera, settings) = (&shot.camera, &shot.render);
    let warm_up = Shot {
        camera: Camera::new(
            camera.projection,
            camera.frame,
            camera.lens.first_order_only(),
            camera.near,
            camera.far,
            8,
            8,
            camera.screen_window.centre,
        ),
        render: RenderSettings {
            spp: 1,
            ..*settings
        },
    };
    renderer.render(&warm_up, &mut |_, _| {})?;
    let pass = if settings.shading.is_aov() {
        BenchedPass::GBuffer
    } else {
        BenchedPass::Trace
    };
    let (mut run_gpu_ms, mut run_wall_ms) = (Vec::new(), Vec::new());
    let mut rays_per_run = 0;
    let mut dispatches_per_run = 0;
    for _ in 0..repeats.max(1) {
        let before = renderer.timings();
        let start = Instant::now();
        renderer.render(shot, &mut |_, _| {})?;
        run_wall_ms.push(start.elapsed().as_secs_f64() * 1e3);
        let after = renderer.timings();
        run_gpu_ms.push(match pass {
            BenchedPass::Trace => after.trace_gpu_ms - before.trace_gpu_ms,
            BenchedPass::GBuffer => after.gbuffer_gpu_ms - before.gbuffer_gpu_ms,
        });
        rays_per_run = after.rays_traced - before.rays_traced;
        dispatches_per_run = after.dispatches - before.dispatches;
    }
    let timings = renderer.timings();
    Ok(PassBenchReport {
        device: renderer.device_name(),
        triangles: scene.triangle_count(),
        width: camera.width,
        height: camera.height,
        spp: settings.spp,
        pass,
        accel_build_gpu_ms: timings.accel_build_gpu_ms,
        accel_build_wall_ms: timings.accel_build_wall_ms,
        first_dispatch_ms: timings.first_dispatch_ms.unwrap_or(0.0),
        run_gpu_ms,
        run_wall_ms,
        rays_per_run,
        dispatches_per_run,
        longest_dispatch_ms: timings.longest_dispatch_ms,
    })
}
