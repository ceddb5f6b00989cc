//! Query pools: timestamps and acceleration-structure compacted sizes.

use std::sync::Arc;

use ash::vk;

use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};

pub(crate) struct QueryPool {
    ctx: Arc<Context>,
    pub pool: vk::QueryPool,
    count: u32,
}

impl QueryPool {
    pub(crate) fn new(ctx: &Arc<Context>, ty: vk::QueryType, count: u32) -> Result<Self, GpuError> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(ty)
            .query_count(count);
        // SAFETY: valid create-info on a live device (the extension for the AS query type is
        // enabled).
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }
            .map_err(vk_err("vkCreateQueryPool"))?;
        Ok(Self {
            ctx: ctx.clone(),
            pool,
            count,
        })
    }

    /// Records a reset of every query (needed before the first write).
    pub(crate) fn reset(&self, cmd: vk::CommandBuffer) {
        // SAFETY: command buffer in the recording state, range inside the pool.
        unsafe {
            self.ctx
                .device
                .cmd_reset_query_pool(cmd, self.pool, 0, self.count)
        };
    }

    pub(crate) fn count(&self) -> u32 {
        self.count
    }

    /// Records a timestamp after the work of `stage` of earlier commands.
    pub(crate) fn write(&self, cmd: vk::CommandBuffer, stage: vk::PipelineStageFlags, index: u32) {
        // SAFETY: timestamp pool, index inside it, reset earlier in submission order.
        unsafe {
            self.ctx
                .device
                .cmd_write_timestamp(cmd, stage, self.pool, index)
        };
    }

    /// Every query's 64-bit result; call after the submission that wrote them finished.
    pub(crate) fn results(&self) -> Result<Vec<u64>, GpuError> {
        self.results_of(self.count)
    }

    /// The first `count` queries' 64-bit results; call after the submission that wrote them
    /// finished.
    pub(crate) fn results_of(&self, count: u32) -> Result<Vec<u64>, GpuError> {
        self.results_in(0, count)
    }

    /// The 64-bit results of queries `first..first + count` (clamped to the pool); call after
    /// the submission that wrote them finished.
    pub(crate) fn results_in(&self, first: u32, count: u32) -> Result<Vec<u64>, GpuError> {
        let first = first.min(self.count);
        let count = count.min(self.count - first);
        let mut out = vec![0u64; count as usize];
        if count == 0 {
            return Ok(out);
        }
        self.ctx.counters.read_back(8 * u64::from(count));
        // SAFETY: `out` has one u64 per query of the range, inside the pool; the writing
        // submission has completed.
        unsafe {
            self.ctx.device.get_query_pool_results(
                self.pool,
                first,
                &mut out,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .map_err(vk_err("vkGetQueryPoolResults"))?;
        Ok(out)
    }
}

impl Drop for QueryPool {
    fn drop(&mut self) {
        // SAFETY: no pending submission uses the pool (users wait before dropping).
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}
