//! Buffers with gpu-allocator memory, staging uploads and host readback.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::core::device::Context;
use crate::core::error::{alloc_err, check_allocation, vk_err, GpuError};

/// A buffer and its memory, freed on drop.
/// The least size of a buffer in bytes: descriptors bind whole buffers, so a shader's
/// `.length()` of a shorter array counts this padding too.
pub(crate) const MIN_BUFFER_SIZE: u64 = 16;

pub(crate) struct Buffer {
    ctx: Arc<Context>,
    pub buffer: vk::Buffer,
    allocation: Option<Allocation>,
    pub size: u64,
    /// Device address when created with `SHADER_DEVICE_ADDRESS` usage, else 0.
    pub address: vk::DeviceAddress,
}

impl Buffer {
    pub(crate) fn new(
        ctx: &Arc<Context>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self, GpuError> {
        let size = size.max(MIN_BUFFER_SIZE);
        check_allocation(ctx, name, size)?;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create-info on a live device.
        let buffer =
            unsafe { ctx.device.create_buffer(&info, None) }.map_err(vk_err("vkCreateBuffer"))?;
        let mut this = Self {
            ctx: ctx.clone(),
            buffer,
            allocation: None,
            size,
            address: 0,
        };
        // SAFETY: `buffer` was just created from this device.
        let requirements = unsafe { ctx.device.get_buffer_memory_requirements(buffer) };
        let allocation = ctx
            .allocator()
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(alloc_err(name))?;
        // SAFETY: the allocation satisfies the buffer's requirements and is not bound elsewhere.
        let bound = unsafe {
            ctx.device
                .bind_buffer_memory(buffer, allocation.memory(), allocation.offset())
        };
        this.allocation = Some(allocation);
        bound.map_err(vk_err("vkBindBufferMemory"))?;
        if usage.contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS) {
            let info = vk::BufferDeviceAddressInfo::default().buffer(buffer);
            // SAFETY: created with SHADER_DEVICE_ADDRESS usage and bound to memory allocated
            // with the device-address flag (allocator setting `buffer_device_address`).
            this.address = unsafe { ctx.device.get_buffer_device_address(&info) };
        }
        Ok(this)
    }

    /// A device-local buffer filled with `data` through a staging buffer.
    pub(crate) fn with_data(
        ctx: &Arc<Context>,
        name: &str,
        data: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, GpuError> {
        let buffer = Self::new(
            ctx,
            name,
            data.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        if data.is_empty() {
            return Ok(buffer);
        }
        let mut staging = Self::new(
            ctx,
            &format!("{name} (staging)"),
            data.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(data)?;
        ctx.submit_and_wait(|rec| {
            let region = vk::BufferCopy::default().size(data.len() as u64);
            rec.copy_buffer(&staging, &buffer, &[region]);
            rec.publish(&[&buffer]);
            Ok(())
        })?;
        Ok(buffer)
    }

    /// Copies `data` into a host-visible buffer.
    pub(crate) fn write(&mut self, data: &[u8]) -> Result<(), GpuError> {
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| {
                GpuError::Invalid("write to a buffer that is not host-visible".into())
            })?;
        slice[..data.len()].copy_from_slice(data);
        Ok(())
    }

    /// The contents of a host-visible buffer.
    pub(crate) fn read(&self) -> Result<&[u8], GpuError> {
        self.ctx.counters.read_back(self.size);
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .map(|s| &s[..self.size as usize])
            .ok_or_else(|| GpuError::Invalid("read of a buffer that is not host-visible".into()))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: users wait for their submissions before dropping resources, so the buffer is
        // no longer in use; the memory is freed after the buffer is destroyed.
        unsafe { self.ctx.device.destroy_buffer(self.buffer, None) };
        if let Some(a) = self.allocation.take() {
            let _ = self.ctx.allocator().free(a);
        }
    }
}
