//! A check of the GLSL mirrors (shaders/include/sampler.glsl, shaders/include/camera.glsl): evaluates them for
//! a list of queries with probe.comp so tests can compare against lensray-core/src/sampler/ and lensray-core/src/camera.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::shader;
use crate::passes::aperture::ApertureTable;
use crate::passes::lens::LensBuffer;
use lensray_core::camera::Camera;
use lensray_core::interface::{
    ApertureGroup, DescriptorSet, GpuCamera, LensGroup, MirrorProbeGroup, MirrorProbeSet,
};
pub use lensray_core::interface::{ProbeQuery, ProbeResult};

pub(crate) fn run(
    ctx: &Arc<Context>,
    camera: &Camera,
    queries: &[ProbeQuery],
) -> Result<Vec<ProbeResult>, GpuError> {
    let pipeline = Pipeline::compute(ctx, MirrorProbeSet::DECL, shader::MIRRORS_COMP)?;
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
    cam.write(bytemuck::bytes_of(&crate::upload::gpu_camera(camera)))?;
    pipeline.bind_group(&MirrorProbeGroup::<Gpu> {
        queries: &input,
        results: &output,
        camera: &cam,
    });
    let aperture = ApertureTable::of(ctx, camera)?;
    pipeline.bind_group(&ApertureGroup::<Gpu> {
        aperture_table: &aperture,
    });
    let lens = LensBuffer::of(ctx, camera)?;
    pipeline.bind_group(&LensGroup::<Gpu> { lens: &lens });
    let count = queries.len() as u32;
    super::run_probe(ctx, &pipeline, count, &output)?;
    let results: &[ProbeResult] = bytemuck::cast_slice(output.read()?);
    Ok(results[..queries.len()].to_vec())
}
