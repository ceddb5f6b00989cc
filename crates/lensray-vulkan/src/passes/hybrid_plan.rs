//! The hybrid path's plan on the device (shaders/passes/hybrid_plan.comp): from the G-buffer images
//! already drawn in the same command buffer into the trace pass's plan buffer
//! (`HybridTraceGroup`), with no readback. The rules are those of the host's reference
//! `probes::hybrid_plan::Plan::new`; tests/hybrid.rs checks that both plans are equal.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::image::Transition;
use crate::core::pipeline::Pipeline;
use crate::core::recorder::{Access, Recorder};
use crate::core::shader;
use crate::passes::gbuffer::GBufferTargets;
use lensray_core::camera::Camera;
use lensray_core::interface::{
    DescriptorSet, HybridPlanGroup, HybridPlanPush, HybridPlanSet, HYBRID_PLAN_GROUP_SIZE,
    HYBRID_PLAN_STEP_COLUMNS, HYBRID_PLAN_STEP_DILATE, HYBRID_PLAN_STEP_ENTRIES,
    HYBRID_PLAN_STEP_ROWS, HYBRID_PLAN_STEP_TILES, HYBRID_SEGMENT, HYBRID_TILE, SHADING_LIT,
    SHADING_UNLIT,
};
use lensray_core::settings::Shading;

// hybrid_plan.comp's ENTRIES step takes a segment to be one tile row, and a tile to be one
// workgroup.
const _: () = assert!(HYBRID_SEGMENT == HYBRID_TILE);
const _: () = assert!(HYBRID_TILE * HYBRID_TILE == HYBRID_PLAN_GROUP_SIZE);

/// The plan pass's scratch buffers of one image size.
struct Scratch {
    /// Per tile: the maximum CoC of its pixels (f32), then per tile its dilated CoC.
    tiles: Buffer,
    /// The summed-area table of edge marks, (width + 1) x (height + 1) u32.
    edges: Buffer,
    width: u32,
    height: u32,
}

pub(crate) struct HybridPlanPass {
    ctx: Arc<Context>,
    pipeline: Pipeline,
    scratch: Option<Scratch>,
    /// The trace pass's plan and surface-depth buffers bound (the recorder orders the plan's
    /// writes against the trace pass's reads).
    bound_plan: vk::Buffer,
    bound_surface_depth: vk::Buffer,
}

impl HybridPlanPass {
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let pipeline = Pipeline::compute(ctx, HybridPlanSet::DECL, shader::HYBRID_PLAN_COMP)?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            scratch: None,
            bound_plan: vk::Buffer::null(),
            bound_surface_depth: vk::Buffer::null(),
        })
    }

    /// Binds the G-buffer `targets` and the trace pass's `plan` and `surface_depth` buffers (at
    /// least one entry per pixel), with scratch buffers of the targets' size. No submission
    /// using the pass may be pending (descriptor updates).
    pub(crate) fn bind(
        &mut self,
        targets: &GBufferTargets,
        plan: &Buffer,
        surface_depth: &Buffer,
    ) -> Result<(), GpuError> {
        let (width, height) = (targets.width, targets.height);
        if plan.size < u64::from(width) * u64::from(height) * 16 {
            return Err(GpuError::Invalid(format!(
                "a {}-byte plan buffer for a {width}x{height} image",
                plan.size
            )));
        }
        if self
            .scratch
            .as_ref()
            .is_none_or(|s| (s.width, s.height) != (width, height))
        {
            self.scratch = None;
            let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
            let tiles = u64::from(width.div_ceil(HYBRID_TILE) * height.div_ceil(HYBRID_TILE));
            let table = (u64::from(width) + 1) * (u64::from(height) + 1);
            self.scratch = Some(Scratch {
                tiles: Buffer::new(
                    &self.ctx,
                    "hybrid plan tiles",
                    tiles * 8,
                    usage,
                    MemoryLocation::GpuOnly,
                )?,
                edges: Buffer::new(
                    &self.ctx,
                    "hybrid plan edge table",
                    table * 4,
                    usage,
                    MemoryLocation::GpuOnly,
                )?,
                width,
                height,
            });
        }
        let scratch = self.scratch.as_ref().expect("created above");
        (self.bound_plan, self.bound_surface_depth) = (plan.buffer, surface_depth.buffer);
        self.pipeline.bind_group(&HybridPlanGroup::<Gpu> {
            g_normal: targets.normal.view,
            g_albedo: targets.albedo.view,
            g_depth: targets.view_depth.view,
            tiles: &scratch.tiles,
            edges: &scratch.edges,
            plan,
            surface_depth,
        });
        Ok(())
    }

    /// Records the plan of `spp` samples of `shading` seen by `camera` (the lens the CoC is
    /// computed with; the G-buffer was drawn with its planning camera, same rays and pixels)
    /// after the G-buffer pass: the images go from TRANSFER_SRC_OPTIMAL to GENERAL and back, the
    /// plan's writes are ordered before later compute reads.
    pub(crate) fn record(
        &self,
        rec: &mut Recorder<'_>,
        targets: &GBufferTargets,
        camera: &Camera,
        shading: Shading,
        spp: u32,
    ) {
        targets.record_to_general(rec, vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
        let (width, height) = (targets.width, targets.height);
        let (tiles_x, tiles_y) = (width.div_ceil(HYBRID_TILE), height.div_ceil(HYBRID_TILE));
        let push = |step| HybridPlanPush {
            width,
            height,
            tiles_x,
            tiles_y,
            step,
            shading: if shading == Shading::Lit {
                SHADING_LIT
            } else {
                SHADING_UNLIT
            },
            spp,
            coc: crate::upload::gpu_coc_lens(camera),
        };
        // One invocation per tile, row, column, tile, segment.
        let steps = [
            (HYBRID_PLAN_STEP_TILES, tiles_x * tiles_y),
            (HYBRID_PLAN_STEP_ROWS, height),
            (HYBRID_PLAN_STEP_COLUMNS, width),
            (HYBRID_PLAN_STEP_DILATE, tiles_x * tiles_y),
            (HYBRID_PLAN_STEP_ENTRIES, tiles_x * height),
        ];
        let scratch = self.scratch.as_ref().expect("bind made it");
        let uses = [
            (scratch.tiles.buffer, Access::ComputeWrite),
            (scratch.edges.buffer, Access::ComputeWrite),
            (self.bound_plan, Access::ComputeWrite),
            (self.bound_surface_depth, Access::ComputeWrite),
        ];
        for (step, invocations) in steps {
            let groups = [invocations.div_ceil(HYBRID_PLAN_GROUP_SIZE), 1, 1];
            rec.dispatch(
                &self.pipeline,
                bytemuck::bytes_of(&push(step)),
                groups,
                &uses,
            );
        }
        for image in [&targets.normal, &targets.albedo, &targets.view_depth] {
            rec.transition(
                image.image,
                &Transition {
                    old: vk::ImageLayout::GENERAL,
                    new: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    src_stage: vk::PipelineStageFlags::COMPUTE_SHADER,
                    src_access: vk::AccessFlags::empty(),
                    dst_stage: vk::PipelineStageFlags::COMPUTE_SHADER
                        | vk::PipelineStageFlags::TRANSFER,
                    dst_access: vk::AccessFlags::SHADER_READ | vk::AccessFlags::TRANSFER_READ,
                },
            );
        }
    }
}
