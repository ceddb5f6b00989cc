//! The ray-tracing pipeline's functions and properties, and its shader binding table: the
//! records `vkCmdTraceRaysKHR` takes its ray generation, miss and hit stages from, laid out as
//! the device's properties ask (each handle aligned to `shaderGroupHandleAlignment`, each
//! region's start to `shaderGroupBaseAlignment`).

use std::sync::Arc;

use ash::{khr, vk};
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};

/// VK_KHR_ray_tracing_pipeline's functions and the properties its table is laid out by.
pub(crate) struct RayTracing {
    pub fns: khr::ray_tracing_pipeline::Device,
    /// Bytes of a shader group's handle.
    pub handle_size: u32,
    /// What a record's start is a multiple of.
    pub handle_alignment: u32,
    /// What a region's start is a multiple of.
    pub base_alignment: u32,
}

impl RayTracing {
    /// The functions of `device`, opened with the extension, and the properties of `physical`.
    pub(crate) fn load(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        device: &ash::Device,
    ) -> Self {
        let mut props = vk::PhysicalDeviceRayTracingPipelinePropertiesKHR::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut props);
        // SAFETY: the device was opened with the extension; a query only.
        unsafe { instance.get_physical_device_properties2(physical, &mut props2) };
        Self {
            fns: khr::ray_tracing_pipeline::Device::new(instance, device),
            handle_size: props.shader_group_handle_size,
            handle_alignment: props.shader_group_handle_alignment.max(1),
            base_alignment: props.shader_group_base_alignment.max(1),
        }
    }
}

/// How many shader groups of a pipeline each region holds, in the pipeline's group order: the
/// ray generation group, then the miss groups, then the hit groups.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct GroupCounts {
    pub misses: u32,
    pub hits: u32,
}

/// A pipeline's shader binding table: one host-visible buffer and its regions.
pub(crate) struct ShaderBindingTable {
    _buffer: Buffer,
    pub raygen: vk::StridedDeviceAddressRegionKHR,
    pub miss: vk::StridedDeviceAddressRegionKHR,
    pub hit: vk::StridedDeviceAddressRegionKHR,
    /// None: the pipeline has no callable stages.
    pub callable: vk::StridedDeviceAddressRegionKHR,
}

impl ShaderBindingTable {
    /// The table of `pipeline`, whose groups are one ray generation group, then `counts`.
    pub(crate) fn new(
        ctx: &Arc<Context>,
        pipeline: vk::Pipeline,
        counts: GroupCounts,
    ) -> Result<Self, GpuError> {
        let rt = ctx.ray_tracing()?;
        let layout = TableLayout::of(rt, counts);
        let group_count = 1 + counts.misses + counts.hits;
        let handle_size = rt.handle_size as usize;
        // SAFETY: `pipeline` is a live ray-tracing pipeline with `group_count` groups; the size
        // is that many handles.
        let handles = unsafe {
            rt.fns.get_ray_tracing_shader_group_handles(
                pipeline,
                0,
                group_count,
                group_count as usize * handle_size,
            )
        }
        .map_err(vk_err("vkGetRayTracingShaderGroupHandlesKHR"))?;
        // Room to move the table's start up to the base alignment (a buffer's address need
        // not be that aligned).
        let base = u64::from(rt.base_alignment);
        let mut buffer = Buffer::new(
            ctx,
            "shader binding table",
            layout.bytes + base,
            vk::BufferUsageFlags::SHADER_BINDING_TABLE_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            MemoryLocation::CpuToGpu,
        )?;
        let start = buffer.address.next_multiple_of(base);
        let skip = (start - buffer.address) as usize;
        let mut data = vec![0u8; skip + layout.bytes as usize];
        for (group, handle) in handles.chunks_exact(handle_size).enumerate() {
            let at = skip + layout.record_offset(group as u32) as usize;
            data[at..at + handle_size].copy_from_slice(handle);
        }
        // Host writes are visible to the device's reads of any later submission.
        buffer.write(&data)?;
        let region = |offset: u64, stride: u64, size: u64| vk::StridedDeviceAddressRegionKHR {
            device_address: start + offset,
            stride,
            size,
        };
        Ok(Self {
            _buffer: buffer,
            raygen: region(0, layout.raygen_size, layout.raygen_size),
            miss: region(
                layout.miss_offset,
                layout.record,
                layout.record * u64::from(counts.misses),
            ),
            hit: region(
                layout.hit_offset,
                layout.record,
                layout.record * u64::from(counts.hits),
            ),
            callable: vk::StridedDeviceAddressRegionKHR::default(),
        })
    }
}

/// Where the regions and records lie in a table, in bytes from its start.
#[derive(Debug, PartialEq, Eq)]
struct TableLayout {
    /// A miss or hit record: the handle, rounded up to the handle alignment.
    record: u64,
    /// The ray generation region: one record, rounded up to the base alignment (its stride
    /// is its size).
    raygen_size: u64,
    miss_offset: u64,
    misses: u64,
    hit_offset: u64,
    bytes: u64,
}

impl TableLayout {
    fn of(rt: &RayTracing, counts: GroupCounts) -> Self {
        Self::with(
            (rt.handle_size, rt.handle_alignment, rt.base_alignment),
            counts,
        )
    }

    fn with((handle, handle_align, base_align): (u32, u32, u32), counts: GroupCounts) -> Self {
        let record = u64::from(handle).next_multiple_of(u64::from(handle_align));
        let base = u64::from(base_align);
        let raygen_size = record.next_multiple_of(base);
        let miss_offset = raygen_size;
        let hit_offset = (miss_offset + record * u64::from(counts.misses)).next_multiple_of(base);
        Self {
            record,
            raygen_size,
            miss_offset,
            misses: u64::from(counts.misses),
            hit_offset,
            bytes: hit_offset + record * u64::from(counts.hits),
        }
    }

    /// Where the record of the pipeline's group `group` starts.
    fn record_offset(&self, group: u32) -> u64 {
        match u64::from(group) {
            0 => 0,
            g if g <= self.misses => self.miss_offset + (g - 1) * self.record,
            g => self.hit_offset + (g - 1 - self.misses) * self.record,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_start_at_the_base_alignment_and_records_at_the_handle_alignment() {
        let counts = GroupCounts { misses: 2, hits: 2 };
        // NVIDIA's properties: 32-byte handles, 32-byte records, regions at 64 bytes.
        let layout = TableLayout::with((32, 32, 64), counts);
        assert_eq!(layout.record, 32);
        assert_eq!(layout.raygen_size, 64);
        assert_eq!((layout.miss_offset, layout.hit_offset), (64, 128));
        assert_eq!(layout.bytes, 192);
        let offsets: Vec<u64> = (0..5).map(|g| layout.record_offset(g)).collect();
        assert_eq!(offsets, [0, 64, 96, 128, 160]);
        // A handle smaller than its alignment: records keep the alignment.
        let layout = TableLayout::with((20, 32, 64), GroupCounts { misses: 3, hits: 1 });
        assert_eq!(layout.record, 32);
        assert_eq!(layout.hit_offset, 192);
        assert_eq!(layout.record_offset(3), 128);
        assert_eq!(layout.record_offset(4), 192);
    }
}
