//! A scene on the device: the flattened arrays as storage buffers, and its acceleration
//! structures.

use std::sync::Arc;

use ash::vk;

use super::accel::{self, SceneAccel};
use super::buffer::Buffer;
use super::conv::FlatScene;
use super::device::Context;
use super::error::GpuError;
use super::pipeline::{Binding, Pipeline};
use crate::interface::{
    SCENE_BINDING_INDICES, SCENE_BINDING_MATERIALS, SCENE_BINDING_NORMALS, SCENE_BINDING_POSITIONS,
    SCENE_BINDING_TRI_INFO,
};
use crate::scene::Scene;

/// The arrays' binding numbers, in the order of the fields below.
const SCENE_BINDINGS: [u32; 5] = [
    SCENE_BINDING_POSITIONS,
    SCENE_BINDING_NORMALS,
    SCENE_BINDING_INDICES,
    SCENE_BINDING_TRI_INFO,
    SCENE_BINDING_MATERIALS,
];

pub(crate) struct SceneBuffers {
    pub accel: SceneAccel,
    positions: Buffer,
    normals: Buffer,
    indices: Buffer,
    tri_info: Buffer,
    materials: Buffer,
    pub triangle_count: u32,
}

impl SceneBuffers {
    pub fn new(ctx: &Arc<Context>, scene: &Scene) -> Result<Self, GpuError> {
        let flat = FlatScene::new(scene)?;
        let limit = u64::from(ctx.report.max_storage_buffer_range);
        for (what, bytes) in [
            ("vertex", std::mem::size_of_val(flat.positions.as_slice())),
            ("index", std::mem::size_of_val(flat.indices.as_slice())),
            ("material", std::mem::size_of_val(flat.materials.as_slice())),
        ] {
            if bytes as u64 > limit {
                return Err(GpuError::Invalid(format!(
                    "the scene's {what} array needs {bytes} bytes, more than the device's \
                     maximum storage buffer range ({limit} bytes)"
                )));
            }
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let build_input = storage
            | vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
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
        let normals = Buffer::with_data(
            ctx,
            "scene normals",
            bytemuck::cast_slice(&flat.normals),
            storage,
        )?;
        let tri_info = Buffer::with_data(
            ctx,
            "scene triangle info",
            bytemuck::cast_slice(&flat.tri_info),
            storage,
        )?;
        let materials = Buffer::with_data(
            ctx,
            "scene materials",
            bytemuck::cast_slice(&flat.materials),
            storage,
        )?;
        let accel = accel::build(ctx, &flat, &positions, &indices)?;
        Ok(Self {
            accel,
            positions,
            normals,
            indices,
            tri_info,
            materials,
            triangle_count: flat.triangle_count(),
        })
    }

    /// The descriptors of shaders/scene.glsl, read by `stages`.
    pub fn bindings(stages: vk::ShaderStageFlags) -> [Binding; 5] {
        SCENE_BINDINGS.map(|b| (b, vk::DescriptorType::STORAGE_BUFFER, stages))
    }

    /// Points the scene's descriptors of `pipeline`'s set at these arrays.
    pub fn bind(&self, pipeline: &Pipeline) {
        let buffers = [
            &self.positions,
            &self.normals,
            &self.indices,
            &self.tri_info,
            &self.materials,
        ];
        for (binding, buffer) in SCENE_BINDINGS.into_iter().zip(buffers) {
            pipeline.bind_buffer(binding, vk::DescriptorType::STORAGE_BUFFER, buffer);
        }
    }
}
