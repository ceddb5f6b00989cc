//! A check of the GLSL mirror of the tone maps (shaders/include/tonemap.glsl): evaluates them
//! with tonemap.comp for a list of colours so that tests can compare them with
//! lensray-core/src/film/tonemap.rs.

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::pipeline::Pipeline;
use crate::core::shader;
use crate::{GpuError, GpuRenderer};
use lensray_core::interface::{DescriptorSet, TonemapProbeGroup, TonemapProbeSet};

/// `[pbr_neutral(c), agx(c)]` as the device computes them, for each linear colour `c`.
pub fn probe_tonemaps(
    renderer: &GpuRenderer,
    colours: &[[f32; 3]],
) -> Result<Vec<[[f32; 3]; 2]>, GpuError> {
    let ctx = renderer.ctx();
    let pipeline = Pipeline::compute(ctx, TonemapProbeSet::DECL, shader::TONEMAP_COMP)?;
    let queries: Vec<[f32; 4]> = colours.iter().map(|c| [c[0], c[1], c[2], 0.0]).collect();
    let input = Buffer::with_data(
        ctx,
        "tonemap probe queries",
        bytemuck::cast_slice(&queries),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let output = Buffer::new(
        ctx,
        "tonemap probe results",
        (colours.len() * 2 * 16) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    pipeline.bind_group(&TonemapProbeGroup::<Gpu> {
        queries: &input,
        results: &output,
    });
    let count = colours.len() as u32;
    super::run_probe(ctx, &pipeline, count, &output)?;
    let results: &[[f32; 4]] = bytemuck::cast_slice(output.read()?);
    Ok(results
        .chunks_exact(2)
        .take(colours.len())
        .map(|r| [0, 1].map(|i| [r[i][0], r[i][1], r[i][2]]))
        .collect())
}
