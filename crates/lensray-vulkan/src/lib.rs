//! The Vulkan renderer (ash, raw Vulkan 1.2): a raster G-buffer pass and a thin-lens compute
//! pass that finds closest hits with one of three [`Traversal`]s: VK_KHR_ray_query against
//! per-mesh BLASes under one TLAS, VK_KHR_ray_tracing_pipeline against the same structures (the
//! pass's shader as a ray-tracing pipeline's ray generation stage), or a software traversal of
//! the project's own BVH in the shader, which needs no ray-tracing support.
//!
//! The camera is the Rust [`Camera`](lensray_core::camera::Camera): the raster pass projects
//! with `clip_from_world()`, the compute pass generates rays with
//! `shaders/include/camera.glsl`, a function-by-function mirror of `lensray-core/src/camera`,
//! fed with the camera's own matrices. This crate is the only one of the workspace with
//! `unsafe` code, all of it in `core`; every Vulkan object is owned by a Rust value and
//! destroyed on drop.
//!
//! Layers, each a folder (the shaders in `shaders/` have the same ones):
//! - `core`: Vulkan itself: instance and validation, device and submissions, buffers, images,
//!   queries, pipelines, render passes, fences and semaphores, the window's surface and
//!   swapchain, embedded SPIR-V, host data in the shaders' layouts, errors;
//! - `scene`: a scene on the device: its arrays, acceleration structures, the software BVH;
//! - `passes`: the renderer's passes: G-buffer, thin-lens trace, the raster path's visibility
//!   pass and the hybrid's plan;
//! - `renderer`: [`GpuRenderer`], which owns the device and the passes: its entries, the one
//!   function that records a batch of samples with an [`Estimator`] (headless renders and the
//!   preview's frames alike), and what the preview records through it;
//! - `present`: the preview window: frames in flight, resolve, view pass, egui overlay, and
//!   the viewer that drives a frame;
//! - `probes` (feature `probes`, on for the crate's tests and benches): GLSL mirror checks,
//!   the hybrid plan's host reference, shared-struct layouts, the preview's view routes, sample
//!   generation cost, pass timings.
//!
//! This file holds the crate's exports, the [`Estimator`]s, the device options and the device list.
//!
//! ```no_run
//! use lensray_vulkan::{GpuOptions, GpuRenderer};
//! # fn demo(scene: &lensray_core::scene::Scene,
//! #         shot: &lensray_core::settings::Shot) -> Result<(), lensray_vulkan::GpuError> {
//! let mut gpu = GpuRenderer::new(&GpuOptions::default())?;
//! gpu.load_scene(scene)?; // BLAS per mesh (compacted) + TLAS and/or BVH, scene arrays uploaded
//! println!("tracing with {} of {:?}", gpu.traversal(), gpu.traversals());
//! let image = gpu.render(shot, &mut |done, total| eprint!("\r{done}/{total}"))?;
//! let camera = &shot.camera;
//! let gbuffer = gpu.render_gbuffer(camera, shot.render.background)?;
//! let focus = lensray_vulkan::focus_distance_at(&gbuffer, camera.width / 2, camera.height / 2);
//! println!("{} rays/s", gpu.timings().rays_per_second().unwrap_or(0.0));
//! # let _ = (image, focus); Ok(()) }
//! ```

// `pub` means exported: what no other crate can reach is `pub(crate)`.
#![deny(unreachable_pub)]
#![deny(clippy::undocumented_unsafe_blocks)]

mod core;
mod passes;
mod present;
#[cfg(feature = "probes")]
mod probes;
mod renderer;
mod scene;
mod traversal;
mod upload;

use core::instance::Instance;

pub use core::adapter::DeviceReport;
pub use core::counters::Counters;
pub use core::error::GpuError;
pub use core::instance::ValidationLog;
pub use passes::gbuffer::{focus_distance_at, GBuffer};
pub use passes::ghosts::GhostRequest;
pub use passes::trace::Timings;
pub use present::overlay::OverlayFrame;
pub use present::viewer::{
    FrameRequest, FrameResult, FrameTimes, HostSamples, PresentMode, Viewer, ViewerOptions,
};
#[cfg(feature = "probes")]
pub use probes::environment::{probe_environment, EnvironmentProbe};
#[cfg(feature = "probes")]
pub use probes::hybrid_plan::{device_plan, host_plan, read_plan, Plan};
#[cfg(feature = "probes")]
pub use probes::layouts::LayoutReport;
#[cfg(feature = "probes")]
pub use probes::mirrors::{ProbeQuery, ProbeResult};
#[cfg(feature = "probes")]
pub use probes::spectral::{probe_spectral, SpectralProbe};
#[cfg(feature = "probes")]
pub use probes::timing::{bench, bench_renderer, BenchedPass, PassBenchOptions, PassBenchReport};
#[cfg(feature = "probes")]
pub use probes::tonemap::probe_tonemaps;
#[cfg(feature = "probes")]
pub use probes::view_routes::ViewRoutes;
pub use renderer::{GpuRenderer, SamplesAdded};
pub use scene::bvh::BvhParams;
pub use traversal::Traversal;

/// How a render adds samples to an accumulation: traced per pixel through the lens with the
/// renderer's [`Traversal`], rasterized once per lens sample through a sheared projection
/// (every pixel sharing the sample), or the hybrid's mix of the G-buffer and traced samples
/// where its plan says the lens matters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Estimator {
    #[default]
    Traced,
    Raster,
    Hybrid,
}

/// How to open the GPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpuOptions {
    /// Enable VK_LAYER_KHRONOS_validation (with synchronization validation) and record its
    /// warnings and errors (see [`GpuRenderer::validation_messages`]).
    pub validate: bool,
    /// Use this device of [`list_devices`]; default: the best one for `traversal` (discrete
    /// first).
    pub device_index: Option<usize>,
    /// The traversal to open the device for: `RayQuery` needs a device with ray queries,
    /// `RtPipeline` one with the ray-tracing pipeline, `Software` enables no ray-tracing
    /// extension and builds only the BVH; None opens every traversal the device runs but the
    /// ray-tracing pipeline where ray queries serve, the first in use
    /// (`DeviceReport::opened_traversals`).
    pub traversal: Option<Traversal>,
    /// Treat every device as lacking VK_KHR_ray_query and VK_KHR_ray_tracing_pipeline (tests of
    /// the software traversal on a device that has them).
    pub hide_ray_query: bool,
    /// Say in one line on stderr when the driver compiles the shaders for a device's first use
    /// (its pipeline cache file is not there yet).
    pub first_use_notice: bool,
}

/// Every Vulkan device, with what it lacks for lensray (for `lensray info`).
pub fn list_devices() -> Result<Vec<DeviceReport>, GpuError> {
    let instance = Instance::new(false, &[])?;
    Ok(core::adapter::enumerate(&instance.instance)?
        .into_iter()
        .map(|(_, r)| r)
        .collect())
}

/// The device [`GpuRenderer::new`] would open with `options` (the same selection), without
/// opening it: the instance and the device list only.
pub fn preferred_device(options: &GpuOptions) -> Result<DeviceReport, GpuError> {
    let instance = Instance::new(false, &[])?;
    let mut devices = core::adapter::enumerate(&instance.instance)?;
    if options.hide_ray_query {
        for (_, report) in &mut devices {
            report.hide_ray_query();
        }
    }
    Ok(core::adapter::select(&devices, options.device_index, options.traversal)?.1)
}
