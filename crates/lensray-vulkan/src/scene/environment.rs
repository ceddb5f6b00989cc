//! An environment map on the device (shaders/include/environment.glsl): its parameters, its
//! texels and the sampling tables the host built (`EnvironmentSampler`), uploaded as they are
//! so that the shaders draw the same texels from the same points.

use std::sync::Arc;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use glam::Vec3;
use lensray_core::interface::{EnvironmentGroup, GpuEnvironment};
use lensray_core::scene::environment::{EnvironmentMap, EnvironmentSampler};
use lensray_core::scene::Scene;

pub(crate) struct EnvironmentBuffers {
    params: Buffer,
    texels: Buffer,
    row_cdfs: Buffer,
    rows_cdf: Buffer,
    /// Whether these are a scene's map (not the placeholder of a scene without one).
    pub has_map: bool,
}

/// The parameters of `map` as the shaders read them; `total` 0 when nothing in it emits.
pub(crate) fn gpu_environment(map: &EnvironmentMap, total: f32) -> GpuEnvironment {
    let radians = map.rotation_degrees.to_radians();
    GpuEnvironment {
        width: map.width,
        height: map.height,
        total,
        intensity: map.intensity,
        turn: [radians.cos(), radians.sin(), 0.0, 0.0],
    }
}

impl EnvironmentBuffers {
    /// The map of `scene` (`Scene::environment`), or a black 2x1 placeholder that keeps every
    /// binding valid. A map whose texels pass the device's storage buffer range is an error.
    pub(crate) fn of_scene(ctx: &Arc<Context>, scene: &Scene) -> Result<Self, GpuError> {
        let Some(light) = &scene.environment else {
            let black =
                EnvironmentMap::new(2, 1, vec![Vec3::ZERO; 2]).expect("a 2x1 map has its texels");
            let mut placeholder = Self::new(ctx, &black, None)?;
            placeholder.has_map = false;
            return Ok(placeholder);
        };
        let map = &light.map;
        let bytes = u64::from(map.width) * u64::from(map.height) * 16;
        let limit = u64::from(ctx.report.max_storage_buffer_range);
        if bytes > limit {
            return Err(GpuError::Invalid(format!(
                "the environment map's {}x{} texels need {bytes} bytes, more than the \
                 device's maximum storage buffer range ({limit} bytes): use a smaller map",
                map.width, map.height
            )));
        }
        Self::new(ctx, map, light.sampler.as_ref())
    }

    /// Uploads `map` and its tables (`sampler`; `None`: nothing emits, and the tables hold
    /// zeros of the same sizes so that every binding is valid).
    pub(crate) fn new(
        ctx: &Arc<Context>,
        map: &EnvironmentMap,
        sampler: Option<&EnvironmentSampler>,
    ) -> Result<Self, GpuError> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let (w, h) = (map.width as usize, map.height as usize);
        let (row_cdfs, rows_cdf, total) = match sampler {
            Some(s) => (s.row_cdfs().to_vec(), s.rows_cdf().to_vec(), s.total()),
            None => (vec![0.0; h * (w + 1)], vec![0.0; h + 1], 0.0),
        };
        let texels: Vec<[f32; 4]> = map.texels.iter().map(|t| t.extend(0.0).into()).collect();
        let params = gpu_environment(map, total);
        Ok(Self {
            params: Buffer::with_data(ctx, "environment", bytemuck::bytes_of(&params), storage)?,
            texels: Buffer::with_data(
                ctx,
                "environment texels",
                bytemuck::cast_slice(&texels),
                storage,
            )?,
            row_cdfs: Buffer::with_data(
                ctx,
                "environment row tables",
                bytemuck::cast_slice(&row_cdfs),
                storage,
            )?,
            rows_cdf: Buffer::with_data(
                ctx,
                "environment rows table",
                bytemuck::cast_slice(&rows_cdf),
                storage,
            )?,
            has_map: true,
        })
    }

    /// The map as `pipeline`'s set binds it.
    pub(crate) fn bind(&self, pipeline: &Pipeline) {
        pipeline.bind_group(&EnvironmentGroup::<Gpu> {
            environment: &self.params,
            env_texels: &self.texels,
            env_row_cdfs: &self.row_cdfs,
            env_rows_cdf: &self.rows_cdf,
        });
    }
}
