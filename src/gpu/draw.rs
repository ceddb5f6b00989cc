//! Drawing the scene in a raster pass: what the G-buffer and the raster path's visibility pass
//! record alike (render pass over the whole framebuffer, dynamic viewport and scissor, one
//! non-indexed draw of 3 pulled vertices per triangle).

use ash::vk;

use super::device::Context;
use super::pipeline::Pipeline;
use super::scene::SceneBuffers;

/// A render pass instance and what it draws with.
pub(crate) struct SceneDraw<'a> {
    pub render_pass: vk::RenderPass,
    pub framebuffer: vk::Framebuffer,
    pub width: u32,
    pub height: u32,
    pub clear: &'a [vk::ClearValue],
    pub pipeline: &'a Pipeline,
    pub push: &'a [u8],
}

/// Records `draw`: begins the render pass, draws every triangle of `scene`, ends it.
pub(crate) fn record_scene_draw(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    scene: &SceneBuffers,
    draw: &SceneDraw<'_>,
) {
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent: vk::Extent2D {
            width: draw.width,
            height: draw.height,
        },
    };
    let begin = vk::RenderPassBeginInfo::default()
        .render_pass(draw.render_pass)
        .framebuffer(draw.framebuffer)
        .render_area(area)
        .clear_values(draw.clear);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: draw.width as f32,
        height: draw.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: recording state; the framebuffer matches the render pass; the scene buffers
    // bound in the pipeline's set are live.
    unsafe {
        ctx.device
            .cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
        ctx.device.cmd_set_viewport(cmd, 0, &[viewport]);
        ctx.device.cmd_set_scissor(cmd, 0, &[area]);
    }
    draw.pipeline.bind(cmd, draw.push);
    let vertices = scene.triangle_count * 3;
    // SAFETY: inside the render pass with a graphics pipeline bound.
    unsafe {
        if vertices > 0 {
            ctx.device.cmd_draw(cmd, vertices, 1, 0, 0);
        }
        ctx.device.cmd_end_render_pass(cmd);
    }
}
