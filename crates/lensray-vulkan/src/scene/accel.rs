//! Acceleration structures: one compacted BLAS per mesh range (a mesh's double-sided and its
//! single-sided triangles, `MeshRange`), a TLAS over one instance per range with
//! the identity transform (scene positions are world positions). The instance custom index is
//! the mesh's first triangle in the flattened arrays, so a hit's global triangle is
//! `custom index + primitive index`.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::accel::{build_sizes, AccelStruct};
use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::query::QueryPool;
use crate::upload::{FlatScene, MeshRange};

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

/// One 64-byte VkAccelerationStructureInstanceKHR: identity transform, mask 0xFF, culling off
/// unless `single_sided`. A single-sided mesh's instance culls the triangles a ray meets from
/// behind when the ray asks for it (gl_RayFlagsCullBackFacingTrianglesEXT, which the shaders set
/// only for scenes with single-sided surfaces). Vulkan's default facing, front = counter-clockwise
/// as the ray origin sees the triangle in a right-handed frame (clockwise in a left-handed one),
/// is glTF's: the instance keeps it, and the tests of single-sided quads check it against the
/// CPU reference's [`lensray_core::reference::is_back_face`].
fn instance_bytes(custom_index: u32, blas_address: u64, single_sided: bool) -> [u8; 64] {
    let mut out = [0u8; 64];
    let transform: [f32; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    out[..48].copy_from_slice(bytemuck::cast_slice(&transform));
    let custom_and_mask = (custom_index & 0x00ff_ffff) | (0xffu32 << 24);
    let flags = if single_sided {
        vk::GeometryInstanceFlagsKHR::empty()
    } else {
        vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE
    };
    let flags = flags.as_raw() as u8;
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
    } = create_blases(ctx, &mut infos, &meshes)?;
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
    build_blases(ctx, &infos, &ranges, &blases, &queries)?;
    drop(scratch);

    let (compacted, blas_compacted_bytes) = create_compacted(ctx, compact_sizes.as_ref())?;
    let (instances, instance_bytes_len) = tlas_instances(ctx, &meshes, &compacted)?;
    let (tlas, tlas_size) = build_tlas(
        ctx,
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
    infos: &mut [vk::AccelerationStructureBuildGeometryInfoKHR<'_>],
    meshes: &[MeshRange],
) -> Result<BlasStorage, GpuError> {
    let align = ctx.scratch_alignment;
    let mut blases = Vec::with_capacity(meshes.len());
    let mut scratch_offsets = Vec::with_capacity(meshes.len());
    let mut scratch_total = 0u64;
    let mut blas_bytes = 0u64;
    for (info, m) in infos.iter().zip(meshes) {
        let sizes = build_sizes(ctx, info, &[m.triangle_count])?;
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
    infos: &[vk::AccelerationStructureBuildGeometryInfoKHR<'_>],
    ranges: &[[vk::AccelerationStructureBuildRangeInfoKHR; 1]],
    blases: &[AccelStruct],
    queries: &BuildQueries<'_>,
) -> Result<(), GpuError> {
    let range_refs: Vec<&[vk::AccelerationStructureBuildRangeInfoKHR]> =
        ranges.iter().map(|r| &r[..]).collect();
    let timestamps = queries.timestamps;
    let built: Vec<&AccelStruct> = blases.iter().collect();
    ctx.submit_and_wait(|rec| {
        rec.reset_queries(timestamps);
        if let Some(q) = queries.compact_sizes {
            rec.reset_queries(q);
        }
        rec.timestamp(timestamps, vk::PipelineStageFlags::TOP_OF_PIPE, 0);
        rec.build_accels(infos, &range_refs, (&built, &[]))?;
        if let Some(q) = queries.compact_sizes {
            rec.write_compacted_sizes(&built, q)?;
        }
        rec.timestamp(timestamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 1);
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
        instance_data.extend_from_slice(&instance_bytes(
            m.first_triangle,
            blas.address,
            m.single_sided,
        ));
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
    let tlas_sizes = build_sizes(ctx, &tlas_info, &[instance_count])?;
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
    ctx.submit_and_wait(|rec| {
        rec.timestamp(timestamps, vk::PipelineStageFlags::TOP_OF_PIPE, 2);
        for (src, dst) in blases.iter().zip(compacted) {
            rec.compact_accel(src, dst)?;
        }
        // The instances reference the compacted BLASes (or the built ones, without
        // compaction); scratch is aligned and large enough.
        let read: Vec<&AccelStruct> = if compacted.is_empty() {
            blases.iter().collect()
        } else {
            compacted.iter().collect()
        };
        rec.build_accels(&[tlas_info], &[&tlas_range], (&[&tlas], &read))?;
        // The trace pass's ray queries read it in later submissions.
        rec.publish(&[&tlas.storage]);
        rec.timestamp(timestamps, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 3);
        Ok(())
    })?;
    drop(tlas_scratch);
    Ok((tlas, tlas_sizes.acceleration_structure_size))
}
