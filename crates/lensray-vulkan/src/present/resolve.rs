//! The preview's resolve pass (shaders/present/resolve.comp): the accumulation or a G-buffer view into
//! an 8-bit display image, which the viewer then copies to the window.

use std::sync::Arc;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::image::{DeviceImage, Transition};
use crate::core::pipeline::Pipeline;
use crate::core::recorder::{Access, Recorder};
use crate::core::shader;
use crate::passes::gbuffer::GBufferTargets;
use lensray_core::interface::{
    DescriptorSet, ResolveGroup, ResolvePush, ResolveSet, RESOLVE_GROUP_SIZE,
};

/// rgba8 in resolve.comp; sRGB-encoded values, as in lensray's PNGs.
pub(crate) const DISPLAY_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

pub(crate) struct ResolvePass {
    ctx: Arc<Context>,
    pipeline: Pipeline,
    /// The display image of the current size.
    pub display: Option<DeviceImage>,
    /// The accumulation bound (the recorder orders the resolve after the samples' writes).
    bound_accum: vk::Buffer,
}

impl ResolvePass {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let pipeline = Pipeline::compute(ctx, ResolveSet::DECL, shader::RESOLVE_COMP)?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            display: None,
            bound_accum: vk::Buffer::null(),
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
        self.bound_accum = accum.buffer;
        self.pipeline.bind_group(&ResolveGroup::<Gpu> {
            accum,
            g_normal: targets.normal.view,
            g_albedo: targets.albedo.view,
            g_depth: targets.view_depth.view,
            display: display.view,
        });
        self.display = Some(display);
        Ok(())
    }

    /// Records the resolve: the G-buffer images go to GENERAL (from TRANSFER_SRC_OPTIMAL after
    /// their pass in this frame, or already there from an earlier resolve), the display is
    /// written and left in TRANSFER_SRC_OPTIMAL for the copy.
    pub(crate) fn record(
        &self,
        rec: &mut Recorder<'_>,
        targets: &GBufferTargets,
        push: &ResolvePush,
    ) {
        let display = self.display.as_ref().expect("bind first");
        let old = targets.layout.get();
        if old != vk::ImageLayout::GENERAL {
            targets.record_to_general(rec, old);
            targets.layout.set(vk::ImageLayout::GENERAL);
        }
        rec.transition(
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
        let groups = [
            push.width.div_ceil(RESOLVE_GROUP_SIZE),
            push.height.div_ceil(RESOLVE_GROUP_SIZE),
            1,
        ];
        rec.dispatch(
            &self.pipeline,
            bytemuck::bytes_of(push),
            groups,
            &[(self.bound_accum, Access::ComputeRead)],
        );
        rec.transition(
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
