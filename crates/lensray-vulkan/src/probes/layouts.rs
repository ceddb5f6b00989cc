//! Runs shaders/probes/layouts.comp: every shared struct of `lensray_core::interface` (the list
//! `shared_structs()`, from which the shader's blocks are generated too) is written by Rust with
//! a distinct pattern in each 32-bit word, read by the shader through the kind of block the real
//! shaders use (std140 uniform, std430 storage buffer, push constants), and stored back scalar by
//! scalar. A field that GLSL reads at another offset than Rust wrote comes back with another
//! word's pattern.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::recorder::Access;
use crate::core::shader;
use lensray_core::interface::glsl::{
    layout_probe_reads, ProbeBlock, ProbeRead, SharedStruct, LAYOUT_PROBE_BINDING_OUT,
};
use lensray_core::interface::shared_structs;

/// What the probe found: the blocks it read, how many scalars it compared, and a line per one
/// read elsewhere.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LayoutReport {
    /// In the order the shader read them.
    pub blocks: Vec<ProbedBlock>,
    pub scalars_checked: usize,
    pub mismatches: Vec<String>,
}

/// A block the probe read: `copies` values of the shared struct `rust` (`glsl` in GLSL), each
/// of `scalars` scalars.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProbedBlock {
    pub rust: &'static str,
    pub glsl: &'static str,
    pub block: ProbeBlock,
    pub copies: usize,
    pub scalars: usize,
}

/// Word k of the value tagged `tag` (below 128): a normal float (exponent of 1.0), so no device
/// flushes it.
fn pattern_word(tag: u32, k: usize) -> u32 {
    0x3f80_0000 | (tag << 16) | k as u32
}

/// Fills the probe's output with this before the dispatch: a word the shader did not store.
const UNWRITTEN: u32 = 0xffff_ffff;

/// Runs the layout probe on `ctx`'s device: writes every shared struct's patterns, lets the
/// shader read them back and compares each scalar.
pub(crate) fn run(ctx: &Arc<Context>) -> Result<LayoutReport, GpuError> {
    let structs = shared_structs();
    let reads = layout_probe_reads(&structs);
    let values = probe_values(&structs, &reads)?;
    let inputs = probe_inputs(ctx, &structs, &reads, &values.contents)?;
    check_limits(ctx, &inputs.bindings, inputs.push.len())?;
    let got = dispatch(ctx, &inputs, values.want.len())?;
    let mismatches = mismatches(&values.want, &got);
    Ok(LayoutReport {
        blocks: values.blocks,
        scalars_checked: values.want.len(),
        mismatches,
    })
}

/// What Rust writes for the probe: per block its values' bytes, and in the shader's order
/// each scalar's name and word.
struct ProbeValues {
    want: Vec<(String, u32)>,
    blocks: Vec<ProbedBlock>,
    contents: Vec<Vec<u8>>,
}

/// The values of every read, each `copies` values of its struct with its own tag; an error
/// when there are more values than the patterns tell apart.
fn probe_values(structs: &[SharedStruct], reads: &[ProbeRead]) -> Result<ProbeValues, GpuError> {
    let mut want: Vec<(String, u32)> = Vec::new();
    let mut blocks = Vec::new();
    let mut contents: Vec<Vec<u8>> = Vec::new();
    let mut tag = 0;
    for read in reads {
        let s = &structs[read.structure];
        let mut bytes = Vec::with_capacity(s.size * read.copies);
        for copy in 0..read.copies {
            tag += 1;
            let words: Vec<u32> = (0..s.size / 4).map(|k| pattern_word(tag, k)).collect();
            for scalar in &s.scalars {
                let at = match read.block {
                    ProbeBlock::PushConstant => String::from("push constants"),
                    block => format!("{} block [{copy}]", block.short_name()),
                };
                want.push((
                    format!("{} ({}) in {at}: {}", s.rust, s.glsl, scalar.path),
                    words[scalar.offset / 4],
                ));
            }
            bytes.extend_from_slice(bytemuck::cast_slice(&words));
        }
        blocks.push(ProbedBlock {
            rust: s.rust,
            glsl: s.glsl,
            block: read.block,
            copies: read.copies,
            scalars: s.scalars.len(),
        });
        contents.push(bytes);
    }
    if tag >= 128 {
        return Err(GpuError::Invalid(format!(
            "layout probe: {tag} values, more than its patterns tell apart (127)"
        )));
    }
    Ok(ProbeValues {
        want,
        blocks,
        contents,
    })
}

/// The probe pipeline's bindings (the output first), a buffer per descriptor block with its
/// binding and type, and the push constants' bytes.
struct ProbeInputs<'a> {
    bindings: Vec<(u32, vk::DescriptorType, vk::ShaderStageFlags)>,
    buffers: Vec<(u32, vk::DescriptorType, Buffer)>,
    push: &'a [u8],
}

/// Uploads each descriptor block's `contents` to a buffer of its kind; the push-constant
/// block's bytes are pushed instead.
fn probe_inputs<'a>(
    ctx: &Arc<Context>,
    structs: &[SharedStruct],
    reads: &[ProbeRead],
    contents: &'a [Vec<u8>],
) -> Result<ProbeInputs<'a>, GpuError> {
    let compute = vk::ShaderStageFlags::COMPUTE;
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let mut bindings = vec![(LAYOUT_PROBE_BINDING_OUT, storage, compute)];
    let mut inputs = Vec::new();
    let mut push: &[u8] = &[];
    for (read, bytes) in reads.iter().zip(contents) {
        let (ty, usage) = match read.block {
            ProbeBlock::PushConstant => {
                push = bytes;
                continue;
            }
            ProbeBlock::Uniform => (
                vk::DescriptorType::UNIFORM_BUFFER,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
            ProbeBlock::Storage => (storage, vk::BufferUsageFlags::STORAGE_BUFFER),
        };
        let binding = read.binding.ok_or_else(|| {
            GpuError::Invalid("layout probe: a descriptor block without a binding".into())
        })?;
        let name = format!("layout probe {}", structs[read.structure].rust);
        bindings.push((binding, ty, compute));
        inputs.push((binding, ty, Buffer::with_data(ctx, &name, bytes, usage)?));
    }
    Ok(ProbeInputs {
        bindings,
        buffers: inputs,
        push,
    })
}

/// Runs the probe shader once over `inputs` and reads back what it stored: `scalars` words,
/// then the count it stored (`UNWRITTEN` where it stored nothing).
fn dispatch(
    ctx: &Arc<Context>,
    inputs: &ProbeInputs<'_>,
    scalars: usize,
) -> Result<Vec<u32>, GpuError> {
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let push = inputs.push;
    let pipeline = Pipeline::compute_with_bindings(
        ctx,
        shader::LAYOUTS_COMP,
        &inputs.bindings,
        push.len() as u32,
    )?;
    // The scalars, then the count the shader stored.
    let mut output = Buffer::new(
        ctx,
        "layout probe output",
        ((scalars + 1) * 4) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    output.write(bytemuck::cast_slice(&vec![UNWRITTEN; scalars + 1]))?;
    pipeline.write_buffer(LAYOUT_PROBE_BINDING_OUT, storage, &output);
    for (binding, ty, buffer) in &inputs.buffers {
        pipeline.write_buffer(*binding, *ty, buffer);
    }
    ctx.submit_and_wait(|rec| {
        rec.dispatch(
            &pipeline,
            push,
            [1, 1, 1],
            &[(output.buffer, Access::ComputeWrite)],
        );
        rec.read_on_host(&[&output]);
        Ok(())
    })?;
    let got: &[u32] = bytemuck::cast_slice(output.read()?);
    Ok(got.to_vec())
}

/// A line per scalar the shader read with another word than Rust wrote, and one when the
/// count it stored is not the number of scalars.
fn mismatches(want: &[(String, u32)], got: &[u32]) -> Vec<String> {
    let mut mismatches: Vec<String> = want
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
    let stored = got[want.len()];
    if stored as usize != want.len() {
        mismatches.push(format!(
            "the shader stored {stored} scalars (0xffffffff: no count), Rust expected {}",
            want.len()
        ));
    }
    mismatches
}

/// The probe's one set holds a block per shared struct: fail clearly on a device with fewer
/// descriptors per stage (Vulkan guarantees 4 storage buffers, 12 uniform buffers, 128 bytes
/// of push constants) rather than with a validation error.
fn check_limits(
    ctx: &Context,
    bindings: &[(u32, vk::DescriptorType, vk::ShaderStageFlags)],
    push_size: usize,
) -> Result<(), GpuError> {
    let limits = ctx.limits();
    let count = |ty| bindings.iter().filter(|b| b.1 == ty).count() as u32;
    let storage = count(vk::DescriptorType::STORAGE_BUFFER);
    let uniform = count(vk::DescriptorType::UNIFORM_BUFFER);
    if storage > limits.max_per_stage_descriptor_storage_buffers
        || uniform > limits.max_per_stage_descriptor_uniform_buffers
        || storage + uniform > limits.max_per_stage_resources
        || push_size as u32 > limits.max_push_constants_size
    {
        return Err(GpuError::Invalid(format!(
            "layout probe: needs {storage} storage buffers, {uniform} uniform buffers and \
             {push_size} bytes of push constants in a compute stage; the device has {}, {} and {}",
            limits.max_per_stage_descriptor_storage_buffers,
            limits.max_per_stage_descriptor_uniform_buffers,
            limits.max_push_constants_size
        )));
    }
    Ok(())
}
