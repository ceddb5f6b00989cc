//! A check of the GLSL mirror of the spectral weighting (shaders/include/spectral.glsl): evaluates
//! it with spectral.comp for a list of queries so that tests can compare it with
//! lensray-core/src/film/spectral.rs.

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::pipeline::Pipeline;
use crate::core::shader;
use crate::{GpuError, GpuRenderer};
use lensray_core::interface::{
    DescriptorSet, SpectralProbeGroup, SpectralProbeSet, SPECTRAL_PROBE_RESULT_FLOATS,
};

/// What the device computes for one query `[u, lambda_nm]` (spectral.glsl).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralProbe {
    /// `sample_wavelength(u)`.
    pub wavelength: f32,
    /// `wavelength_interval(u)`.
    pub interval: u32,
    /// `rgb_weights(wavelength)`, column by column.
    pub sampled_weights: [f32; 9],
    /// `rgb_weights(lambda_nm)`, column by column.
    pub given_weights: [f32; 9],
}

/// Evaluates the GLSL spectral functions on `renderer`'s device for each query `[u, lambda_nm]`.
pub fn probe_spectral(
    renderer: &GpuRenderer,
    queries: &[[f32; 2]],
) -> Result<Vec<SpectralProbe>, GpuError> {
    let ctx = renderer.ctx();
    let pipeline = Pipeline::compute(ctx, SpectralProbeSet::DECL, shader::SPECTRAL_COMP)?;
    let input = Buffer::with_data(
        ctx,
        "spectral probe queries",
        bytemuck::cast_slice(queries),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let stride = SPECTRAL_PROBE_RESULT_FLOATS as usize;
    let output = Buffer::new(
        ctx,
        "spectral probe results",
        (queries.len() * stride * 4) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    pipeline.bind_group(&SpectralProbeGroup::<Gpu> {
        queries: &input,
        results: &output,
    });
    let count = queries.len() as u32;
    super::run_probe(ctx, &pipeline, count, &output)?;
    let floats: &[f32] = bytemuck::cast_slice(output.read()?);
    Ok(floats
        .chunks_exact(stride)
        .take(queries.len())
        .map(|r| SpectralProbe {
            wavelength: r[0],
            interval: r[1] as u32,
            sampled_weights: r[2..11].try_into().expect("9 floats"),
            given_weights: r[11..20].try_into().expect("9 floats"),
        })
        .collect())
}
