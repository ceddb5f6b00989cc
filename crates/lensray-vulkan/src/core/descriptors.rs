//! Descriptor sets from their declarations (lensray-interface's bindings.rs): a pipeline's set
//! layout from its `SetDecl`, and a group of bindings written whole from its typed value, so that
//! no binding is missed or given a resource of the wrong kind.

use std::marker::PhantomData;
use std::sync::Arc;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::{Binding, Pipeline};
use lensray_core::interface::{BindingGroup, DescriptorKind, Resource, Resources, SetDecl, Stages};

/// What lensray-vulkan binds: its buffers, storage-image views (in GENERAL layout when used)
/// and acceleration structures, alive for `'a`.
pub(crate) struct Gpu<'a>(PhantomData<&'a ()>);

impl<'a> Resources for Gpu<'a> {
    type BufferResource = &'a Buffer;
    type ImageResource = vk::ImageView;
    type AccelResource = vk::AccelerationStructureKHR;
}

fn descriptor_type(kind: DescriptorKind) -> vk::DescriptorType {
    match kind {
        DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
        DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
        DescriptorKind::StorageImage { .. } => vk::DescriptorType::STORAGE_IMAGE,
        DescriptorKind::AccelerationStructure => vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
    }
}

pub(crate) fn stage_flags(stages: Stages) -> vk::ShaderStageFlags {
    match stages {
        Stages::Compute => vk::ShaderStageFlags::COMPUTE,
        Stages::Raster => vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
        Stages::RayTracing => {
            vk::ShaderStageFlags::RAYGEN_KHR
                | vk::ShaderStageFlags::CLOSEST_HIT_KHR
                | vk::ShaderStageFlags::ANY_HIT_KHR
                | vk::ShaderStageFlags::MISS_KHR
        }
    }
}

/// The Vulkan bindings of `set`.
pub(crate) fn layout_of(set: &SetDecl) -> Vec<Binding> {
    let stages = stage_flags(set.stages);
    set.bindings()
        .iter()
        .map(|b| (b.binding, descriptor_type(b.decl.kind), stages))
        .collect()
}

impl Pipeline {
    /// The layout objects of a pipeline whose descriptor set is `set` (its push constants
    /// included).
    pub(super) fn with_set(
        ctx: &Arc<Context>,
        set: &'static SetDecl,
        bind_point: vk::PipelineBindPoint,
    ) -> Result<Self, GpuError> {
        let mut this = Self::with_layout(
            ctx,
            &layout_of(set),
            set.push_bytes,
            stage_flags(set.stages),
            bind_point,
        )?;
        this.set_decl = Some(set);
        Ok(this)
    }

    /// Points the bindings of `group` at its resources. The pipeline's set must hold the
    /// group, and no submission using the set may be pending (every submission is waited for
    /// before a rebind).
    pub(crate) fn bind_group<'a, G: BindingGroup<Gpu<'a>>>(&self, group: &G) {
        let decl = G::DECL;
        let set = self
            .set_decl
            .expect("a pipeline made from a set declaration");
        assert!(
            set.holds(decl),
            "set {} has no group {}: declare it in lensray-interface's bindings.rs",
            set.name,
            decl.name
        );
        let first = decl.first_binding();
        for (i, (binding, resource)) in decl.bindings.iter().zip(group.resources()).enumerate() {
            let number = first + i as u32;
            match resource {
                Resource::Buffer(buffer) => {
                    self.write_buffer(number, descriptor_type(binding.kind), buffer);
                }
                Resource::Image(view) => self.write_storage_image(number, *view),
                Resource::Accel(accel) => self.write_accel(number, *accel),
            }
        }
    }

    /// Points binding `binding` at `buffer` (storage or uniform, whole buffer).
    pub(crate) fn write_buffer(&self, binding: u32, ty: vk::DescriptorType, buffer: &Buffer) {
        let info = [vk::DescriptorBufferInfo::default()
            .buffer(buffer.buffer)
            .offset(0)
            .range(vk::WHOLE_SIZE)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(ty)
            .buffer_info(&info);
        // SAFETY: no submission using the set is pending (every submission is waited for).
        unsafe { self.ctx.device.update_descriptor_sets(&[write], &[]) };
    }

    /// Points binding `binding` at a storage image `view` (in GENERAL layout when used).
    fn write_storage_image(&self, binding: u32, view: vk::ImageView) {
        let info = [vk::DescriptorImageInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::GENERAL)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
            .image_info(&info);
        // SAFETY: the set is not in use by a pending command buffer (callers rebind only
        // between frames, after waiting) and the view is live.
        unsafe { self.ctx.device.update_descriptor_sets(&[write], &[]) };
    }

    fn write_accel(&self, binding: u32, accel: vk::AccelerationStructureKHR) {
        let handles = [accel];
        let mut accel_info = vk::WriteDescriptorSetAccelerationStructureKHR::default()
            .acceleration_structures(&handles);
        let mut write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .push_next(&mut accel_info);
        write.descriptor_count = 1;
        // SAFETY: as in `write_buffer`; the count is set explicitly for the extension struct.
        unsafe { self.ctx.device.update_descriptor_sets(&[write], &[]) };
    }
}
