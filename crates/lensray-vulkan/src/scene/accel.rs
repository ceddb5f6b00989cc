//! Acceleration structures: one compacted BLAS per mesh, a TLAS over one instance per mesh with
//! the identity transform (scene positions are world positions). The instance custom index is
//! the mesh's first triangle in the flattened arrays, so a hit's global triangle is
//! `custom index + primitive index`.

use std::sync::Arc;
use std::time::Instant;

use ash::{khr, vk};
use gpu_allocator::MemoryLocation;

use crate::core::buffer::{barrier, Buffer};
use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};
use crate::core::query::QueryPool;
use crate::upload::{FlatScene, MeshRange};

/// An acceleration structure and its storage buffer.
pub(crate) struct AccelStruct {
    ctx: Arc<Context>,
    pub handle: vk::AccelerationStructureKHR,
    pub address: vk::DeviceAddress,
    _buffer: Buffer,
}

impl AccelStruct {
    fn new(
        ctx: &Arc<Context>,
        name: &str,
        ty: vk::AccelerationStructureTypeKHR,
        size: u64,
    ) -> Result<Self, GpuError> {
        let buffer = Buffer::new(
            ctx,
            name,
            size,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            MemoryLocation::GpuOnly,
        )?;
        let info = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(buffer.buffer)
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
            _buffer: buffer,
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

/// The scene's acceleration structures.
pub(crate) struct SceneAccel {
    pub tlas: AccelStruct,
    _blases: Vec<AccelStruct>,
    _instances: Buffer,
    /// GPU time of the BLAS builds + TLAS build (timestamps), and wall-clock time of the whole
    /// build including compaction, nanoseconds.
    pub build_gpu_ns: f64,
    pub build_wall_ns: f64,
    pub blas_bytes: u64,
    pub blas_compacted_bytes: u64,
    /// Bytes the structures keep on the device: compacted BLASes, TLAS and its instances.
    pub device_bytes: u64,
}

fn align_up(x: u64, a: u64) -> u64 {
    x.div_ceil(a) * a
}

/// One 64-byte VkAccelerationStructureInstanceKHR: identity transform, mask 0xFF, culling off.
fn instance_bytes(custom_index: u32, blas_address: u64) -> [u8; 64] {
    let mut out = [0u8; 64];
    let transform: [f32; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    out[..48].copy_from_slice(bytemuck::cast_slice(&transform));
    let custom_and_mask = (custom_index & 0x00ff_ffff) | (0xffu32 << 24);
    let flags = vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE.as_raw() as u8;
    let sbt_and_flags = u32::from(flags) << 24;
    out[48..52].copy_from_slice(&custom_and_mask.to_le_bytes());
    out[52..56].copy_from_slice(&sbt_and_flags.to_le_bytes());
    out[56..64].copy_from_slice(&blas_address.to_le_bytes());
    out
}

/// Builds the scene's acceleration structures: a BLAS per mesh with triangles (built, then
/// compacted), and the TLAS over them.
pub(crate) fn build(
    ctx: &Arc<Context>,
    flat: &FlatScene,
    positions: &Buffer,
    indices: &Buffer,
) -> Result<SceneAccel, GpuError> {
    let start = Instant::now();
    let fns = ctx.accel()?;
    let meshes: Vec<_> = flat
        .meshes
        .iter()
        .filter(|m| m.triangle_count > 0)
        .copied()
        .collect();
    let vertex_count = flat.positions.len() as u32;
    let geometries = blas_geometries(&meshes, vertex_count, positions, indices);
    let mut infos = blas_infos(&geometries);
    let BlasStorage {
        blases,
        scratch,
        bytes: blas_bytes,
    } = create_blases(ctx, fns, &mut infos, &meshes)?;
    let ranges: Vec<[vk::AccelerationStructureBuildRangeInfoKHR; 1]> = meshes
        .iter()
        .map(|m| {
            [vk::AccelerationStructureBuildRangeInfoKHR::default()
                .primitive_count(m.triangle_count)]
        })
        .collect();

    let timestamps = QueryPool::new(ctx, vk::QueryType::TIMESTAMP, 4)?;
    let compact_sizes = if blases.is_empty() {
        None
    } else {
        Some(QueryPool::new(
            ctx,
            vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
            blases.len() as u32,
        )?)
    };
    let queries = BuildQueries {
        timestamps: &timestamps,
        compact_sizes: compact_sizes.as_ref(),
    };
    build_blases(ctx, fns, &infos, &ranges, &blases, &queries)?;
    drop(scratch);

    let (compacted, blas_compacted_bytes) = create_compacted(ctx, compact_sizes.as_ref())?;
    let (instances, instance_bytes_len) = tlas_instances(ctx, &meshes, &compacted)?;
    let (tlas, tlas_size) = build_tlas(
        ctx,
        fns,
        &instances,
        meshes.len() as u32,
        (&blases, &compacted),
        &timestamps,
    )?;
    drop(blases);
    let ticks = timestamps.results()?;
    let build_gpu_ns = ctx.elapsed_ns(ticks[0], ticks[1]) + ctx.elapsed_ns(ticks[2], ticks[3]);
    Ok(SceneAccel {
        tlas,
        _blases: compacted,
        _instances: instances,
        build_gpu_ns,
        build_wall_ns: start.elapsed().as_nanos() as f64,
        blas_bytes,
        blas_compacted_bytes,
        device_bytes: blas_compacted_bytes + tlas_size + instance_bytes_len,
    })
}

/// The bottom-level geometry of each mesh: its triangles in the global vertex and index
/// buffers.
fn blas_geometries(
    meshes: &[MeshRange],
    vertex_count: u32,
    positions: &Buffer,
    indices: &Buffer,
) -> Vec<[vk::AccelerationStructureGeometryKHR<'static>; 1]> {
    meshes
        .iter()
        .map(|m| {
            let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
                .vertex_format(vk::Format::R32G32B32_SFLOAT)
                .vertex_data(vk::DeviceOrHostAddressConstKHR {
                    device_address: positions.address,
                })
                .vertex_stride(16)
                .max_vertex(vertex_count.saturating_sub(1))
                .index_type(vk::IndexType::UINT32)
                .index_data(vk::DeviceOrHostAddressConstKHR {
                    device_address: indices.address + u64::from(m.first_triangle) * 12,
                });
            [vk::AccelerationStructureGeometryKHR::default()
                .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
                .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
                // Alpha-tested triangles reach the shaders' candidate loop.
                .flags(if m.opaque {
                    vk::GeometryFlagsKHR::OPAQUE
                } else {
                    vk::GeometryFlagsKHR::empty()
                })]
        })
        .collect()
}

/// One BLAS build per geometry, traced fast and compactable; destinations and scratch come
/// later (`create_blases`).
fn blas_infos<'a>(
    geometries: &'a [[vk::AccelerationStructureGeometryKHR<'static>; 1]],
) -> Vec<vk::AccelerationStructureBuildGeometryInfoKHR<'a>> {
    let blas_flags = vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE
        | vk::BuildAccelerationStructureFlagsKHR::ALLOW_COMPACTION;
    geometries
        .iter()
        .map(|g| {
            vk::AccelerationStructureBuildGeometryInfoKHR::default()
                .ty(vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL)
                .flags(blas_flags)
                .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
                .geometries(g)
        })
        .collect()
}

/// The BLASes at their build sizes, the scratch buffer their builds share, and their bytes.
struct BlasStorage {
    blases: Vec<AccelStruct>,
    scratch: Buffer,
    bytes: u64,
}

/// Creates a BLAS of its build size for each of `infos` and one scratch buffer with an
/// aligned, disjoint range per build, and points each info at its destination and scratch.
fn create_blases(
    ctx: &Arc<Context>,
    fns: &khr::acceleration_structure::Device,
    infos: &mut [vk::AccelerationStructureBuildGeometryInfoKHR<'_>],
    meshes: &[MeshRange],
) -> Result<BlasStorage, GpuError> {
    let align = ctx.scratch_alignment;
    let mut blases = Vec::with_capacity(meshes.len());
    let mut scratch_offsets = Vec::with_capacity(meshes.len());
    let mut scratch_total = 0u64;
    let mut blas_bytes = 0u64;
    for (info, m) in infos.iter().zip(meshes) {
        let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
        // SAFETY: `info` describes valid geometry; one primitive count per geometry.
        unsafe {
            fns.get_acceleration_structure_build_sizes(
                vk::AccelerationStructureBuildTypeKHR::DEVICE,
                info,
                &[m.triangle_count],
                &mut sizes,
            )
        };
        blases.push(AccelStruct::new(
            ctx,
            "BLAS",
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            sizes.acceleration_structure_size,
        )?);
        blas_bytes += sizes.acceleration_structure_size;
        scratch_offsets.push(scratch_total);
        scratch_total += align_up(sizes.build_scratch_size, align);
    }
    let scratch = Buffer::new(
        ctx,
        "BLAS scratch",
        scratch_total + align,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        MemoryLocation::GpuOnly,
    )?;
    let scratch_base = align_up(scratch.address, align);
    for ((info, blas), offset) in infos.iter_mut().zip(&blases).zip(&scratch_offsets) {
        *info =
            info.dst_acceleration_structure(blas.handle)
                .scratch_data(vk::DeviceOrHostAddressKHR {
                    device_address: scratch_base + offset,
                });
    }
    Ok(BlasStorage {
        blases,
        scratch,
        bytes: blas_bytes,
    })
}

/// The queries of a build: timestamps around the BLAS builds (0, 1) and around compaction and
/// the TLAS build (2, 3), and the BLASes' compacted sizes (none without BLASes).
struct BuildQueries<'a> {
    timestamps: &'a QueryPool,
    compact_sizes: Option<&'a QueryPool>,
}

/// Builds every BLAS in one submission and queries their compacted sizes; waits for it.
fn build_blases(
    ctx: &Context,
    fns: &khr::acceleration_structure::Device,
    infos: &[vk::AccelerationStructureBuildGeometryInfoKHR<'_>],
    ranges: &[[vk::AccelerationStructureBuildRangeInfoKHR; 1]],
    blases: &[AccelStruct],
    queries: &BuildQueries<'_>,
) -> Result<(), GpuError> {
    let range_refs: Vec<&[vk::AccelerationStructureBuildRangeInfoKHR]> =
        ranges.iter().map(|r| &r[..]).collect();
    let timestamps = queries.timestamps;
    let handles: Vec<_> = blases.iter().map(|b| b.handle).collect();
    ctx.submit_and_wait(|cmd| {
        timestamps.reset(cmd);
        if let Some(q) = queries.compact_sizes {
            q.reset(cmd);
        }
        timestamps.write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 0);
        if !infos.is_empty() {
            // SAFETY: every info has a destination, scratch inside `scratch` (aligned, disjoint
            // per build) and inputs in live buffers with the build-input usage.
            unsafe { fns.cmd_build_acceleration_structures(cmd, infos, &range_refs) };
        }
        build_to_build_barrier(ctx, cmd);
        if let Some(q) = queries.compact_sizes {
            // SAFETY: the structures were built with ALLOW_COMPACTION; the barrier above
            // orders the builds before the query.
            unsafe {
                fns.cmd_write_acceleration_structures_properties(
                    cmd,
                    &handles,
                    vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
                    q.pool,
                    0,
                )
            };
        }
        timestamps.write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
        Ok(())
    })
}

/// A structure of its compacted size for each BLAS (the queried sizes), and their bytes.
fn create_compacted(
    ctx: &Arc<Context>,
    compact_sizes: Option<&QueryPool>,
) -> Result<(Vec<AccelStruct>, u64), GpuError> {
    let sizes = match compact_sizes {
        Some(q) => q.results()?,
        None => Vec::new(),
    };
    let mut compacted = Vec::with_capacity(sizes.len());
    let mut blas_compacted_bytes = 0;
    for &size in &sizes {
        blas_compacted_bytes += size;
        compacted.push(AccelStruct::new(
            ctx,
            "BLAS (compacted)",
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            size,
        )?);
    }
    Ok((compacted, blas_compacted_bytes))
}

/// The TLAS's instance buffer, one instance per mesh with triangles (at least one
/// instance's bytes), and its length in bytes.
fn tlas_instances(
    ctx: &Arc<Context>,
    meshes: &[MeshRange],
    compacted: &[AccelStruct],
) -> Result<(Buffer, u64), GpuError> {
    let mut instance_data = Vec::with_capacity(64 * meshes.len().max(1));
    for (m, blas) in meshes.iter().zip(compacted) {
        instance_data.extend_from_slice(&instance_bytes(m.first_triangle, blas.address));
    }
    instance_data.resize(instance_data.len().max(64), 0);
    let instances = Buffer::with_data(
        ctx,
        "TLAS instances",
        &instance_data,
        vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
    )?;
    Ok((instances, instance_data.len() as u64))
}

/// Creates the TLAS over `instance_count` instances and, in one submission, copies each of
/// `blases` into its compacted structure and builds the TLAS; waits for it. Returns the TLAS
/// and its size.
fn build_tlas(
    ctx: &Arc<Context>,
    fns: &khr::acceleration_structure::Device,
    instances: &Buffer,
    instance_count: u32,
    (blases, compacted): (&[AccelStruct], &[AccelStruct]),
    timestamps: &QueryPool,
) -> Result<(AccelStruct, u64), GpuError> {
    let align = ctx.scratch_alignment;
    let instance_geometry = [vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::INSTANCES)
        .geometry(vk::AccelerationStructureGeometryDataKHR {
            instances: vk::AccelerationStructureGeometryInstancesDataKHR::default()
                .array_of_pointers(false)
                .data(vk::DeviceOrHostAddressConstKHR {
                    device_address: instances.address,
                }),
        })
        .flags(vk::GeometryFlagsKHR::OPAQUE)];
    let mut tlas_info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(vk::AccelerationStructureTypeKHR::TOP_LEVEL)
        .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
        .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
        .geometries(&instance_geometry);
    let mut tlas_sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: valid instance geometry description.
    unsafe {
        fns.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            &tlas_info,
            &[instance_count],
            &mut tlas_sizes,
        )
    };
    let tlas = AccelStruct::new(
        ctx,
        "TLAS",
        vk::AccelerationStructureTypeKHR::TOP_LEVEL,
        tlas_sizes.acceleration_structure_size,
    )?;
    let tlas_scratch = Buffer::new(
        ctx,
        "TLAS scratch",
        tlas_sizes.build_scratch_size + align,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        MemoryLocation::GpuOnly,
    )?;
    tlas_info = tlas_info
        .dst_acceleration_structure(tlas.handle)
        .scratch_data(vk::DeviceOrHostAddressKHR {
            device_address: align_up(tlas_scratch.address, align),
        });
    let tlas_range =
        [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(instance_count)];
    ctx.submit_and_wait(|cmd| {
        timestamps.write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 2);
        record_compaction(fns, cmd, blases, compacted);
        build_to_build_barrier(ctx, cmd);
        // SAFETY: the instances reference the compacted BLASes, whose copies the barrier
        // above orders before this build; scratch is aligned and large enough.
        unsafe { fns.cmd_build_acceleration_structures(cmd, &[tlas_info], &[&tlas_range]) };
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
            vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR,
        );
        timestamps.write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 3);
        Ok(())
    })?;
    drop(tlas_scratch);
    Ok((tlas, tlas_sizes.acceleration_structure_size))
}

/// Records a compacting copy of each of `blases` into its structure in `compacted`.
fn record_compaction(
    fns: &khr::acceleration_structure::Device,
    cmd: vk::CommandBuffer,
    blases: &[AccelStruct],
    compacted: &[AccelStruct],
) {
    for (src, dst) in blases.iter().zip(compacted) {
        let copy = vk::CopyAccelerationStructureInfoKHR::default()
            .src(src.handle)
            .dst(dst.handle)
            .mode(vk::CopyAccelerationStructureModeKHR::COMPACT);
        // SAFETY: `src` was built with ALLOW_COMPACTION, `dst` has the queried size.
        unsafe { fns.cmd_copy_acceleration_structure(cmd, &copy) };
    }
}

/// Orders acceleration-structure writes (builds, compaction copies) before later builds and
/// copies that read them.
fn build_to_build_barrier(ctx: &Context, cmd: vk::CommandBuffer) {
    barrier(
        ctx,
        cmd,
        vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
        vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
        vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
        vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR,
    );
}
