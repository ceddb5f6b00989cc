//! The preview's view pass (shaders/present/view.frag): a non-final view (albedo, normal, depth, circle
//! of confusion) rasterized straight into an 8-bit target, the window image. It shows what the
//! G-buffer pass followed by the resolve shows (the same vertex stage, the encodings of
//! shaders/include/views.glsl), for a third of the G-buffer's target bandwidth and without the resolve
//! and the copy into the window: those frames are what a window that only frames the shot
//! draws, and on lavapipe they are where the frame rate is won (docs/preview.md). Each view has
//! its own pipeline, made when the view is first drawn, whose stages pass only what that view
//! reads (shaders/include/surface_varyings.glsl): lavapipe's cost per fragment grows with the
//! inputs the fragment stage declares.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;

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
use lensray_core::film::colour::linear_to_srgb;
use lensray_core::interface::{
    DescriptorSet, ViewParams, ViewPush, ViewSet, SURFACE_ALPHA_TESTED, SURFACE_SINGLE_SIDED,
    SURFACE_TEXTURED, VIEW_ALBEDO, VIEW_COC, VIEW_FINAL,
};

/// The views the pass draws, VIEW_ALBEDO to VIEW_COC: one pipeline each.
const VIEWS: usize = (VIEW_COC - VIEW_ALBEDO + 1) as usize;

/// One framebuffer per target image, sharing a depth buffer.
struct ViewTargets {
    /// First: dropped before the depth image their views use.
    framebuffers: Vec<Framebuffer>,
    #[expect(dead_code, reason = "owned here: the framebuffers use its view")]
    depth: DeviceImage,
    width: u32,
    height: u32,
}

pub(crate) struct ViewPass {
    ctx: Arc<Context>,
    /// Entry `view - VIEW_ALBEDO`: that view's pipeline, made the first time the view is drawn.
    pipelines: [Option<Pipeline>; VIEWS],
    targets: Option<ViewTargets>,
    render_pass: RenderPass,
    format: vk::Format,
}

impl ViewPass {
    /// Draws into images of `format`, left in `final_layout`.
    pub(crate) fn new(
        ctx: &Arc<Context>,
        format: vk::Format,
        final_layout: vk::ImageLayout,
    ) -> Result<Self, GpuError> {
        let render_pass = scene_render_pass(ctx, &[format], final_layout)?;
        Ok(Self {
            ctx: ctx.clone(),
            pipelines: Default::default(),
            targets: None,
            render_pass,
            format,
        })
    }

    pub(crate) fn format(&self) -> vk::Format {
        self.format
    }

    /// Points the sets of the pipelines made so far at `scene`'s arrays (a new scene). No
    /// frame is in flight.
    pub(crate) fn rebind(&self, scene: &SceneBuffers) {
        for pipeline in self.pipelines.iter().flatten() {
            scene.bind(pipeline);
        }
    }

    /// Makes the pipeline of `view` (VIEW_ALBEDO to VIEW_COC) unless it exists, its set
    /// pointed at `scene`'s arrays.
    pub(crate) fn ensure_view(&mut self, view: u32, scene: &SceneBuffers) -> Result<(), GpuError> {
        let slot = &mut self.pipelines[view_index(view)];
        if slot.is_some() {
            return Ok(());
        }
        let [(vert, frag), plain] = shader::VIEW_STAGES[view_index(view)];
        let pipeline = Pipeline::graphics(
            &self.ctx,
            ViewSet::DECL,
            &GraphicsDesc {
                vert,
                frag,
                render_pass: self.render_pass.handle,
                color_attachments: 1,
                depth_compare: vk::CompareOp::LESS,
                surface_variants: SURFACE_TEXTURED | SURFACE_ALPHA_TESTED | SURFACE_SINGLE_SIDED,
                plain: Some(plain),
            },
        )?;
        scene.bind(&pipeline);
        *slot = Some(pipeline);
        Ok(())
    }

    /// Framebuffers over `views` (target images of `width` x `height`, alive until the next
    /// `attach` or the pass's drop). No frame may be in flight.
    pub(crate) fn attach(
        &mut self,
        views: &[vk::ImageView],
        width: u32,
        height: u32,
    ) -> Result<(), GpuError> {
        self.targets = None;
        let depth = DeviceImage::new(
            &self.ctx,
            "view pass depth",
            width,
            height,
            SCENE_DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        let framebuffers = views
            .iter()
            .map(|&view| {
                Framebuffer::new(
                    &self.ctx,
                    self.render_pass.handle,
                    &[view, depth.view],
                    width,
                    height,
                )
            })
            .collect::<Result<_, _>>()?;
        self.targets = Some(ViewTargets {
            framebuffers,
            depth,
            width,
            height,
        });
        Ok(())
    }

    /// Records view `shown.view` (not VIEW_FINAL; its pipeline made by [`Self::ensure_view`])
    /// of `camera` into target `index`: uncovered pixels show the background in the albedo view
    /// (as the G-buffer's cleared albedo does), black in the others.
    pub(crate) fn record(
        &self,
        rec: &mut Recorder<'_>,
        scene: &SceneBuffers,
        camera: &Camera,
        background: Vec3,
        shown: ViewParams,
        index: usize,
    ) {
        debug_assert_ne!(shown.view, VIEW_FINAL, "the final view is the resolve's");
        let targets = self.targets.as_ref().expect("attach first");
        let pipeline = self.pipelines[view_index(shown.view)]
            .as_ref()
            .expect("ensure_view first");
        let clear_color = if shown.view == VIEW_ALBEDO {
            background.map(|c| linear_to_srgb(c).clamp(0.0, 1.0))
        } else {
            Vec3::ZERO
        };
        let clear = [
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: clear_color.extend(1.0).to_array(),
                },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
        ];
        let push = ViewPush {
            raster: crate::upload::raster_push(camera),
            shown,
        };
        record_scene_draw(
            rec,
            scene,
            &SceneDraw {
                render_pass: self.render_pass.handle,
                framebuffer: targets.framebuffers[index].handle,
                width: targets.width,
                height: targets.height,
                clear: &clear,
                pipeline,
                push: bytemuck::bytes_of(&push),
            },
        );
    }
}

/// The entry of `view` (VIEW_ALBEDO to VIEW_COC) in `ViewPass::pipelines`.
fn view_index(view: u32) -> usize {
    debug_assert!((VIEW_ALBEDO..=VIEW_COC).contains(&view), "view {view}");
    (view - VIEW_ALBEDO) as usize
}
