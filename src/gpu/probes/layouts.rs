//! Runs shaders/layout_probe.comp: every shared struct of `crate::interface` is written by Rust
//! with a distinct pattern in each 32-bit word, read by the shader through the kind of block the
//! real shaders use (std140 uniform, std430 storage buffer, push constants), and stored back
//! scalar by scalar. A field that GLSL reads at another offset than Rust wrote comes back with
//! another word's pattern.

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;
use gpu_allocator::MemoryLocation;

use crate::gpu::core::buffer::{barrier_to_host, Buffer};
use crate::gpu::core::device::Context;
use crate::gpu::core::error::GpuError;
use crate::gpu::core::pipeline::Pipeline;
use crate::gpu::core::shader;
use crate::interface::glsl::{scalars_of, GlslStruct};
use crate::interface::{
    GpuBvhNode, GpuBvhTriangle, GpuMaterial, RasterPush, ResolvePush, TraceParams, TracePush,
    LAYOUT_PROBE_BINDING_BVH, LAYOUT_PROBE_BINDING_MATERIALS, LAYOUT_PROBE_BINDING_OUT,
    LAYOUT_PROBE_BINDING_PARAMS, LAYOUT_PROBE_BINDING_RASTER, LAYOUT_PROBE_BINDING_RESOLVE,
};

/// What the probe found: how many scalars it compared, and a line per one read elsewhere.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LayoutReport {
    pub scalars_checked: usize,
    pub mismatches: Vec<String>,
}

/// Word k of the value tagged `tag`: a normal float (exponent of 1.0), so no device flushes it.
fn pattern_word(tag: u32, k: usize) -> u32 {
    0x3f80_0000 | (tag << 16) | k as u32
}

fn patterned<S: Pod>(tag: u32) -> S {
    let words: Vec<u32> = (0..std::mem::size_of::<S>() / 4)
        .map(|k| pattern_word(tag, k))
        .collect();
    bytemuck::pod_read_unaligned(bytemuck::cast_slice(&words))
}

/// The words the shader should store for `value`, with the name of each scalar.
fn expected<S: GlslStruct + Pod>(value: &S, out: &mut Vec<(String, u32)>) {
    let words: &[u32] = bytemuck::cast_slice(bytemuck::bytes_of(value));
    for s in scalars_of::<S>() {
        out.push((format!("{}: {}", S::GLSL, s.path), words[s.offset / 4]));
    }
}

pub(crate) fn run(ctx: &Arc<Context>) -> Result<LayoutReport, GpuError> {
    let params: TraceParams = patterned(1);
    let push: TracePush = patterned(2);
    let raster: RasterPush = patterned(3);
    let materials: [GpuMaterial; 2] = [patterned(4), patterned(5)];
    let resolve: ResolvePush = patterned(6);
    let bvh_nodes: [GpuBvhNode; 2] = [patterned(7), patterned(8)];
    let bvh_triangles: [GpuBvhTriangle; 2] = [patterned(9), patterned(10)];
    let mut want = Vec::new();
    expected(&params, &mut want);
    expected(&push, &mut want);
    expected(&raster, &mut want);
    for m in &materials {
        expected(m, &mut want);
    }
    expected(&resolve, &mut want);
    for n in &bvh_nodes {
        expected(n, &mut want);
    }
    for t in &bvh_triangles {
        expected(t, &mut want);
    }

    let (storage, uniform) = (
        vk::DescriptorType::STORAGE_BUFFER,
        vk::DescriptorType::UNIFORM_BUFFER,
    );
    let compute = vk::ShaderStageFlags::COMPUTE;
    let bindings = [
        (LAYOUT_PROBE_BINDING_OUT, storage, compute),
        (LAYOUT_PROBE_BINDING_PARAMS, uniform, compute),
        (LAYOUT_PROBE_BINDING_RASTER, storage, compute),
        (LAYOUT_PROBE_BINDING_MATERIALS, storage, compute),
        (LAYOUT_PROBE_BINDING_RESOLVE, storage, compute),
        (LAYOUT_PROBE_BINDING_BVH, storage, compute),
    ];
    let pipeline = Pipeline::compute(
        ctx,
        shader::LAYOUTS_COMP,
        &bindings,
        std::mem::size_of::<TracePush>() as u32,
    )?;
    let output = Buffer::new(
        ctx,
        "layout probe output",
        (want.len() * 4) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    let params_buffer = Buffer::with_data(
        ctx,
        "layout probe params",
        bytemuck::bytes_of(&params),
        vk::BufferUsageFlags::UNIFORM_BUFFER,
    )?;
    let raster_buffer = Buffer::with_data(
        ctx,
        "layout probe raster",
        bytemuck::bytes_of(&raster),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let material_buffer = Buffer::with_data(
        ctx,
        "layout probe materials",
        bytemuck::cast_slice(&materials),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let resolve_buffer = Buffer::with_data(
        ctx,
        "layout probe resolve",
        bytemuck::bytes_of(&resolve),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    // The block's two arrays back to back (std430: the node array's size is a multiple of 16).
    let mut bvh_bytes = bytemuck::cast_slice::<_, u8>(&bvh_nodes).to_vec();
    bvh_bytes.extend_from_slice(bytemuck::cast_slice(&bvh_triangles));
    let bvh_buffer = Buffer::with_data(
        ctx,
        "layout probe BVH",
        &bvh_bytes,
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    pipeline.bind_buffer(LAYOUT_PROBE_BINDING_BVH, storage, &bvh_buffer);
    pipeline.bind_buffer(LAYOUT_PROBE_BINDING_RESOLVE, storage, &resolve_buffer);
    pipeline.bind_buffer(LAYOUT_PROBE_BINDING_OUT, storage, &output);
    pipeline.bind_buffer(LAYOUT_PROBE_BINDING_PARAMS, uniform, &params_buffer);
    pipeline.bind_buffer(LAYOUT_PROBE_BINDING_RASTER, storage, &raster_buffer);
    pipeline.bind_buffer(LAYOUT_PROBE_BINDING_MATERIALS, storage, &material_buffer);
    ctx.submit_and_wait(|cmd| {
        pipeline.bind(cmd, bytemuck::bytes_of(&push));
        // SAFETY: compute pipeline and complete set bound.
        unsafe { ctx.device.cmd_dispatch(cmd, 1, 1, 1) };
        barrier_to_host(
            ctx,
            cmd,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_WRITE,
        );
        Ok(())
    })?;
    let got: &[u32] = bytemuck::cast_slice(output.read()?);
    let mismatches = want
        .iter()
        .zip(got)
        .filter(|((_, w), g)| w != *g)
        .map(|((name, w), g)| {
            format!(
                "{name}: the shader read {g:#010x} (value {} word {}), Rust wrote {w:#010x} \
                 (value {} word {})",
                (g >> 16) & 0x7f,
                g & 0xffff,
                (w >> 16) & 0x7f,
                w & 0xffff
            )
        })
        .collect();
    Ok(LayoutReport {
        scalars_checked: want.len(),
        mismatches,
    })
}
