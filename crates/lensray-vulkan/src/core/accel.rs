//! Acceleration structures as Vulkan objects, and the commands that build, compact and query
//! them (recorded with the accesses that order them: a structure is read and written through
//! its storage buffer). What the scene builds from them is `scene::accel`.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};
use crate::core::query::QueryPool;
use crate::core::recorder::{Access, Recorder};

/// An acceleration structure and its storage buffer.
pub(crate) struct AccelStruct {
    ctx: Arc<Context>,
    pub handle: vk::AccelerationStructureKHR,
    pub address: vk::DeviceAddress,
    /// Its storage: the recorder orders builds, copies and reads by it.
    pub storage: Buffer,
}

impl AccelStruct {
    pub(crate) fn new(
        ctx: &Arc<Context>,
        name: &str,
        ty: vk::AccelerationStructureTypeKHR,
        size: u64,
    ) -> Result<Self, GpuError> {
        let storage = Buffer::new(
            ctx,
            name,
            size,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            MemoryLocation::GpuOnly,
        )?;
        let info = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(storage.buffer)
            .offset(0)
            .size(size)
            .ty(ty);
        let fns = ctx.accel()?;
        // SAFETY: the buffer is bound, large enough and has the storage usage.
        let handle = unsafe { fns.create_acceleration_structure(&info, None) }
            .map_err(vk_err("vkCreateAccelerationStructureKHR"))?;
        let address_info =
            vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(handle);
        // SAFETY: `handle` was just created on this device.
        let address = unsafe { fns.get_acceleration_structure_device_address(&address_info) };
        Ok(Self {
            ctx: ctx.clone(),
            handle,
            address,
            storage,
        })
    }
}

impl Drop for AccelStruct {
    fn drop(&mut self) {
        // Created only through `Context::accel`, so the functions exist.
        if let Some(fns) = &self.ctx.accel {
            // SAFETY: no submission using it is pending (users wait); destroyed before its
            // buffer.
            unsafe { fns.destroy_acceleration_structure(self.handle, None) };
        }
    }
}

/// The sizes of the structure and of the scratch that building `info` with `counts`
/// primitives per geometry takes.
pub(crate) fn build_sizes(
    ctx: &Context,
    info: &vk::AccelerationStructureBuildGeometryInfoKHR<'_>,
    counts: &[u32],
) -> Result<vk::AccelerationStructureBuildSizesInfoKHR<'static>, GpuError> {
    let fns = ctx.accel()?;
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: `info` describes valid geometry, with one primitive count per geometry.
    unsafe {
        fns.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            info,
            counts,
            &mut sizes,
        )
    };
    Ok(sizes)
}

impl Recorder<'_> {
    /// Builds the structures `infos` name (`built`, their destinations), each from its
    /// `ranges`, after the writes of the structures they read (`read`: a TLAS's BLASes).
    pub(crate) fn build_accels(
        &mut self,
        infos: &[vk::AccelerationStructureBuildGeometryInfoKHR<'_>],
        ranges: &[&[vk::AccelerationStructureBuildRangeInfoKHR]],
        (built, read): (&[&AccelStruct], &[&AccelStruct]),
    ) -> Result<(), GpuError> {
        let fns = self.ctx().accel()?;
        let mut uses: Vec<(vk::Buffer, Access)> = read
            .iter()
            .map(|s| (s.storage.buffer, Access::AccelBuildRead))
            .collect();
        uses.extend(
            built
                .iter()
                .map(|s| (s.storage.buffer, Access::AccelBuildWrite)),
        );
        self.uses(&uses);
        if !infos.is_empty() {
            // SAFETY: every info has a destination, scratch (aligned, disjoint per build) and
            // inputs in live buffers with the build-input usage (the scene's builder).
            unsafe { fns.cmd_build_acceleration_structures(self.cmd(), infos, ranges) };
        }
        Ok(())
    }

    /// Writes the compacted size of each of `structs` (built with ALLOW_COMPACTION) into
    /// `pool`'s queries from 0, after their builds.
    pub(crate) fn write_compacted_sizes(
        &mut self,
        structs: &[&AccelStruct],
        pool: &QueryPool,
    ) -> Result<(), GpuError> {
        let fns = self.ctx().accel()?;
        let uses: Vec<(vk::Buffer, Access)> = structs
            .iter()
            .map(|s| (s.storage.buffer, Access::AccelBuildRead))
            .collect();
        self.uses(&uses);
        let handles: Vec<_> = structs.iter().map(|s| s.handle).collect();
        // SAFETY: the structures were built with ALLOW_COMPACTION, their builds ordered before
        // (the uses above); the pool has a query per structure, reset earlier.
        unsafe {
            fns.cmd_write_acceleration_structures_properties(
                self.cmd(),
                &handles,
                vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
                pool.pool,
                0,
            )
        };
        Ok(())
    }

    /// Copies `src` (built with ALLOW_COMPACTION) into `dst`, of its compacted size.
    pub(crate) fn compact_accel(
        &mut self,
        src: &AccelStruct,
        dst: &AccelStruct,
    ) -> Result<(), GpuError> {
        let fns = self.ctx().accel()?;
        self.uses(&[
            (src.storage.buffer, Access::AccelBuildRead),
            (dst.storage.buffer, Access::AccelBuildWrite),
        ]);
        let copy = vk::CopyAccelerationStructureInfoKHR::default()
            .src(src.handle)
            .dst(dst.handle)
            .mode(vk::CopyAccelerationStructureModeKHR::COMPACT);
        // SAFETY: `src` was built with ALLOW_COMPACTION, `dst` has its queried compacted size.
        unsafe { fns.cmd_copy_acceleration_structure(self.cmd(), &copy) };
        Ok(())
    }
}
