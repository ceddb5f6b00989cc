//! 2D images with gpu-allocator memory and a view, destroyed on drop.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::core::device::Context;
use crate::core::error::{alloc_err, check_allocation, vk_err, GpuError};

pub(crate) struct DeviceImage {
    ctx: Arc<Context>,
    pub image: vk::Image,
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
}

impl DeviceImage {
    pub(crate) fn new(
        ctx: &Arc<Context>,
        name: &str,
        width: u32,
        height: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self, GpuError> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create-info on a live device.
        let image =
            unsafe { ctx.device.create_image(&info, None) }.map_err(vk_err("vkCreateImage"))?;
        let mut this = Self {
            ctx: ctx.clone(),
            image,
            view: vk::ImageView::null(),
            allocation: None,
        };
        // SAFETY: `image` was just created from this device.
        let requirements = unsafe { ctx.device.get_image_memory_requirements(image) };
        // `this` destroys the image on the way out.
        check_allocation(ctx, name, requirements.size)?;
        let allocation = ctx
            .allocator()
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(alloc_err(name))?;
        // SAFETY: the allocation satisfies the image's requirements and is bound once.
        let bound = unsafe {
            ctx.device
                .bind_image_memory(image, allocation.memory(), allocation.offset())
        };
        this.allocation = Some(allocation);
        bound.map_err(vk_err("vkBindImageMemory"))?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        // SAFETY: the image is bound to memory; the view matches its format and aspect.
        this.view = unsafe { ctx.device.create_image_view(&view_info, None) }
            .map_err(vk_err("vkCreateImageView"))?;
        Ok(this)
    }
}

pub(crate) fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .base_mip_level(0)
        .level_count(1)
        .base_array_layer(0)
        .layer_count(1)
}

impl Drop for DeviceImage {
    fn drop(&mut self) {
        // SAFETY: users wait for their submissions before dropping; view before image, image
        // before its memory.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.ctx.device.destroy_image_view(self.view, None);
            }
            self.ctx.device.destroy_image(self.image, None);
        }
        if let Some(a) = self.allocation.take() {
            let _ = self.ctx.allocator().free(a);
        }
    }
}

/// One image's layout transition with the memory dependency around it (colour aspect).
pub(crate) struct Transition {
    pub old: vk::ImageLayout,
    pub new: vk::ImageLayout,
    pub src_stage: vk::PipelineStageFlags,
    pub src_access: vk::AccessFlags,
    pub dst_stage: vk::PipelineStageFlags,
    pub dst_access: vk::AccessFlags,
}

/// Records `transition` of `image`.
pub(crate) fn transition(ctx: &Context, cmd: vk::CommandBuffer, image: vk::Image, t: &Transition) {
    let barrier = [vk::ImageMemoryBarrier::default()
        .old_layout(t.old)
        .new_layout(t.new)
        .src_access_mask(t.src_access)
        .dst_access_mask(t.dst_access)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(subresource_range(vk::ImageAspectFlags::COLOR))];
    // SAFETY: recording state; the image is live and in `old` layout (or `old` is UNDEFINED).
    unsafe {
        ctx.device.cmd_pipeline_barrier(
            cmd,
            t.src_stage,
            t.dst_stage,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &barrier,
        )
    };
}

/// Records a copy of the `extent` pixels at `offset` of colour image `image` (in
/// TRANSFER_SRC_OPTIMAL, its writes ordered before transfers) into `buffer`, packed row by row.
pub(crate) fn record_copy_to_buffer(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    buffer: vk::Buffer,
    offset: [u32; 2],
    extent: [u32; 2],
) {
    let region = vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_offset(vk::Offset3D {
            x: offset[0] as i32,
            y: offset[1] as i32,
            z: 0,
        })
        .image_extent(vk::Extent3D {
            width: extent[0],
            height: extent[1],
            depth: 1,
        });
    // SAFETY: recording state; the caller's image is in TRANSFER_SRC_OPTIMAL with the region
    // inside it, and the buffer holds the region's texels.
    unsafe {
        ctx.device.cmd_copy_image_to_buffer(
            cmd,
            image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            buffer,
            &[region],
        )
    };
}
