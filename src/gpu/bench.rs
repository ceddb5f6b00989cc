//! Throughput of the compute pass, measured with timestamp queries (for `lensray bench` and
//! `benches/gpu.rs`).

use std::time::Instant;

use super::{GpuError, GpuOptions, GpuRenderer};
use crate::camera::Camera;
use crate::render::RenderSettings;
use crate::scene::Scene;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BenchOptions {
    pub gpu: GpuOptions,
    /// Timed renders after the warm-up (>= 1).
    pub repeats: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct BenchReport {
    pub device: String,
    pub triangles: usize,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Acceleration-structure build: GPU timestamps and wall clock, ms.
    pub accel_build_gpu_ms: f64,
    pub accel_build_wall_ms: f64,
    /// The pipeline's first dispatch (a tiny warm-up render; drivers compile lazily), ms.
    pub first_dispatch_ms: f64,
    /// GPU time of the timed renders' dispatches, ms (sum over repeats).
    pub trace_gpu_ms: f64,
    /// Rays (camera + shadow) of the timed renders.
    pub rays: u64,
    /// Dispatches of the timed renders, and the longest one (ms).
    pub dispatches: u64,
    pub longest_dispatch_ms: f64,
    pub rays_per_second: f64,
    /// Wall-clock time of the timed renders, ms (includes submission and readback).
    pub wall_ms: f64,
}

impl std::fmt::Display for BenchReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
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
        writeln!(f, "first dispatch:    {:.1} ms", self.first_dispatch_ms)?;
        writeln!(
            f,
            "dispatches:        {} (longest {:.1} ms)",
            self.dispatches, self.longest_dispatch_ms
        )?;
        writeln!(
            f,
            "trace:             {:.1} ms GPU ({:.1} ms wall) for {} rays",
            self.trace_gpu_ms, self.wall_ms, self.rays
        )?;
        write!(
            f,
            "throughput:        {:.2} Mrays/s",
            self.rays_per_second * 1e-6
        )
    }
}

/// Loads `scene`, warms the trace pipeline up with a tiny render, then renders `camera` with
/// `settings` `options.repeats` times and reports the compute pass's throughput.
pub fn bench(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    options: &BenchOptions,
) -> Result<BenchReport, GpuError> {
    let mut renderer = GpuRenderer::new(&options.gpu)?;
    renderer.load_scene(scene)?;
    let mut tiny = camera.clone();
    tiny.width = 8;
    tiny.height = 8;
    let tiny = Camera::new(
        tiny.projection,
        tiny.frame,
        tiny.lens,
        tiny.near,
        tiny.far,
        8,
        8,
    );
    renderer.render(
        &tiny,
        &RenderSettings {
            spp: 1,
            ..*settings
        },
        &mut |_, _| {},
    )?;
    let before = renderer.timings();
    let start = Instant::now();
    for _ in 0..options.repeats.max(1) {
        renderer.render(camera, settings, &mut |_, _| {})?;
    }
    let wall_ms = start.elapsed().as_secs_f64() * 1e3;
    let after = renderer.timings();
    let trace_gpu_ms = after.trace_gpu_ms - before.trace_gpu_ms;
    let rays = after.rays_traced - before.rays_traced;
    Ok(BenchReport {
        device: renderer.device_name(),
        triangles: scene.triangle_count(),
        width: camera.width,
        height: camera.height,
        spp: settings.spp,
        accel_build_gpu_ms: after.accel_build_gpu_ms,
        accel_build_wall_ms: after.accel_build_wall_ms,
        first_dispatch_ms: after.first_dispatch_ms.unwrap_or(0.0),
        trace_gpu_ms,
        rays,
        dispatches: after.dispatches - before.dispatches,
        longest_dispatch_ms: after.longest_dispatch_ms,
        rays_per_second: if trace_gpu_ms > 0.0 {
            rays as f64 / (trace_gpu_ms * 1e-3)
        } else {
            0.0
        },
        wall_ms,
    })
}
