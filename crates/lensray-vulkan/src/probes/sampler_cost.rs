//! How long the GPU takes to generate a render's camera samples alone (shaders/probes/sampler_cost.comp:
//! the compute pass's sample loop without tracing), to compare with the whole pass's time.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::query::QueryPool;
use crate::core::recorder::Access;
use crate::core::shader;
use lensray_core::interface::{
    DescriptorSet, SamplerCostGroup, SamplerCostPush, SamplerCostSet, TRACE_GROUP_SIZE as GROUP,
};
use lensray_core::settings::RenderSettings;

/// GPU milliseconds of generating `settings.spp` camera samples for each pixel of a
/// `width` x `height` image, one dispatch, timed with timestamps after an untimed warm-up
/// dispatch (drivers may compile on first use).
pub(crate) fn run(
    ctx: &Arc<Context>,
    width: u32,
    height: u32,
    settings: &RenderSettings,
) -> Result<f64, GpuError> {
    let pipeline = Pipeline::compute(ctx, SamplerCostSet::DECL, shader::SAMPLER_COST_COMP)?;
    let sums = Buffer::new(
        ctx,
        "sample sums",
        u64::from(width) * u64::from(height) * 16,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )?;
    pipeline.bind_group(&SamplerCostGroup::<Gpu> { sums: &sums });
    let timestamps = QueryPool::new(ctx, vk::QueryType::TIMESTAMP, 2)?;
    let push = SamplerCostPush {
        width,
        height,
        seed: settings.seed,
        sampler_kind: settings.sampler.id(),
        spp: settings.spp,
    };
    for _warm_up_then_timed in 0..2 {
        ctx.submit_and_wait(|rec| {
            rec.reset_queries(&timestamps);
            rec.timestamp(&timestamps, vk::PipelineStageFlags::TOP_OF_PIPE, 0);
            let groups = [width.div_ceil(GROUP), height.div_ceil(GROUP), 1];
            let uses = [(sums.buffer, Access::ComputeWrite)];
            rec.dispatch(&pipeline, bytemuck::bytes_of(&push), groups, &uses);
            rec.timestamp(&timestamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
            Ok(())
        })?;
    }
    let ticks = timestamps.results()?;
    Ok(ctx.elapsed_ns(ticks[0], ticks[1]) * 1e-6)
}
