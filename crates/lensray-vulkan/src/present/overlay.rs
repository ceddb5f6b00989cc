//! The preview's on-screen panel: egui's triangles drawn over the window image by
//! egui-ash-renderer, in a render pass that loads the copied display image and leaves the
//! window image ready to present.

use std::sync::Arc;

use ash::vk;
use egui_ash_renderer::allocator::DefaultAllocator;
use egui_ash_renderer::{Options, RenderMode, Renderer};

use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::recorder::Recorder;
use crate::core::render_pass::{Framebuffer, RenderPass};
use crate::core::swapchain::Swapchain;

/// What egui asks the frame to draw.
pub struct OverlayFrame {
    pub primitives: Vec<egui::ClippedPrimitive>,
    pub textures: egui::TexturesDelta,
    pub pixels_per_point: f32,
}

pub(crate) struct Overlay {
    ctx: Arc<Context>,
    // Dropped in this order: the framebuffers and the renderer (its pipeline), then the render
    // pass they were made for.
    framebuffers: Vec<Framebuffer>,
    renderer: Renderer<DefaultAllocator>,
    render_pass: RenderPass,
    extent: vk::Extent2D,
    format: vk::Format,
}

fn egui_err(e: egui_ash_renderer::RendererError) -> GpuError {
    GpuError::Invalid(format!("the egui renderer failed: {e}"))
}

impl Overlay {
    pub(crate) fn new(
        ctx: &Arc<Context>,
        format: vk::Format,
        frames: usize,
    ) -> Result<Self, GpuError> {
        let attachment = [vk::AttachmentDescription::default()
            .format(format)
            .samples(vk::SampleCountFlags::TYPE_1)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .final_layout(vk::ImageLayout::PRESENT_SRC_KHR)];
        let color_ref = [vk::AttachmentReference::default()
            .attachment(0)
            .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
        let subpass = [vk::SubpassDescription::default()
            .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
            .color_attachments(&color_ref)];
        let color_stage = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT;
        let color_rw =
            vk::AccessFlags::COLOR_ATTACHMENT_READ | vk::AccessFlags::COLOR_ATTACHMENT_WRITE;
        let dependencies = [
            // The copy of the display image into the window image comes first.
            vk::SubpassDependency::default()
                .src_subpass(vk::SUBPASS_EXTERNAL)
                .dst_subpass(0)
                .src_stage_mask(vk::PipelineStageFlags::TRANSFER)
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_stage_mask(color_stage)
                .dst_access_mask(color_rw),
            // Presentation waits on the frame's semaphore, signalled after everything.
            vk::SubpassDependency::default()
                .src_subpass(0)
                .dst_subpass(vk::SUBPASS_EXTERNAL)
                .src_stage_mask(color_stage)
                .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags::BOTTOM_OF_PIPE)
                .dst_access_mask(vk::AccessFlags::empty()),
        ];
        let info = vk::RenderPassCreateInfo::default()
            .attachments(&attachment)
            .subpasses(&subpass)
            .dependencies(&dependencies);
        let render_pass = RenderPass::new(ctx, &info)?;
        let renderer = Renderer::with_default_allocator(
            &ctx.instance.instance,
            ctx.physical_device,
            ctx.device.clone(),
            RenderMode::RenderPass(render_pass.handle),
            Options {
                in_flight_frames: frames,
                enable_depth_test: false,
                enable_depth_write: false,
                // The window image is UNORM holding sRGB-encoded values: egui encodes.
                srgb_framebuffer: false,
            },
        )
        .map_err(egui_err)?;
        Ok(Self {
            ctx: ctx.clone(),
            framebuffers: Vec::new(),
            renderer,
            render_pass,
            extent: vk::Extent2D::default(),
            format,
        })
    }

    pub(crate) fn format(&self) -> vk::Format {
        self.format
    }

    /// Framebuffers for the images of a new swapchain. No frame may be in flight.
    pub(crate) fn attach(&mut self, swapchain: &Swapchain) -> Result<(), GpuError> {
        self.framebuffers.clear();
        let extent = swapchain.extent;
        for &view in &swapchain.views {
            self.framebuffers.push(Framebuffer::new(
                &self.ctx,
                self.render_pass.handle,
                &[view],
                extent.width,
                extent.height,
            )?);
        }
        self.extent = swapchain.extent;
        Ok(())
    }

    /// Uploads egui's new and changed textures (before recording the frame that uses them).
    pub(crate) fn set_textures(&mut self, textures: &egui::TexturesDelta) -> Result<(), GpuError> {
        for (id, deltas) in &textures.set {
            for delta in deltas {
                self.renderer
                    .set_texture(self.ctx.queue, self.ctx.command_pool, *id, delta)
                    .map_err(egui_err)?;
            }
        }
        Ok(())
    }

    /// Frees textures egui no longer uses (after the frames that drew with them finished).
    pub(crate) fn free_textures(&mut self, ids: &[egui::TextureId]) -> Result<(), GpuError> {
        for &id in ids {
            self.renderer.free_texture(id).map_err(egui_err)?;
        }
        Ok(())
    }

    /// Records the render pass over window image `image_index` (in TRANSFER_DST_OPTIMAL after
    /// the copy), leaving it in PRESENT_SRC_KHR.
    pub(crate) fn record(
        &mut self,
        rec: &mut Recorder<'_>,
        image_index: u32,
        frame: Option<&OverlayFrame>,
    ) -> Result<(), GpuError> {
        let extent = self.extent;
        // The render pass loads the window image: nothing to clear. egui sets its own viewport
        // and scissors over the ones the recorder sets.
        rec.begin_render_pass(
            self.render_pass.handle,
            self.framebuffers[image_index as usize].handle,
            (extent.width, extent.height),
            &[],
        );
        if let Some(frame) = frame {
            self.renderer
                .cmd_draw(rec.cmd(), extent, frame.pixels_per_point, &frame.primitives)
                .map_err(egui_err)?;
        }
        rec.end_render_pass();
        Ok(())
    }
}
