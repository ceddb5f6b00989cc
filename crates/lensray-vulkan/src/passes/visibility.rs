//! The raster path's visibility pass (accumulation-buffer depth of field, docs/raster.md): the
//! scene rasterized through one lens point (`Camera::clip_from_world_through_lens`) into an
//! R32_UINT image of triangle index + 1 (0: nothing) with reversed D32 depth, then copied into
//! a storage buffer that the shading pass (trace.comp, TRACE_MODE_RASTER) reads.

use std::sync::Arc;

use ash::vk;
use glam::{UVec2, Vec2};
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::image::DeviceImage;
use crate::core::pipeline::{GraphicsDesc, Pipeline};
use crate::core::recorder::Recorder;
use crate::core::render_pass::{Framebuffer, RenderPass};
use crate::core::shader;
use crate::passes::draw::{record_scene_draw, scene_render_pass, SceneDraw, SCENE_DEPTH_FORMAT};
use crate::scene::SceneBuffers;
use lensray_core::camera::Camera;
use lensray_core::interface::{
    DescriptorSet, VisibilityPush, VisibilitySet, SURFACE_ALPHA_TESTED, SURFACE_SINGLE_SIDED,
};
use lensray_core::sampler::{pixel_camera_sample, shared_pixel_sampler};
use lensray_core::settings::RenderSettings;

const TRIANGLE_FORMAT: vk::Format = vk::Format::R32_UINT;

/// The images of one size, their framebuffer, and the buffer the shading pass reads.
pub(crate) struct VisibilityTargets {
    /// First: dropped before the images whose views it uses.
    framebuffer: Framebuffer,
    triangle: DeviceImage,
    #[expect(dead_code, reason = "owned here: the framebuffer uses its view")]
    depth: DeviceImage,
    /// One uint per pixel, row-major: `RasterTraceGroup`'s `visibility`.
    pub buffer: Buffer,
    pub width: u32,
    pub height: u32,
}

impl VisibilityTargets {
    fn new(
        ctx: &Arc<Context>,
        render_pass: vk::RenderPass,
        width: u32,
        height: u32,
    ) -> Result<Self, GpuError> {
        let triangle = DeviceImage::new(
            ctx,
            "raster visibility",
            width,
            height,
            TRIANGLE_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
        )?;
        let depth = DeviceImage::new(
            ctx,
            "raster visibility depth",
            width,
            height,
            SCENE_DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        let buffer = Buffer::new(
            ctx,
            "raster visibility buffer",
            u64::from(width) * u64::from(height) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let framebuffer = Framebuffer::new(
            ctx,
            render_pass,
            &[triangle.view, depth.view],
            width,
            height,
        )?;
        Ok(Self {
            framebuffer,
            triangle,
            depth,
            buffer,
            width,
            height,
        })
    }
}

pub(crate) struct VisibilityPass {
    ctx: Arc<Context>,
    pipeline: Pipeline,
    pub targets: Option<VisibilityTargets>,
    render_pass: RenderPass,
}

impl VisibilityPass {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let render_pass = scene_render_pass(
            ctx,
            &[TRIANGLE_FORMAT],
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        )?;
        let pipeline = Pipeline::graphics(
            ctx,
            VisibilitySet::DECL,
            &GraphicsDesc {
                vert: shader::VISIBILITY_VERT,
                frag: shader::VISIBILITY_FRAG,
                render_pass: render_pass.handle,
                color_attachments: 1,
                depth_compare: vk::CompareOp::GREATER,
                surface_variants: SURFACE_ALPHA_TESTED | SURFACE_SINGLE_SIDED,
                plain: Some((shader::VISIBILITY_PLAIN_VERT, shader::VISIBILITY_PLAIN_FRAG)),
            },
        )?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            targets: None,
            render_pass,
        })
    }

    /// Points the pipeline's set at a newly loaded scene.
    pub(crate) fn bind_scene(&self, scene: &SceneBuffers) {
        scene.bind(&self.pipeline);
    }

    /// Makes the targets `width` x `height` (recreating them on a size change); returns them
    /// when they were recreated (their buffer must be bound again).
    pub(crate) fn ensure_targets(
        &mut self,
        width: u32,
        height: u32,
    ) -> Result<Option<&VisibilityTargets>, GpuError> {
        if self
            .targets
            .as_ref()
            .is_some_and(|t| t.width == width && t.height == height)
        {
            return Ok(None);
        }
        // The old images go before the new ones are allocated.
        self.targets = None;
        let targets = VisibilityTargets::new(&self.ctx, self.render_pass.handle, width, height)?;
        Ok(Some(self.targets.insert(targets)))
    }

    /// Records the pass of camera sample `sample`, shared by every pixel: pixel (0, 0)'s
    /// sample (`sampler::shared_pixel_sampler`), whose film position is the offset within the
    /// pixel. See `record`.
    pub(crate) fn record_sample(
        &self,
        rec: &mut Recorder<'_>,
        scene: &SceneBuffers,
        camera: &Camera,
        settings: &RenderSettings,
        sample: u32,
    ) {
        let shared = shared_pixel_sampler(settings.sampler, settings.seed, UVec2::ZERO);
        let cs = pixel_camera_sample(&shared, sample);
        let blend = Some((settings.seed, sample));
        self.record(rec, scene, camera, (cs.film, cs.lens), blend);
    }

    /// Records the pass along each pixel's aperture-centre ray through its centre (the hybrid's
    /// lit pre-pass shades what it sees: trace.comp, TRACE_MODE_SHORTCUT). `camera` is the
    /// traced camera; its raster counterpart is taken here.
    pub(crate) fn record_aperture_centre(
        &self,
        rec: &mut Recorder<'_>,
        scene: &SceneBuffers,
        camera: &Camera,
    ) {
        // Film offset 0.5 is the pixel centre; lens_u (0.5, 0.5) the lens centre
        // (concentric_sample_disk), as first_order_ray is given them in the pre-pass.
        let centre = Vec2::splat(0.5);
        let camera = camera.for_rasterizing_rays();
        self.record(rec, scene, &camera, (centre, centre), None);
    }

    /// Records the pass for one camera sample shared by every pixel (`film_u`, `lens_u`; the
    /// camera as `Camera::for_rasterizing_rays` gives it), whose BLEND cuts are drawn with the
    /// seed and sample index `blend` (`None`: the aperture-centre rays' fixed threshold), and
    /// the copy into the buffer, whose
    /// writes are then ordered before compute-shader reads. Earlier compute reads of the
    /// buffer are ordered before the copy.
    pub(crate) fn record(
        &self,
        rec: &mut Recorder<'_>,
        scene: &SceneBuffers,
        camera: &Camera,
        (film_u, lens_u): (Vec2, Vec2),
        blend: Option<(u32, u32)>,
    ) {
        let targets = self.targets.as_ref().expect("ensure_targets first");
        let (width, height) = (targets.width, targets.height);
        let (seed, sample_index) = blend.unwrap_or((0, 0));
        let push = VisibilityPush {
            clip_from_world: camera
                .clip_from_world_through_lens(film_u, lens_u)
                .to_cols_array(),
            seed,
            width,
            sample_index,
            aperture_centre: u32::from(blend.is_none()),
        };
        let clear = [
            vk::ClearValue {
                color: vk::ClearColorValue { uint32: [0; 4] },
            },
            // Reversed depth: 0 is the far plane.
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 0.0,
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
        // The render pass left the image in TRANSFER_SRC_OPTIMAL and its outgoing dependency
        // orders the attachment writes before this copy; the buffer holds a uint per pixel, and
        // the previous sample's shading pass read it (the recorder orders the copy after).
        rec.copy_image_to_buffer(
            targets.triangle.image,
            &targets.buffer,
            [0, 0],
            [width, height],
        );
    }
}
