//! Frames in flight: each slot has its own command buffer, fence, "image acquired" semaphore,
//! timestamp queries and pick readback, so the host records frame N+1 while the device still
//! runs frame N. A slot is reused only after its fence says its last frame finished.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};
use crate::core::query::QueryPool;

pub(crate) const FRAMES_IN_FLIGHT: usize = 2;
/// Timestamps of a frame: G-buffer start/end, trace start/end, resolve end, frame end, the
/// hybrid plan's start/end (adjacent when the frame makes no plan).
pub(crate) const FRAME_QUERIES: u32 = 8;

pub(crate) struct FrameSlot {
    ctx: Arc<Context>,
    pub cmd: vk::CommandBuffer,
    /// Signalled when the slot's last submission finished (created signalled).
    pub fence: vk::Fence,
    /// Signalled by the acquire of the window image this slot renders to.
    pub image_acquired: vk::Semaphore,
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
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(ctx.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device; used from the viewer's thread only.
        let cmd = unsafe { ctx.device.allocate_command_buffers(&info) }
            .map_err(vk_err("vkAllocateCommandBuffers"))?[0];
        let mut slot = Self {
            ctx: ctx.clone(),
            cmd,
            fence: vk::Fence::null(),
            image_acquired: vk::Semaphore::null(),
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
        };
        let fence_info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        // SAFETY: valid create-infos on a live device; destroyed in Drop.
        unsafe {
            slot.fence = ctx
                .device
                .create_fence(&fence_info, None)
                .map_err(vk_err("vkCreateFence"))?;
            slot.image_acquired = ctx
                .device
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                .map_err(vk_err("vkCreateSemaphore"))?;
        }
        Ok(slot)
    }

    /// Waits until the slot's last frame finished.
    pub(crate) fn wait(&self) -> Result<(), GpuError> {
        self.ctx.counters.waited();
        // SAFETY: our own fence.
        unsafe {
            self.ctx
                .device
                .wait_for_fences(&[self.fence], true, u64::MAX)
        }
        .map_err(vk_err("vkWaitForFences"))
    }
}

impl Drop for FrameSlot {
    fn drop(&mut self) {
        // SAFETY: the viewer waits for the device to be idle before dropping its frames.
        unsafe {
            self.ctx
                .device
                .free_command_buffers(self.ctx.command_pool, &[self.cmd]);
            if self.fence != vk::Fence::null() {
                self.ctx.device.destroy_fence(self.fence, None);
            }
            if self.image_acquired != vk::Semaphore::null() {
                self.ctx.device.destroy_semaphore(self.image_acquired, None);
            }
        }
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
