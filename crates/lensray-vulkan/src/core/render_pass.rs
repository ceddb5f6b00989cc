//! Render passes and framebuffers, each owned and destroyed on drop. Their owners describe
//! them (the scene draws in `passes::draw`, the preview's panel) and keep a framebuffer's
//! image views alive longer than it.

use std::sync::Arc;

use ash::vk;

use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};

/// A render pass, destroyed on drop.
pub(crate) struct RenderPass {
    ctx: Arc<Context>,
    pub handle: vk::RenderPass,
}

impl RenderPass {
    pub(crate) fn new(
        ctx: &Arc<Context>,
        info: &vk::RenderPassCreateInfo<'_>,
    ) -> Result<Self, GpuError> {
        // SAFETY: a create-info built by the caller's builders, over its live arrays.
        let handle = unsafe { ctx.device.create_render_pass(info, None) }
            .map_err(vk_err("vkCreateRenderPass"))?;
        Ok(Self {
            ctx: ctx.clone(),
            handle,
        })
    }
}

impl Drop for RenderPass {
    fn drop(&mut self) {
        // SAFETY: no pending submission uses it (pipelines and framebuffers only needed it at
        // creation).
        unsafe { self.ctx.device.destroy_render_pass(self.handle, None) };
    }
}

/// A framebuffer of a render pass over image views that its owner keeps alive longer
/// (declared after it, so dropped after it).
pub(crate) struct Framebuffer {
    ctx: Arc<Context>,
    pub handle: vk::Framebuffer,
}

impl Framebuffer {
    /// A framebuffer of `render_pass` over `views` (one per attachment), of one layer.
    pub(crate) fn new(
        ctx: &Arc<Context>,
        render_pass: vk::RenderPass,
        views: &[vk::ImageView],
        width: u32,
        height: u32,
    ) -> Result<Self, GpuError> {
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(views)
            .width(width)
            .height(height)
            .layers(1);
        // SAFETY: the views match the render pass's attachments and outlive the framebuffer
        // (the owner declares them after it).
        let handle = unsafe { ctx.device.create_framebuffer(&info, None) }
            .map_err(vk_err("vkCreateFramebuffer"))?;
        Ok(Self {
            ctx: ctx.clone(),
            handle,
        })
    }
}

impl Drop for Framebuffer {
    fn drop(&mut self) {
        // SAFETY: no pending submission uses it; its views are dropped after it.
        unsafe { self.ctx.device.destroy_framebuffer(self.handle, None) };
    }
}
