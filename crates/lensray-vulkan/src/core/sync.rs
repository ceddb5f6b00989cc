//! What a frame in flight submits with, each owned and destroyed on drop: a primary command
//! buffer of the device's pool (recorded again once its fence says its last submission
//! finished, `Recorder::begin_again`), a fence and a binary semaphore. Their owners drop them
//! only when no pending submission uses them (the viewer waits for the device first).

use std::sync::Arc;

use ash::vk;

use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};

/// A primary command buffer of the device's command pool, freed on drop.
pub(crate) struct CommandBuffer {
    ctx: Arc<Context>,
    pub handle: vk::CommandBuffer,
}

impl CommandBuffer {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(ctx.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device; used from the viewer's thread only.
        let handle = unsafe { ctx.device.allocate_command_buffers(&info) }
            .map_err(vk_err("vkAllocateCommandBuffers"))?[0];
        Ok(Self {
            ctx: ctx.clone(),
            handle,
        })
    }
}

impl Drop for CommandBuffer {
    fn drop(&mut self) {
        // SAFETY: no pending submission uses it (its owner drops it after the device is idle).
        unsafe {
            self.ctx
                .device
                .free_command_buffers(self.ctx.command_pool, &[self.handle])
        };
    }
}

/// A fence, destroyed on drop.
pub(crate) struct Fence {
    ctx: Arc<Context>,
    pub handle: vk::Fence,
}

impl Fence {
    /// A fence created signalled: the first wait on it returns at once.
    pub(crate) fn signalled(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        // SAFETY: valid create-info on a live device; destroyed on drop.
        let handle =
            unsafe { ctx.device.create_fence(&info, None) }.map_err(vk_err("vkCreateFence"))?;
        Ok(Self {
            ctx: ctx.clone(),
            handle,
        })
    }

    /// Waits until the fence is signalled (a host wait, counted).
    pub(crate) fn wait(&self) -> Result<(), GpuError> {
        self.ctx.counters.waited();
        // SAFETY: our own live fence.
        unsafe {
            self.ctx
                .device
                .wait_for_fences(&[self.handle], true, u64::MAX)
        }
        .map_err(vk_err("vkWaitForFences"))
    }
}

impl Drop for Fence {
    fn drop(&mut self) {
        // SAFETY: no pending submission signals it (its owner drops it after the device is idle).
        unsafe { self.ctx.device.destroy_fence(self.handle, None) };
    }
}

/// A binary semaphore, destroyed on drop.
pub(crate) struct Semaphore {
    ctx: Arc<Context>,
    pub handle: vk::Semaphore,
}

impl Semaphore {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        // SAFETY: default create-info on a live device; destroyed on drop.
        let handle = unsafe {
            ctx.device
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
        }
        .map_err(vk_err("vkCreateSemaphore"))?;
        Ok(Self {
            ctx: ctx.clone(),
            handle,
        })
    }
}

impl Drop for Semaphore {
    fn drop(&mut self) {
        // SAFETY: no pending submission or present uses it (its owner drops it after the
        // device is idle).
        unsafe { self.ctx.device.destroy_semaphore(self.handle, None) };
    }
}
