//! Which renderer runs a command: the Vulkan renderer or the CPU reference, behind one interface.

use anyhow::{bail, Context, Result};
use glam::{UVec2, Vec2};

use super::args::DeviceChoice;
use crate::camera::Camera;
use crate::gpu::{focus_distance_at, GpuOptions, GpuRenderer};
use crate::reference::Renderer;
use crate::render::{Image, RenderSettings};
use crate::scene::Scene;

pub enum Backend {
    Cpu(Box<Renderer>),
    Gpu(Box<GpuRenderer>),
}

/// What a render did, for the summary line.
pub struct RenderReport {
    pub rays: u64,
    /// Time spent tracing (GPU: timestamp queries, first dispatch excluded; CPU: wall clock).
    pub trace_seconds: f64,
}

impl Backend {
    /// Opens the chosen device and loads the scene. `Auto` falls back to the CPU with a one-line
    /// notice saying why, unless the command asked for something only the GPU has: a device
    /// (`--gpu`) or validation of the Vulkan renderer (`--validate`). Both are errors with
    /// `--device cpu`, where they would mean nothing.
    pub fn open(choice: DeviceChoice, options: &GpuOptions, scene: &Scene) -> Result<Self> {
        match choice {
            DeviceChoice::Cpu => {
                if options.validate {
                    bail!(
                        "--validate checks the Vulkan renderer: it cannot be used with \
                         --device cpu"
                    );
                }
                if let Some(index) = options.device_index {
                    bail!(
                        "--gpu {index} picks a Vulkan device: it cannot be used with --device cpu"
                    );
                }
                Ok(Backend::Cpu(Box::new(Renderer::new(scene))))
            }
            DeviceChoice::Gpu => Self::open_gpu(options, scene).context("--device gpu"),
            DeviceChoice::Auto => match Self::open_gpu(options, scene) {
                Ok(gpu) => Ok(gpu),
                Err(error) => match options.device_index {
                    Some(index) => Err(error.context(format!("--gpu {index}"))),
                    None if options.validate => Err(error.context("--validate")),
                    None => {
                        eprintln!("notice: rendering on the CPU: no usable GPU ({error:#})");
                        Ok(Backend::Cpu(Box::new(Renderer::new(scene))))
                    }
                },
            },
        }
    }

    fn open_gpu(options: &GpuOptions, scene: &Scene) -> Result<Self> {
        let mut gpu = GpuRenderer::new(options)?;
        gpu.load_scene(scene)?;
        Ok(Backend::Gpu(Box::new(gpu)))
    }

    pub fn describe(&self) -> String {
        match self {
            Backend::Cpu(_) => format!("CPU reference, {} threads", rayon::current_num_threads()),
            Backend::Gpu(gpu) => format!("GPU {}", gpu.device_name()),
        }
    }

    /// Autofocus: the view depth of the surface seen through the centre of pixel (x, y) by the
    /// aperture-centre ray (GPU: read from the raster G-buffer; CPU: traced).
    pub fn focus_distance_at(&mut self, camera: &Camera, pixel: [u32; 2]) -> Result<f32> {
        let [x, y] = pixel;
        if x >= camera.width || y >= camera.height {
            bail!(
                "--focus-at {x},{y} lies outside the {}x{} image",
                camera.width,
                camera.height
            );
        }
        let depth = match self {
            Backend::Gpu(gpu) => {
                let gbuffer = gpu.render_gbuffer(camera, glam::Vec3::ZERO)?;
                focus_distance_at(&gbuffer, x, y)
            }
            Backend::Cpu(cpu) => {
                let centre = UVec2::new(x, y).as_vec2() + Vec2::splat(0.5);
                let ray = camera.generate_ray(centre, Vec2::splat(0.5));
                cpu.intersect(&ray)
                    .map(|hit| camera.view_depth(ray.at(hit.t)))
            }
        };
        depth.with_context(|| format!("--focus-at {x},{y}: no surface at that pixel to focus on"))
    }

    pub fn render(
        &mut self,
        camera: &Camera,
        settings: &RenderSettings,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(Image, RenderReport)> {
        match self {
            Backend::Cpu(cpu) => {
                let (image, stats) = cpu.render(camera, settings, progress);
                Ok((
                    image,
                    RenderReport {
                        rays: stats.rays,
                        trace_seconds: stats.elapsed.as_secs_f64(),
                    },
                ))
            }
            Backend::Gpu(gpu) => {
                let before = gpu.timings();
                let image = gpu.render(camera, settings, progress)?;
                let after = gpu.timings();
                let rays = (after.rays_traced + after.first_dispatch_rays)
                    - (before.rays_traced + before.first_dispatch_rays);
                let first = after.first_dispatch_ms.unwrap_or(0.0)
                    - before.first_dispatch_ms.unwrap_or(0.0);
                let ms = after.trace_gpu_ms - before.trace_gpu_ms + first;
                Ok((
                    image,
                    RenderReport {
                        rays,
                        trace_seconds: ms * 1e-3,
                    },
                ))
            }
        }
    }

    /// Releases the device. With `--validate`, fails on any message of the validation layer,
    /// including its leak report, which comes while the device and instance are destroyed.
    pub fn close(self) -> Result<()> {
        match self {
            Backend::Cpu(_) => Ok(()),
            Backend::Gpu(gpu) => Ok(gpu.close()?),
        }
    }
}
