//! Drawing the scene in a raster pass: what the G-buffer and the raster path's visibility pass
//! record alike (render pass over the whole framebuffer, dynamic viewport and scissor,
//! non-indexed draws of 3 pulled vertices per triangle, one per run of triangles with the same
//! surfaces).

use std::sync::Arc;

use ash::vk;
use lensray_core::interface::SURFACE_SINGLE_SIDED;

use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::recorder::Recorder;
use crate::core::render_pass::RenderPass;
use crate::scene::SceneBuffers;
use crate::upload::SurfaceRun;

/// The depth buffer of every scene draw.
pub(crate) const SCENE_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The render pass of a scene draw: colour attachments of `color_formats` (locations 0, 1, ...)
/// cleared, stored and left in `final_layout`, a transfer layout (TRANSFER_SRC_OPTIMAL for
/// readbacks, copies and compute reads; TRANSFER_DST_OPTIMAL for the window image the panel's
/// pass takes over), then a D32 depth buffer.
pub(crate) fn scene_render_pass(
    ctx: &Arc<Context>,
    color_formats: &[vk::Format],
    final_layout: vk::ImageLayout,
) -> Result<RenderPass, GpuError> {
    let color = |format| {
        vk::AttachmentDescription::default()
            .format(format)
            .samples(vk::SampleCountFlags::TYPE_1)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(final_layout)
    };
    let depth = vk::AttachmentDescription::default()
        .format(SCENE_DEPTH_FORMAT)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let attachments: Vec<_> = color_formats
        .iter()
        .map(|&format| color(format))
        .chain(std::iter::once(depth))
        .collect();
    let color_refs: Vec<_> = (0..color_formats.len() as u32)
        .map(|i| {
            vk::AttachmentReference::default()
                .attachment(i)
                .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        })
        .collect();
    let depth_ref = vk::AttachmentReference::default()
        .attachment(color_formats.len() as u32)
        .layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let subpasses = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&color_refs)
        .depth_stencil_attachment(&depth_ref)];
    let attachment_stages = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
        | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
        | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
    let attachment_writes =
        vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE;
    let dependencies = [
        // Earlier readbacks / passes of these images before this pass writes them.
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(
                attachment_stages
                    | vk::PipelineStageFlags::TRANSFER
                    | vk::PipelineStageFlags::COMPUTE_SHADER,
            )
            .src_access_mask(attachment_writes)
            .dst_stage_mask(attachment_stages)
            .dst_access_mask(attachment_writes | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ),
        // This pass's writes before readbacks and later shader reads.
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(attachment_stages)
            .src_access_mask(attachment_writes)
            .dst_stage_mask(
                vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
            )
            .dst_access_mask(
                vk::AccessFlags::TRANSFER_READ
                    | vk::AccessFlags::TRANSFER_WRITE
                    | vk::AccessFlags::SHADER_READ,
            ),
    ];
    let info = vk::RenderPassCreateInfo::default()
        .attachments(&attachments)
        .subpasses(&subpasses)
        .dependencies(&dependencies);
    RenderPass::new(ctx, &info)
}

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

/// Records `draw`: begins the render pass, draws every triangle of `scene`, ends it. The
/// render pass's dependencies order its attachments' writes against earlier and later
/// transfers and compute reads; the scene's arrays are uploads, published to every command.
pub(crate) fn record_scene_draw(
    rec: &mut Recorder<'_>,
    scene: &SceneBuffers,
    draw: &SceneDraw<'_>,
) {
    rec.begin_render_pass(
        draw.render_pass,
        draw.framebuffer,
        (draw.width, draw.height),
        draw.clear,
    );
    rec.bind_graphics(draw.pipeline, draw.push);
    for run in surface_draws(scene, draw.pipeline.surface_variants()) {
        rec.bind_surfaces(draw.pipeline, run.surfaces);
        rec.draw(run.first_triangle * 3, run.triangle_count * 3);
    }
    rec.end_render_pass();
}

/// More draws than this in one pass cost more than the fragments they spare: the scene is drawn
/// with the general pipeline instead, one draw per run of single- or double-sided triangles.
const MAX_SURFACE_DRAWS: usize = 64;

/// The draws of `scene`'s triangles, in order: its surface runs with the bits a pipeline
/// specialized on `variants` tells apart, neighbours that become equal merged. Which pipeline
/// draws a triangle changes what its fragments compute, not their values: the general code
/// finds an untextured, opaque surface's colour as the specialized one does. Whether it culls
/// back faces (SURFACE_SINGLE_SIDED) is what the surface is, and every draw keeps it.
fn surface_draws(scene: &SceneBuffers, variants: u32) -> Vec<SurfaceRun> {
    let draws = merged_runs(&scene.surface_runs, |s| s & variants);
    if draws.len() > MAX_SURFACE_DRAWS {
        let general = variants & !SURFACE_SINGLE_SIDED;
        return merged_runs(&scene.surface_runs, |s| general | (s & variants));
    }
    draws
}

/// `runs` with their bits mapped by `bits`, neighbours that become equal merged.
fn merged_runs(runs: &[SurfaceRun], bits: impl Fn(u32) -> u32) -> Vec<SurfaceRun> {
    let mut draws: Vec<SurfaceRun> = Vec::new();
    for run in runs {
        let surfaces = bits(run.surfaces);
        match draws.last_mut() {
            Some(last) if last.surfaces == surfaces => last.triangle_count += run.triangle_count,
            _ => draws.push(SurfaceRun { surfaces, ..*run }),
        }
    }
    draws
}
