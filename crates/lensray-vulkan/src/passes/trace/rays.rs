//! The trace shader's ray counter (`TraceGroup`), three 64-bit counts as (low, high) pairs of
//! words: count 0 is every ray (camera + shadow) since the call's clear, count 1 keeps it after
//! the pipeline's first dispatch (reported apart), count 2 the hybrid's lit pre-pass, which the
//! plan records without waiting and the next call reports.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::recorder::Recorder;

/// What the counter held after a call's wait.
pub(super) struct CountedRays {
    /// Every ray of the call.
    pub(super) all: u64,
    /// The rays of the pipeline's first dispatch (when the call made it).
    pub(super) first: u64,
    /// The rays of a lit pre-pass not yet reported (0 when none).
    pub(super) prepass: u64,
}

pub(crate) struct RayCounter {
    /// Device-local: every workgroup of every dispatch adds to it.
    buffer: Buffer,
    /// Host-visible: the counts copied at the end of a call, read after its wait.
    host: Buffer,
    /// The hybrid's lit pre-pass counted rays into count 2, not yet reported.
    prepass_pending: bool,
    /// What a call's clear sets the low word of count 0 to (tests start near 2^32 to see the
    /// carry); reports subtract it.
    pub(crate) start: u32,
}

/// Bytes of one count: two words.
const COUNT: u64 = 8;
/// Bytes of the buffer: three counts.
const BYTES: u64 = 3 * COUNT;

impl RayCounter {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let buffer = Buffer::new(
            ctx,
            "trace ray counter",
            BYTES,
            // TRANSFER_SRC: the first dispatch's count is copied into the second word.
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let host = Buffer::new(
            ctx,
            "trace ray counts",
            BYTES,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            buffer,
            host,
            prepass_pending: false,
            start: 0,
        })
    }

    /// The counter's buffer (bound to the pipelines).
    pub(crate) fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    /// Records the copy of the counts to host-visible memory, at the end of a call; returns
    /// the buffer the host reads (`read`) after the call's wait.
    pub(super) fn record_read_back(&self, rec: &mut Recorder<'_>) -> &Buffer {
        rec.copy_buffer(
            &self.buffer,
            &self.host,
            &[vk::BufferCopy::default().size(BYTES)],
        );
        &self.host
    }

    /// Records a clear of counts 0 and 1 (all rays, the first dispatch's); count 2 keeps the
    /// hybrid's lit pre-pass until the next call reads it.
    pub(crate) fn record_clear(&self, rec: &mut Recorder<'_>) {
        rec.fill_buffer(&self.buffer, 0, 2 * COUNT, 0);
        if self.start != 0 {
            rec.fill_buffer(&self.buffer, 0, 4, self.start);
        }
    }

    /// Records a copy of the rays counted so far (the hybrid's lit pre-pass) into count 2,
    /// which the next `accumulate` adds to its report: the plan is not waited for.
    pub(crate) fn record_keep_prepass(&mut self, rec: &mut Recorder<'_>) {
        self.record_copy(rec, 2 * COUNT);
        self.prepass_pending = true;
    }

    /// Keeps the rays counted so far (the pipeline's first dispatch) in count 1.
    pub(super) fn record_copy_first(&self, rec: &mut Recorder<'_>) {
        self.record_copy(rec, COUNT);
    }

    /// Copies count 0 (rays so far) to the byte offset `to` (a later count: no overlap).
    fn record_copy(&self, rec: &mut Recorder<'_>, to: u64) {
        let copy = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(to)
            .size(COUNT);
        rec.copy_buffer(&self.buffer, &self.buffer, &[copy]);
    }

    /// The counts after a call's wait; a pending pre-pass's count is reported once.
    pub(super) fn read(&mut self) -> Result<CountedRays, GpuError> {
        let words = bytemuck::cast_slice::<u8, u32>(self.host.read()?);
        let count = |i: usize| u64::from(words[2 * i]) | (u64::from(words[2 * i + 1]) << 32);
        let start = u64::from(self.start);
        let prepass = if std::mem::take(&mut self.prepass_pending) {
            count(2).saturating_sub(start)
        } else {
            0
        };
        Ok(CountedRays {
            all: count(0) - start,
            first: count(1).saturating_sub(start),
            prepass,
        })
    }
}
