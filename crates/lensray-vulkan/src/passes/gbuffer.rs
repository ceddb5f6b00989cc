//! The raster G-buffer pass: world-space shading normal (facing the viewer), albedo (Kd) and
//! linear view depth per pixel, with a D32 depth buffer, projected by the Rust camera's
//! `clip_from_world()`. The targets stay alive in the renderer (in TRANSFER_SRC_OPTIMAL layout)
//! for later passes; `render` also reads them back to the host.

use std::cell::Cell;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::image::{DeviceImage, Transition};
use crate::core::pipeline::{GraphicsDesc, Pipeline};
use crate::core::query::QueryPool;
use crate::core::recorder::Recorder;
use crate::core::render_pass::{Framebuffer, RenderPass};
use crate::core::shader;
use crate::passes::draw::{record_scene_draw, scene_render_pass, SceneDraw, SCENE_DEPTH_FORMAT};
use crate::scene::SceneBuffers;
use lensray_core::camera::Camera;
use lensray_core::interface::{
    DescriptorSet, GBufferSet, SURFACE_ALPHA_TESTED, SURFACE_SINGLE_SIDED, SURFACE_TEXTURED,
};

/// The G-buffer read back to the host; row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct GBuffer {
    pub width: u32,
    pub height: u32,
    /// Camera-space z of the visible surface at each pixel centre; 0 where nothing is covered.
    pub view_depth: Vec<f32>,
    /// World-space shading normal facing the viewer; 0 where nothing is covered.
    pub normal: Vec<Vec3>,
    /// Kd of the visible surface; the background where nothing is covered.
    pub albedo: Vec<Vec3>,
    pub coverage: Vec<bool>,
}

impl GBuffer {
    pub fn index(&self, x: u32, y: u32) -> usize {
        (y * self.width + x) as usize
    }
}

/// Autofocus: the view depth at pixel (x, y), `None` outside the image or where nothing is
/// covered.
pub fn focus_distance_at(gbuffer: &GBuffer, x: u32, y: u32) -> Option<f32> {
    if x >= gbuffer.width || y >= gbuffer.height {
        return None;
    }
    let i = gbuffer.index(x, y);
    gbuffer.coverage[i].then_some(gbuffer.view_depth[i])
}

const NORMAL_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
const ALBEDO_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
const VIEW_DEPTH_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// The G-buffer images of one size and their framebuffer.
pub(crate) struct GBufferTargets {
    /// The colour images' layout after the commands recorded so far (recorded in submission
    /// order): the G-buffer pass leaves TRANSFER_SRC_OPTIMAL, the preview's resolve GENERAL.
    pub layout: Cell<vk::ImageLayout>,
    /// First: dropped before the images whose views it uses.
    framebuffer: Framebuffer,
    pub normal: DeviceImage,
    pub albedo: DeviceImage,
    pub view_depth: DeviceImage,
    /// The depth buffer (D32) the framebuffer tests against.
    #[expect(dead_code, reason = "owned here: the framebuffer uses its view")]
    depth: DeviceImage,
    pub width: u32,
    pub height: u32,
}

impl GBufferTargets {
    /// Records the colour images' transition from `old` (TRANSFER_SRC_OPTIMAL after their pass)
    /// to GENERAL for compute-shader reads (the preview's resolve, the hybrid's plan), their
    /// pass's writes ordered before those reads. The caller keeps `layout` up to date.
    pub(crate) fn record_to_general(&self, rec: &mut Recorder<'_>, old: vk::ImageLayout) {
        for image in [&self.normal, &self.albedo, &self.view_depth] {
            rec.transition(
                image.image,
                &Transition {
                    old,
                    new: vk::ImageLayout::GENERAL,
                    src_stage: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                        | vk::PipelineStageFlags::TRANSFER,
                    src_access: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                    dst_stage: vk::PipelineStageFlags::COMPUTE_SHADER,
                    dst_access: vk::AccessFlags::SHADER_READ,
                },
            );
        }
    }

    fn new(
        ctx: &Arc<Context>,
        render_pass: vk::RenderPass,
        width: u32,
        height: u32,
    ) -> Result<Self, GpuError> {
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::STORAGE;
        let color = |name, format| {
            DeviceImage::new(
                ctx,
                name,
                width,
                height,
                format,
                color_usage,
                vk::ImageAspectFlags::COLOR,
            )
        };
        let normal = color("G-buffer normal", NORMAL_FORMAT)?;
        let albedo = color("G-buffer albedo", ALBEDO_FORMAT)?;
        let view_depth = color("G-buffer view depth", VIEW_DEPTH_FORMAT)?;
        let depth = DeviceImage::new(
            ctx,
            "G-buffer depth",
            width,
            height,
            SCENE_DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        let framebuffer = Framebuffer::new(
            ctx,
            render_pass,
            &[normal.view, albedo.view, view_depth.view, depth.view],
            width,
            height,
        )?;
        Ok(Self {
            layout: Cell::new(vk::ImageLayout::UNDEFINED),
            framebuffer,
            normal,
            albedo,
            view_depth,
            depth,
            width,
            height,
        })
    }
}

pub(crate) struct GBufferPass {
    ctx: Arc<Context>,
    pipeline: Pipeline,
    pub targets: Option<GBufferTargets>,
    render_pass: RenderPass,
    timestamps: QueryPool,
    /// GPU time of the last pass's draw (timestamps around the render pass), ms.
    pub last_gpu_ms: f64,
}

impl GBufferPass {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let render_pass = scene_render_pass(
            ctx,
            &[NORMAL_FORMAT, ALBEDO_FORMAT, VIEW_DEPTH_FORMAT],
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        )?;
        let pipeline = Pipeline::graphics(
            ctx,
            GBufferSet::DECL,
            &GraphicsDesc {
                vert: shader::GBUFFER_VERT,
                frag: shader::GBUFFER_FRAG,
                render_pass: render_pass.handle,
                color_attachments: 3,
                depth_compare: vk::CompareOp::LESS,
                surface_variants: SURFACE_TEXTURED | SURFACE_ALPHA_TESTED | SURFACE_SINGLE_SIDED,
                plain: Some((shader::GBUFFER_PLAIN_VERT, shader::GBUFFER_PLAIN_FRAG)),
            },
        )?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            targets: None,
            render_pass,
            timestamps: QueryPool::new(ctx, vk::QueryType::TIMESTAMP, 2)?,
            last_gpu_ms: 0.0,
        })
    }

    /// Points the pipeline's set at a newly loaded scene.
    pub(crate) fn bind_scene(&self, scene: &SceneBuffers) {
        scene.bind(&self.pipeline);
    }

    /// Makes the targets `width` x `height` (recreating them on a size change) and returns
    /// them.
    pub(crate) fn ensure_targets(
        &mut self,
        width: u32,
        height: u32,
    ) -> Result<&GBufferTargets, GpuError> {
        if self
            .targets
            .as_ref()
            .is_some_and(|t| t.width != width || t.height != height)
        {
            // The old images go before the new ones are allocated.
            self.targets = None;
        }
        match &mut self.targets {
            Some(targets) => Ok(targets),
            none => Ok(none.insert(GBufferTargets::new(
                &self.ctx,
                self.render_pass.handle,
                width,
                height,
            )?)),
        }
    }

    /// Records the pass into `cmd` (targets of the camera's size must exist): afterwards the
    /// images are in TRANSFER_SRC_OPTIMAL, their writes ordered before transfers and compute
    /// reads. `timestamps`: a pool and the first of two queries written around the draw.
    pub(crate) fn record(
        &self,
        rec: &mut Recorder<'_>,
        scene: &SceneBuffers,
        camera: &Camera,
        background: Vec3,
        timestamps: Option<(&QueryPool, u32)>,
    ) {
        let targets = self.targets.as_ref().expect("ensure_targets first");
        let (width, height) = (targets.width, targets.height);
        let push = crate::upload::raster_push(camera);
        if let Some((pool, first)) = timestamps {
            rec.timestamp(pool, vk::PipelineStageFlags::TOP_OF_PIPE, first);
        }
        let clear = [
            vk::ClearValue {
                color: vk::ClearColorValue { float32: [0.0; 4] },
            },
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: background.extend(0.0).to_array(),
                },
            },
            vk::ClearValue {
                color: vk::ClearColorValue { float32: [0.0; 4] },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
        ];
        record_scene_draw(
            rec,
            scene,
            &SceneDraw {
                render_pass: self.render_pass.handle,
                framebuffer: targets.framebuffer.handle,
                width,
                height,
                clear: &clear,
                pipeline: &self.pipeline,
                push: bytemuck::bytes_of(&push),
            },
        );
        targets.layout.set(vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
        if let Some((pool, first)) = timestamps {
            rec.timestamp(pool, vk::PipelineStageFlags::BOTTOM_OF_PIPE, first + 1);
        }
    }

    /// Draws the G-buffer of `camera` and reads it back to the host.
    pub(crate) fn render(
        &mut self,
        scene: &SceneBuffers,
        camera: &Camera,
        background: Vec3,
    ) -> Result<GBuffer, GpuError> {
        let (width, height) = (camera.width, camera.height);
        self.ensure_targets(width, height)?;
        let targets = self.targets.as_ref().expect("targets were just created");
        let pixels = u64::from(width) * u64::from(height);
        let readback = |name, bytes_per_pixel: u64| {
            Buffer::new(
                &self.ctx,
                name,
                pixels * bytes_per_pixel,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )
        };
        let normal_rb = readback("G-buffer normal readback", 16)?;
        let albedo_rb = readback("G-buffer albedo readback", 16)?;
        let depth_rb = readback("G-buffer depth readback", 4)?;
        let ctx = &self.ctx;
        ctx.submit_and_wait(|rec| {
            rec.reset_queries(&self.timestamps);
            self.record(rec, scene, camera, background, Some((&self.timestamps, 0)));
            // The render pass left the images in TRANSFER_SRC_OPTIMAL and its outgoing
            // dependency orders the attachment writes before these copies.
            let copies = [
                (&targets.normal, &normal_rb),
                (&targets.albedo, &albedo_rb),
                (&targets.view_depth, &depth_rb),
            ];
            for (image, buffer) in copies {
                rec.copy_image_to_buffer(image.image, buffer, [0, 0], [width, height]);
            }
            rec.read_on_host(&[&normal_rb, &albedo_rb, &depth_rb]);
            Ok(())
        })?;
        let ticks = self.timestamps.results()?;
        self.last_gpu_ms = self.ctx.elapsed_ns(ticks[0], ticks[1]) * 1e-6;
        let normal: &[[f32; 4]] = bytemuck::cast_slice(normal_rb.read()?);
        let albedo: &[[f32; 4]] = bytemuck::cast_slice(albedo_rb.read()?);
        let depth: &[f32] = bytemuck::cast_slice(depth_rb.read()?);
        let n = pixels as usize;
        Ok(GBuffer {
            width,
            height,
            view_depth: depth[..n].to_vec(),
            normal: normal[..n]
                .iter()
                .map(|v| Vec3::new(v[0], v[1], v[2]))
                .collect(),
            albedo: albedo[..n]
                .iter()
                .map(|v| Vec3::new(v[0], v[1], v[2]))
                .collect(),
            coverage: normal[..n].iter().map(|v| v[3] > 0.5).collect(),
        })
    }
}
