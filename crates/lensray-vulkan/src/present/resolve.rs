//! The preview's resolve pass (shaders/present/resolve.comp): the accumulation or a G-buffer view into
//! an 8-bit display image, which the viewer then copies to the window.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

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
    /// The lens's own light per pixel of the current size (host-written), and whether the
    /// final view adds it.
    flare: Option<Buffer>,
    flare_shown: bool,
}

impl ResolvePass {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let pipeline = Pipeline::compute(ctx, ResolveSet::DECL, shader::RESOLVE_COMP)?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            display: None,
            bound_accum: vk::Buffer::null(),
            flare: None,
            flare_shown: false,
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
        let flare = Buffer::new(
            &self.ctx,
            "preview flare",
            u64::from(width) * u64::from(height) * 16,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        self.pipeline.bind_group(&ResolveGroup::<Gpu> {
            accum,
            g_normal: targets.normal.view,
            g_albedo: targets.albedo.view,
            g_depth: targets.view_depth.view,
            display: display.view,
            flare: &flare,
        });
        self.display = Some(display);
        self.flare = Some(flare);
        self.flare_shown = false;
        Ok(())
    }

    /// The lens's own light the final view adds (`None`: none), one value per pixel of the
    /// bound size. No frame may be in flight (the buffer is written from the host).
    pub(crate) fn set_flare(&mut self, light: Option<&[Vec3]>) -> Result<(), GpuError> {
        self.flare_shown = false;
        let (Some(light), Some(buffer)) = (light, self.flare.as_mut()) else {
            return Ok(());
        };
        let values: Vec<[f32; 4]> = light.iter().map(|v| [v.x, v.y, v.z, 0.0]).collect();
        if (values.len() * 16) as u64 > buffer.size {
            return Err(GpuError::Invalid(
                "the flare's image is not the preview's size".into(),
            ));
        }
        buffer.write(bytemuck::cast_slice(&values))?;
        self.flare_shown = true;
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
        let push = &ResolvePush {
            flare: u32::from(self.flare_shown),
            ..*push
        };
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
