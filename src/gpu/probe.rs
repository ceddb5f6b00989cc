//! A check of the GLSL mirrors (shaders/sampler.glsl, shaders/camera.glsl): evaluates them for
//! a list of queries with probe.comp so tests can compare against src/sampler/ and src/camera.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use gpu_allocator::MemoryLocation;

use super::buffer::{barrier, Buffer};
use super::conv::GpuCamera;
use super::device::Context;
use super::error::GpuError;
use super::pipeline::Pipeline;
use super::shader;
use crate::camera::Camera;

/// One evaluation request (layout of `Query` in probe.comp).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ProbeQuery {
    pub seed: u32,
    pub pixel_x: u32,
    pub pixel_y: u32,
    pub width: u32,
    pub sample_index: u32,
    pub dim: u32,
    pub hash_input: u32,
    /// `SamplerKind::id`.
    pub sampler_kind: u32,
}

/// What the shader computed (layout of `Result` in probe.comp).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ProbeResult {
    /// `hash_u32(hash_input)`.
    pub hash: u32,
    /// `sample_key(seed, pixel_y * width + pixel_x, sample_index)`.
    pub key: u32,
    /// Bits of `sample_1d(key, dim)`.
    pub sample_bits: u32,
    /// `lens_index(hash_input)`.
    pub lens: u32,
    /// `owen_scramble_reversed(hash_input, seed)`.
    pub scrambled: u32,
    /// `shuffle_index(hash_input, seed)`.
    pub shuffled: u32,
    /// `sobol_reversed(dim % 2, hash_input)`.
    pub sobol: u32,
    /// Bits of `sample_dimension(sampler_kind, seed, pixel_y * width + pixel_x, sample_index,
    /// dim)`.
    pub dimension_bits: u32,
    /// film.x, film.y, lens.x, lens.y of `camera_sample(sampler_kind, seed, pixel, width,
    /// sample_index)`.
    pub camera_sample: [f32; 4],
    /// `generate_ray(camera, film, lens)`: origin (w = 1) and direction (w = 0).
    pub origin: [f32; 4],
    pub direction: [f32; 4],
}

pub(crate) fn run(
    ctx: &Arc<Context>,
    camera: &Camera,
    queries: &[ProbeQuery],
) -> Result<Vec<ProbeResult>, GpuError> {
    let storage = (
        vk::DescriptorType::STORAGE_BUFFER,
        vk::ShaderStageFlags::COMPUTE,
    );
    let uniform = (
        vk::DescriptorType::UNIFORM_BUFFER,
        vk::ShaderStageFlags::COMPUTE,
    );
    let pipeline = Pipeline::compute(ctx, shader::PROBE_COMP, &[storage, storage, uniform], 4)?;
    let input = Buffer::with_data(
        ctx,
        "probe queries",
        bytemuck::cast_slice(queries),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let bytes = (queries.len() * std::mem::size_of::<ProbeResult>()) as u64;
    let output = Buffer::new(
        ctx,
        "probe results",
        bytes,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    let mut cam = Buffer::new(
        ctx,
        "probe camera",
        std::mem::size_of::<GpuCamera>() as u64,
        vk::BufferUsageFlags::UNIFORM_BUFFER,
        MemoryLocation::CpuToGpu,
    )?;
    cam.write(bytemuck::bytes_of(&GpuCamera::new(camera)))?;
    pipeline.bind_buffer(0, vk::DescriptorType::STORAGE_BUFFER, &input);
    pipeline.bind_buffer(1, vk::DescriptorType::STORAGE_BUFFER, &output);
    pipeline.bind_buffer(2, vk::DescriptorType::UNIFORM_BUFFER, &cam);
    let count = queries.len() as u32;
    ctx.submit_and_wait(|cmd| {
        pipeline.bind(cmd, bytemuck::bytes_of(&count));
        // SAFETY: compute pipeline and complete set bound.
        unsafe { ctx.device.cmd_dispatch(cmd, count.div_ceil(64), 1, 1) };
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::HOST,
            vk::AccessFlags::HOST_READ,
        );
        Ok(())
    })?;
    let results: &[ProbeResult] = bytemuck::cast_slice(output.read()?);
    Ok(results[..queries.len()].to_vec())
}
