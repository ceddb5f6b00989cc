//! The preview's resolve pass (shaders/present/resolve.comp): the accumulation or a G-buffer view into
//! an 8-bit display image, which the viewer then copies to the window.

use std::sync::Arc;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::image::{transition, DeviceImage, Transition};
use crate::core::pipeline::Pipeline;
use crate::core::shader;
use crate::passes::gbuffer::GBufferTargets;
use lensray_core::interface::{
    ResolvePush, RESOLVE_BINDING_ACCUM, RESOLVE_BINDING_ALBEDO, RESOLVE_BINDING_DISPLAY,
    RESOLVE_BINDING_NORMAL, RESOLVE_BINDING_VIEW_DEPTH, RESOLVE_GROUP_SIZE,
};

/// rgba8 in resolve.comp; sRGB-encoded values, as in lensray's PNGs.
pub(crate) const DISPLAY_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

pub(crate) struct ResolvePass {
    ctx: Arc<Context>,
    pipeline: Pipeline,
    /// The display image of the current size.
    pub display: Option<DeviceImage>,
}

impl ResolvePass {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let compute = vk::ShaderStageFlags::COMPUTE;
        let image = vk::DescriptorType::STORAGE_IMAGE;
        let bindings = [
            (
                RESOLVE_BINDING_ACCUM,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
            (RESOLVE_BINDING_NORMAL, image, compute),
            (RESOLVE_BINDING_ALBEDO, image, compute),
            (RESOLVE_BINDING_VIEW_DEPTH, image, compute),
            (RESOLVE_BINDING_DISPLAY, image, compute),
        ];
        let pipeline = Pipeline::compute(
            ctx,
            shader::RESOLVE_COMP,
            &bindings,
            std::mem::size_of::<ResolvePush>() as u32,
        )?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            display: None,
        })
    }

    /// For a new image size: a display image of that size, and the inputs bound. No frame may
    /// be in flight (descriptor updates).
    pub(crate) fn bind(
        &mut self,
        accum: &Buffer,
        targets: &GBufferTargets,
        width: u32,
        height: u32,
    ) -> Result<(), GpuError> {
        self.display = None;
        let display = DeviceImage::new(
            &self.ctx,
            "preview display",
            width,
            height,
            DISPLAY_FORMAT,
            vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
        )?;
        let p = &self.pipeline;
        p.bind_buffer(
            RESOLVE_BINDING_ACCUM,
            vk::DescriptorType::STORAGE_BUFFER,
            accum,
        );
        p.bind_storage_image(RESOLVE_BINDING_NORMAL, targets.normal.view);
        p.bind_storage_image(RESOLVE_BINDING_ALBEDO, targets.albedo.view);
        p.bind_storage_image(RESOLVE_BINDING_VIEW_DEPTH, targets.view_depth.view);
        p.bind_storage_image(RESOLVE_BINDING_DISPLAY, display.view);
        self.display = Some(display);
        Ok(())
    }

    /// Records the resolve: the G-buffer images go to GENERAL (from TRANSFER_SRC_OPTIMAL after
    /// their pass in this frame, or already there from an earlier resolve), the display is
    /// written and left in TRANSFER_SRC_OPTIMAL for the copy.
    pub(crate) fn record(
        &self,
        cmd: vk::CommandBuffer,
        targets: &GBufferTargets,
        push: &ResolvePush,
    ) {
        let ctx = &self.ctx;
        let display = self.display.as_ref().expect("bind first");
        let old = targets.layout.get();
        if old != vk::ImageLayout::GENERAL {
            targets.record_to_general(ctx, cmd, old);
            targets.layout.set(vk::ImageLayout::GENERAL);
        }
        transition(
            ctx,
            cmd,
            display.image,
            &Transition {
                old: vk::ImageLayout::UNDEFINED,
                new: vk::ImageLayout::GENERAL,
                src_stage: vk::PipelineStageFlags::TRANSFER,
                src_access: vk::AccessFlags::empty(),
                dst_stage: vk::PipelineStageFlags::COMPUTE_SHADER,
                dst_access: vk::AccessFlags::SHADER_WRITE,
            },
        );
        self.pipeline.bind(cmd, bytemuck::bytes_of(push));
        // SAFETY: compute pipeline and complete set bound; the images are in GENERAL.
        unsafe {
            ctx.device.cmd_dispatch(
                cmd,
                push.width.div_ceil(RESOLVE_GROUP_SIZE),
                push.height.div_ceil(RESOLVE_GROUP_SIZE),
                1,
            )
        };
        transition(
            ctx,
            cmd,
            display.image,
            &Transition {
                old: vk::ImageLayout::GENERAL,
                new: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                src_stage: vk::PipelineStageFlags::COMPUTE_SHADER,
                src_access: vk::AccessFlags::SHADER_WRITE,
                dst_stage: vk::PipelineStageFlags::TRANSFER,
                dst_access: vk::AccessFlags::TRANSFER_READ,
            },
        );
    }
}
