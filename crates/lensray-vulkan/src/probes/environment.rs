//! A check of the GLSL mirror of the environment map (shaders/include/environment.glsl):
//! draws a sample by each query's point and looks up each query's direction with
//! environment.comp, so that tests can compare them with lensray-core's scene::environment.

use ash::vk;
use glam::{Vec2, Vec3};
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::pipeline::Pipeline;
use crate::core::shader;
use crate::scene::environment::EnvironmentBuffers;
use crate::{GpuError, GpuRenderer};
use lensray_core::interface::{
    DescriptorSet, EnvironmentProbeGroup, EnvironmentProbeSet, ENVIRONMENT_PROBE_RESULT_FLOATS,
};
use lensray_core::scene::environment::{EnvironmentMap, EnvironmentSampler};

/// What the device computes for one query (environment.glsl).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvironmentProbe {
    /// `env_sample(point)`: the direction, its pdf (0: none) and radiance, and its texel
    /// (column + row * width), `None` when nothing was drawn.
    pub direction: Vec3,
    pub pdf: f32,
    pub radiance: Vec3,
    pub texel: Option<u32>,
    /// `env_pdf`, `env_radiance` and `env_uv_from_world` of the query's direction.
    pub lookup_pdf: f32,
    pub lookup_radiance: Vec3,
    pub lookup_uv: Vec2,
}

/// Evaluates the GLSL environment functions on `renderer`'s device for `map` (sampled by
/// `sampler`) at each query (the point to sample by, the direction to look up).
pub fn probe_environment(
    renderer: &GpuRenderer,
    map: &EnvironmentMap,
    sampler: Option<&EnvironmentSampler>,
    queries: &[(Vec2, Vec3)],
) -> Result<Vec<EnvironmentProbe>, GpuError> {
    let ctx = renderer.ctx();
    let pipeline = Pipeline::compute(ctx, EnvironmentProbeSet::DECL, shader::ENVIRONMENT_COMP)?;
    let environment = EnvironmentBuffers::new(ctx, map, sampler)?;
    let packed: Vec<[f32; 4]> = queries
        .iter()
        .flat_map(|(u, d)| [[u.x, u.y, 0.0, 0.0], d.extend(0.0).into()])
        .collect();
    let input = Buffer::with_data(
        ctx,
        "environment probe queries",
        bytemuck::cast_slice(&packed),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let stride = ENVIRONMENT_PROBE_RESULT_FLOATS as usize;
    let output = Buffer::new(
        ctx,
        "environment probe results",
        (queries.len() * stride * 4) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    environment.bind(&pipeline);
    pipeline.bind_group(&EnvironmentProbeGroup::<Gpu> {
        env_queries: &input,
        env_results: &output,
    });
    super::run_probe(ctx, &pipeline, queries.len() as u32, &output)?;
    let floats: &[f32] = bytemuck::cast_slice(output.read()?);
    Ok(floats
        .chunks_exact(stride)
        .take(queries.len())
        .map(|r| EnvironmentProbe {
            direction: Vec3::new(r[0], r[1], r[2]),
            pdf: r[3],
            radiance: Vec3::new(r[4], r[5], r[6]),
            texel: (r[7] >= 0.0).then_some(r[7] as u32),
            lookup_pdf: r[8],
            lookup_radiance: Vec3::new(r[9], r[10], r[11]),
            lookup_uv: Vec2::new(r[12], r[13]),
        })
        .collect())
}
