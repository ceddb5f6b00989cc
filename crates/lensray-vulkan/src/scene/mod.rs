//! A scene on the device: the flattened arrays as storage buffers, and the structures of the
//! traversals the device was opened for: acceleration structures (ray queries) and the
//! software traversal's BVH.

pub(crate) mod accel;
pub(crate) mod bvh;
pub(crate) mod environment;
pub(crate) mod texels;

use std::sync::Arc;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::traversal::Traversal;
use crate::upload::{FlatScene, SurfaceRun};
use accel::SceneAccel;
use bvh::{BvhParams, FlatBvh};
use lensray_core::interface::{BvhGroup, SceneGroup};
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::Scene;

/// The software traversal's BVH on the device (lensray-vulkan/src/scene/bvh.rs).
pub(crate) struct BvhBuffers {
    nodes: Buffer,
    triangles: Buffer,
    /// Bytes of both buffers.
    pub bytes: u64,
    /// Host build and flattening time (the upload excluded), nanoseconds.
    pub build_ns: f64,
}

impl BvhBuffers {
    fn new(ctx: &Arc<Context>, flat: &FlatScene, params: &BvhParams) -> Result<Self, GpuError> {
        let bvh = FlatBvh::build(
            &flat.positions,
            &flat.indices,
            &flat.motion_vertices,
            params,
        )?;
        let limit = u64::from(ctx.report.max_storage_buffer_range);
        let triangle_bytes = std::mem::size_of_val(bvh.triangles.as_slice()) as u64;
        if triangle_bytes > limit {
            return Err(GpuError::Invalid(format!(
                "the software traversal's triangle array needs {triangle_bytes} bytes, more \
                 than the device's maximum storage buffer range ({limit} bytes)"
            )));
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(Self {
            nodes: Buffer::with_data(ctx, "BVH nodes", bytemuck::cast_slice(&bvh.nodes), storage)?,
            triangles: Buffer::with_data(
                ctx,
                "BVH triangles",
                bytemuck::cast_slice(&bvh.triangles),
                storage,
            )?,
            bytes: bvh.bytes(),
            build_ns: bvh.build_time.as_nanos() as f64,
        })
    }

    /// The BVH as `pipeline`'s set binds it (shaders/include/hit_software.glsl).
    pub(crate) fn bind(&self, pipeline: &Pipeline) {
        pipeline.bind_group(&BvhGroup::<Gpu> {
            bvh_nodes: &self.nodes,
            bvh_triangles: &self.triangles,
        });
    }
}

/// One line naming the textures the GPU reads from a coarser level to fit `limit` bytes.
fn warn_coarsened(flat: &FlatScene, limit: u64) {
    if flat.coarsened.is_empty() {
        return;
    }
    let sizes: Vec<String> = flat
        .coarsened
        .iter()
        .map(|(name, [w, h], [rw, rh])| format!("{name} {w}x{h} at {rw}x{rh}"))
        .collect();
    eprintln!(
        "warning: the scene's textures pass the device's storage buffer range ({} MiB): the \
         GPU reads {} from a coarser mip level (the CPU path reads them whole)",
        limit >> 20,
        sizes.join(", ")
    );
}

/// Refuses a scene whose vertex, index, material or texel array passes the device's storage
/// buffer range (`limit`): the shaders index each as one array.
fn check_array_sizes(flat: &FlatScene, limit: u64) -> Result<(), GpuError> {
    for (what, bytes) in [
        ("vertex", std::mem::size_of_val(flat.positions.as_slice())),
        ("index", std::mem::size_of_val(flat.indices.as_slice())),
        ("material", std::mem::size_of_val(flat.materials.as_slice())),
        (
            "moving vertex",
            std::mem::size_of_val(flat.motion_vertices.as_slice()),
        ),
        ("texel", std::mem::size_of_val(flat.texels.as_slice())),
    ] {
        if bytes as u64 > limit {
            return Err(GpuError::Invalid(format!(
                "the scene's {what} array needs {bytes} bytes, more than the device's \
                 maximum storage buffer range ({limit} bytes)"
            )));
        }
    }
    Ok(())
}

pub(crate) struct SceneBuffers {
    /// With ray queries enabled.
    pub accel: Option<SceneAccel>,
    /// When the software traversal may be used.
    pub bvh: Option<BvhBuffers>,
    positions: Buffer,
    normals: Buffer,
    indices: Buffer,
    tri_info: Buffer,
    materials: Buffer,
    texcoords: Buffer,
    texcoords1: Buffer,
    colours: Buffer,
    tangents: Buffer,
    textures: Buffer,
    texels: Buffer,
    lights: Buffer,
    emitter_triangles: Buffer,
    emitter_cdf: Buffer,
    emitter_area_pdf: Buffer,
    motion_vertices: Buffer,
    /// The scene's environment map, or a black placeholder (`has_map` false).
    pub environment: environment::EnvironmentBuffers,
    /// Every triangle, in runs of the same surfaces (the raster passes' draws).
    pub surface_runs: Vec<SurfaceRun>,
    /// What the traced shading meets on any surface (SURFACE_*): the trace pass's
    /// specialization.
    pub surfaces: u32,
    /// Whether meshes move while the shutter is open (only the software traversal meets them).
    pub moving: bool,
}

impl SceneBuffers {
    /// Builds what the device's traversals need (`ctx.traversals`): acceleration structures,
    /// the BVH of `bvh_params`, or both; the meshes `motion` names move through its steps
    /// (only the software traversal meets them where they are at a ray's moment).
    pub(crate) fn new(
        ctx: &Arc<Context>,
        scene: &Scene,
        motion: Option<&ObjectMotion>,
        bvh_params: &BvhParams,
    ) -> Result<Self, GpuError> {
        let limit = u64::from(ctx.report.max_storage_buffer_range);
        let flat = FlatScene::new(scene, motion, limit)?;
        warn_coarsened(&flat, limit);
        check_array_sizes(&flat, limit)?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        // Both traversals of the driver's trace through its acceleration structures.
        let accel_structures = ctx.accel.is_some();
        let build_input = if accel_structures {
            storage
                | vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS
        } else {
            storage
        };
        let positions = Buffer::with_data(
            ctx,
            "scene positions",
            bytemuck::cast_slice(&flat.positions),
            build_input,
        )?;
        let indices = Buffer::with_data(
            ctx,
            "scene indices",
            bytemuck::cast_slice(&flat.indices),
            build_input,
        )?;
        let [normals, tri_info, materials, texcoords, texcoords1, colours, tangents, textures, texels, lights, emitter_triangles, emitter_cdf, emitter_area_pdf, motion_vertices] =
            [
                ("scene normals", bytemuck::cast_slice(&flat.normals)),
                ("scene triangle info", bytemuck::cast_slice(&flat.tri_info)),
                ("scene materials", bytemuck::cast_slice(&flat.materials)),
                (
                    "scene texture coordinates",
                    bytemuck::cast_slice(&flat.texcoords),
                ),
                (
                    "scene second texture coordinates",
                    bytemuck::cast_slice(&flat.texcoords1),
                ),
                ("scene colours", bytemuck::cast_slice(&flat.colours)),
                ("scene tangents", bytemuck::cast_slice(&flat.tangents)),
                ("scene textures", bytemuck::cast_slice(&flat.textures)),
                ("scene texels", bytemuck::cast_slice(&flat.texels)),
                ("scene lights", bytemuck::cast_slice(&flat.lights)),
                (
                    "scene emitter triangles",
                    bytemuck::cast_slice(&flat.emitters.triangles),
                ),
                (
                    "scene emitter cdf",
                    bytemuck::cast_slice(&flat.emitters.cdf),
                ),
                (
                    "scene emitter area pdf",
                    bytemuck::cast_slice(&flat.emitters.area_pdf),
                ),
                (
                    "scene motion vertices",
                    bytemuck::cast_slice(&flat.motion_vertices),
                ),
            ]
            .map(|(name, data)| Buffer::with_data(ctx, name, data, storage));
        let accel = accel_structures
            .then(|| accel::build(ctx, &flat, &positions, &indices))
            .transpose()?;
        let bvh = ctx
            .traversals
            .contains(&Traversal::Software)
            .then(|| BvhBuffers::new(ctx, &flat, bvh_params))
            .transpose()?;
        Ok(Self {
            accel,
            bvh,
            positions,
            normals: normals?,
            indices,
            tri_info: tri_info?,
            materials: materials?,
            texcoords: texcoords?,
            texcoords1: texcoords1?,
            colours: colours?,
            tangents: tangents?,
            textures: textures?,
            texels: texels?,
            lights: lights?,
            emitter_triangles: emitter_triangles?,
            emitter_cdf: emitter_cdf?,
            emitter_area_pdf: emitter_area_pdf?,
            motion_vertices: motion_vertices?,
            environment: environment::EnvironmentBuffers::of_scene(ctx, scene)?,
            surface_runs: flat.surface_runs,
            surfaces: flat.surfaces,
            moving: motion.is_some(),
        })
    }

    /// Points the scene's group of `pipeline`'s set at these arrays.
    pub(crate) fn bind(&self, pipeline: &Pipeline) {
        pipeline.bind_group(&SceneGroup::<Gpu> {
            positions: &self.positions,
            normals: &self.normals,
            indices: &self.indices,
            tri_info: &self.tri_info,
            materials: &self.materials,
            texcoords: &self.texcoords,
            texcoords1: &self.texcoords1,
            colours: &self.colours,
            tangents: &self.tangents,
            textures: &self.textures,
            texels: &self.texels,
            lights: &self.lights,
            emitter_triangles: &self.emitter_triangles,
            emitter_cdf: &self.emitter_cdf,
            emitter_area_pdf: &self.emitter_area_pdf,
            motion_vertices: &self.motion_vertices,
        });
    }
}
