//! Frames in flight: each slot has its own command buffer, fence, "image acquired" semaphore,
//! timestamp queries and pick readback, so the host records frame N+1 while the device still
//! runs frame N. A slot is reused only after its fence says its last frame finished.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::query::QueryPool;
use crate::core::sync::{CommandBuffer, Fence, Semaphore};

pub(crate) const FRAMES_IN_FLIGHT: usize = 2;
/// Timestamps of a frame: G-buffer start/end, trace start/end, resolve end, frame end, the
/// hybrid plan's start/end (adjacent when the frame makes no plan).
pub(crate) const FRAME_QUERIES: u32 = 8;

pub(crate) struct FrameSlot {
    pub cmd: CommandBuffer,
    /// Signalled when the slot's last submission finished (created signalled).
    pub fence: Fence,
    /// Signalled by the acquire of the window image this slot renders to.
    pub image_acquired: Semaphore,
    pub timestamps: QueryPool,
    /// One f32 of view depth copied from the G-buffer when the frame picks a pixel.
    pub pick: Buffer,
    /// Whether a submission of this slot's was made (its timestamps can be read).
    pub submitted: bool,
    /// Pixel-samples its trace dispatches did (to size later frames from their speed).
    pub trace_work: u64,
    /// Whether its frame made the hybrid's plan (its plan timestamps mean something).
    pub made_plan: bool,
    /// Whether its frame drew the G-buffer or the view pass (its G-buffer time means something).
    pub drew_gbuffer: bool,
    /// egui textures to free once this slot's frame finished.
    pub textures_to_free: Vec<egui::TextureId>,
    /// Host-visible staging of samples traced on the CPU (the CPU path), made on first use.
    pub upload: Option<Buffer>,
}

impl FrameSlot {
    fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        Ok(Self {
            cmd: CommandBuffer::new(ctx)?,
            fence: Fence::signalled(ctx)?,
            image_acquired: Semaphore::new(ctx)?,
            timestamps: QueryPool::new(ctx, vk::QueryType::TIMESTAMP, FRAME_QUERIES)?,
            pick: Buffer::new(
                ctx,
                "preview pick",
                16,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
            submitted: false,
            trace_work: 0,
            made_plan: false,
            drew_gbuffer: false,
            textures_to_free: Vec::new(),
            upload: None,
        })
    }

    /// Waits until the slot's last frame finished.
    pub(crate) fn wait(&self) -> Result<(), GpuError> {
        self.fence.wait()
    }
}

/// The ring of slots.
pub(crate) struct Frames {
    pub slots: Vec<FrameSlot>,
    pub current: usize,
}

impl Frames {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        Ok(Self {
            slots: (0..FRAMES_IN_FLIGHT)
                .map(|_| FrameSlot::new(ctx))
                .collect::<Result<_, _>>()?,
            current: 0,
        })
    }

    pub(crate) fn advance(&mut self) {
        self.current = (self.current + 1) % self.slots.len();
    }
}
