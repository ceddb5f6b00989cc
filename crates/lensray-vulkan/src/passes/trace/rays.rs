//! The trace shader's ray counter (`TraceGroup`): word 0 counts every ray (camera + shadow)
//! since the call's clear, word 1 keeps the count after the pipeline's first dispatch (reported
//! apart), word 2 the hybrid's lit pre-pass, which the plan records without waiting and the next
//! call reports.

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
    /// The hybrid's lit pre-pass counted rays into word 2, not yet reported.
    prepass_pending: bool,
}

impl RayCounter {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let buffer = Buffer::new(
            ctx,
            "trace ray counter",
            16,
            // TRANSFER_SRC: the first dispatch's count is copied into the second word.
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let host = Buffer::new(
            ctx,
            "trace ray counts",
            16,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            buffer,
            host,
            prepass_pending: false,
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
            &[vk::BufferCopy::default().size(16)],
        );
        &self.host
    }

    /// Records a clear of words 0 and 1 (all rays, the first dispatch's); word 2 keeps the
    /// hybrid's lit pre-pass until the next call reads it.
    pub(crate) fn record_clear(&self, rec: &mut Recorder<'_>) {
        rec.fill_buffer(&self.buffer, 0, 8, 0);
    }

    /// Records a copy of the rays counted so far (the hybrid's lit pre-pass) into word 2, which
    /// the next `accumulate` adds to its report: the plan is not waited for.
    pub(crate) fn record_keep_prepass(&mut self, rec: &mut Recorder<'_>) {
        self.record_copy(rec, 8);
        self.prepass_pending = true;
    }

    /// Keeps the rays counted so far (the pipeline's first dispatch) in word 1.
    pub(super) fn record_copy_first(&self, rec: &mut Recorder<'_>) {
        self.record_copy(rec, 4);
    }

    /// Copies word 0 (rays so far) to the byte offset `to` (4 or 8: the words do not overlap).
    fn record_copy(&self, rec: &mut Recorder<'_>, to: u64) {
        let copy = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(to)
            .size(4);
        rec.copy_buffer(&self.buffer, &self.buffer, &[copy]);
    }

    /// The counts after a call's wait; a pending pre-pass's count is reported once.
    pub(super) fn read(&mut self) -> Result<CountedRays, GpuError> {
        let words = bytemuck::cast_slice::<u8, u32>(self.host.read()?);
        let (all, first, prepass) = (words[0], words[1], words[2]);
        let prepass = if std::mem::take(&mut self.prepass_pending) {
            u64::from(prepass)
        } else {
            0
        };
        Ok(CountedRays {
            all: u64::from(all),
            first: u64::from(first),
            prepass,
        })
    }
}
