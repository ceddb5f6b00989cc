//! The dispatch of an estimator: the trace shader's pipelines, one per traversal the device was
//! opened for (the one in use is `traversal()`; compute pipelines, and for the ray-tracing
//! pipeline's traversal a ray-tracing pipeline whose launch stands for the dispatch's
//! workgroups), each built when it is first used with a scene, specialized for that scene's
//! surfaces (a traversal never used is never compiled: lavapipe takes seconds over each);
//! the buffers their sets hold, placeholders until a render, the preview or the raster path
//! binds its own (every binding must be valid in every mode); and the recording of dispatches,
//! each naming to the recorder what it reads and writes.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::query::QueryPool;
use crate::core::recorder::{Access, Recorder};
use crate::core::shader;
use crate::scene::SceneBuffers;
use crate::traversal::Traversal;
use lensray_core::interface::{
    AccumulationGroup, BindingGroup, DescriptorSet, HybridTraceGroup, RasterTraceGroup, TlasGroup,
    TraceGroup, TracePush, TraceRayQuerySet, TraceRtPipelineSet, TraceSoftwareSet,
    TRACE_GROUP_SIZE as GROUP,
};

/// The pipeline of one traversal.
struct TracePipeline {
    traversal: Traversal,
    pipeline: Pipeline,
    /// The SURFACE_* bits its code is specialized for; `None` until it is built (when it is in
    /// use with a scene bound).
    surfaces: Option<u32>,
    /// Its first dispatch (lazily compiled by some drivers) is timed apart.
    first_dispatch_done: bool,
}

/// The buffers every pipeline's set holds now: the recorder orders each dispatch after their
/// writes.
struct BoundBuffers {
    params: vk::Buffer,
    counters: vk::Buffer,
    accum: vk::Buffer,
    plan: vk::Buffer,
    surface_depth: vk::Buffer,
    visibility: vk::Buffer,
}

pub(crate) struct TracePipelines {
    ctx: Arc<Context>,
    /// One per traversal of the device, in `ctx.traversals` order.
    pipelines: Vec<TracePipeline>,
    /// Index of the one in use.
    current: usize,
    bound: BoundBuffers,
    /// Placeholder of the accumulation binding until a render or the preview binds one: the
    /// hybrid's lit pre-pass (which does not touch the sums) may run first.
    accum_placeholder: Buffer,
    /// Placeholder of the raster path's visibility binding until `bind_visibility`.
    visibility_placeholder: Buffer,
    /// Whether the bound scene has an environment map (`TraceParams.environment_map`).
    pub(crate) environment_map: bool,
    /// The SURFACE_* bits of the bound scene (`None` before one is).
    scene_surfaces: Option<u32>,
}

impl TracePipelines {
    /// Creates the layout of a pipeline for each traversal of `ctx.traversals` (the first is in
    /// use; its code is built with the first scene), its accumulation and visibility bound to
    /// placeholders. The parameters and the plan are bound
    /// next (`bind_parameters`, `bind_plan`), before any dispatch.
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let pipelines = ctx
            .traversals
            .iter()
            .map(|&t| {
                Ok(TracePipeline {
                    traversal: t,
                    pipeline: Self::layout(ctx, t)?,
                    surfaces: None,
                    first_dispatch_done: false,
                })
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        if pipelines.is_empty() {
            return Err(GpuError::Invalid(
                "the device was opened with no traversal to trace with".into(),
            ));
        }
        let placeholder = |name| {
            Buffer::new(
                ctx,
                name,
                16,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::GpuOnly,
            )
        };
        let visibility = placeholder("raster visibility placeholder")?;
        let accum = placeholder("trace accumulation placeholder")?;
        let null = vk::Buffer::null();
        let this = Self {
            ctx: ctx.clone(),
            pipelines,
            current: 0,
            bound: BoundBuffers {
                params: null,
                counters: null,
                accum: accum.buffer,
                plan: null,
                surface_depth: null,
                visibility: visibility.buffer,
            },
            accum_placeholder: accum,
            visibility_placeholder: visibility,
            environment_map: false,
            scene_surfaces: None,
        };
        this.bind_group(&AccumulationGroup::<Gpu> {
            accum: &this.accum_placeholder,
        });
        this.bind_group(&RasterTraceGroup::<Gpu> {
            visibility: &this.visibility_placeholder,
        });
        Ok(this)
    }

    /// The layout and set of `traversal`'s pipeline (the scene arrays, that traversal's
    /// structures, and the pass's own buffers), its code not yet built (`build_current`).
    fn layout(ctx: &Arc<Context>, traversal: Traversal) -> Result<Pipeline, GpuError> {
        let (set, bind_point) = match traversal {
            Traversal::RayQuery => (TraceRayQuerySet::DECL, vk::PipelineBindPoint::COMPUTE),
            Traversal::Software => (TraceSoftwareSet::DECL, vk::PipelineBindPoint::COMPUTE),
            Traversal::RtPipeline => (
                TraceRtPipelineSet::DECL,
                vk::PipelineBindPoint::RAY_TRACING_KHR,
            ),
        };
        Pipeline::unbuilt(ctx, set, bind_point)
    }

    /// Builds the pipeline in use for the bound scene's surfaces where its code is for others
    /// or not yet made; nothing before a scene is bound. No submission using it may be pending.
    fn build_current(&mut self) -> Result<(), GpuError> {
        let Some(surfaces) = self.scene_surfaces else {
            return Ok(());
        };
        let p = &mut self.pipelines[self.current];
        if p.surfaces != Some(surfaces) {
            match p.traversal {
                Traversal::RtPipeline => p
                    .pipeline
                    .respecialize_ray_tracing(&shader::TRACE_RTPIPELINE, surfaces)?,
                t => p.pipeline.respecialize(trace_spirv(t), surfaces)?,
            }
            p.surfaces = Some(surfaces);
            p.first_dispatch_done = false;
        }
        Ok(())
    }

    /// The traversals the pass can trace with.
    pub(crate) fn traversals(&self) -> Vec<Traversal> {
        self.pipelines.iter().map(|p| p.traversal).collect()
    }

    /// The traversal in use.
    pub(crate) fn traversal(&self) -> Traversal {
        self.pipelines[self.current].traversal
    }

    /// Uses `traversal` from now on, built for the bound scene; an error when the device was
    /// not opened for it. No submission using the pipelines may be pending.
    pub(crate) fn set_traversal(&mut self, traversal: Traversal) -> Result<(), GpuError> {
        let index = self
            .pipelines
            .iter()
            .position(|p| p.traversal == traversal)
            .ok_or_else(|| GpuError::TraversalUnavailable {
                traversal,
                device: self.ctx.report.name.clone(),
                available: self
                    .traversals()
                    .iter()
                    .map(|t| t.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            })?;
        self.current = index;
        self.build_current()
    }

    /// Whether the pipeline in use dispatched before (its first dispatch is timed apart).
    pub(crate) fn first_dispatch_done(&self) -> bool {
        self.pipelines[self.current].first_dispatch_done
    }

    /// The first dispatch of the pipeline in use was timed.
    pub(crate) fn first_dispatch_timed(&mut self) {
        self.pipelines[self.current].first_dispatch_done = true;
    }

    /// Calls `bind` with every pipeline (the camera tables bind themselves to each).
    pub(crate) fn bind_each(&self, bind: impl Fn(&Pipeline)) {
        for p in &self.pipelines {
            bind(&p.pipeline);
        }
    }

    fn bind_group<'a, G: BindingGroup<Gpu<'a>>>(&self, group: &G) {
        self.bind_each(|p| p.bind_group(group));
    }

    /// Binds `scene` to every pipeline; the one in use is built anew where the scene's surfaces
    /// differ from those it was built for, the others when they are next used. No submission
    /// using the pipelines may be pending.
    pub(crate) fn bind_scene(&mut self, scene: &SceneBuffers) -> Result<(), GpuError> {
        self.scene_surfaces = Some(scene.surfaces);
        self.build_current()?;
        for p in &mut self.pipelines {
            scene.bind(&p.pipeline);
            scene.environment.bind(&p.pipeline);
            match p.traversal {
                Traversal::RayQuery | Traversal::RtPipeline => {
                    if let Some(accel) = &scene.accel {
                        p.pipeline.bind_group(&TlasGroup::<Gpu> {
                            tlas: accel.tlas.handle,
                        });
                    }
                }
                Traversal::Software => {
                    if let Some(bvh) = &scene.bvh {
                        bvh.bind(&p.pipeline);
                    }
                }
            }
        }
        self.environment_map = scene.environment.has_map;
        Ok(())
    }

    /// Points every pipeline at the uniform parameters and the ray counter.
    pub(crate) fn bind_parameters(&mut self, params: &Buffer, counters: &Buffer) {
        (self.bound.params, self.bound.counters) = (params.buffer, counters.buffer);
        self.bind_group(&TraceGroup::<Gpu> { params, counters });
    }

    /// Points every pipeline's accumulation binding at `accum` (a band of sums, or the
    /// preview's accumulation).
    pub(crate) fn bind_accumulation(&mut self, accum: &Buffer) {
        self.bound.accum = accum.buffer;
        self.bind_group(&AccumulationGroup::<Gpu> { accum });
    }

    /// Points every pipeline at the hybrid's plan and surface depths.
    pub(crate) fn bind_plan(&mut self, plan: &Buffer, surface_depth: &Buffer) {
        (self.bound.plan, self.bound.surface_depth) = (plan.buffer, surface_depth.buffer);
        self.bind_group(&HybridTraceGroup::<Gpu> {
            plan,
            surface_depth,
        });
    }

    /// Points the raster path's visibility binding at `visibility` (one uint per pixel, owned
    /// by the visibility pass, which outlives the pipelines' use of it).
    pub(crate) fn bind_visibility(&mut self, visibility: &Buffer) {
        self.bound.visibility = visibility.buffer;
        self.bind_group(&RasterTraceGroup::<Gpu> { visibility });
    }

    /// What a dispatch reads and writes: the parameters, the ray counter, the accumulation
    /// bound, the hybrid's plan (the lit pre-pass writes it) and surface depths, and the raster
    /// path's visibility.
    fn dispatch_uses(&self) -> [(vk::Buffer, Access); 6] {
        let b = &self.bound;
        [
            (b.params, Access::Uniform),
            (b.counters, Access::ComputeWrite),
            (b.accum, Access::ComputeWrite),
            (b.plan, Access::ComputeWrite),
            (b.surface_depth, Access::ComputeRead),
            (b.visibility, Access::ComputeRead),
        ]
    }

    /// Records one dispatch of the pipeline in use over the blocks and samples `push` names, of
    /// an image `width` pixels wide, after what it reads was written.
    pub(crate) fn record_dispatch(&self, rec: &mut Recorder<'_>, push: TracePush, width: u32) {
        self.record(rec, push, [width.div_ceil(GROUP), push.block_count, 1]);
    }

    /// Records `groups` workgroups of the pipeline in use: a compute dispatch, or the launch of
    /// the ray-tracing pipeline's invocations that stand for them.
    fn record(&self, rec: &mut Recorder<'_>, push: TracePush, groups: [u32; 3]) {
        let p = &self.pipelines[self.current];
        debug_assert!(
            p.surfaces.is_some(),
            "a trace dispatch before a scene is bound"
        );
        let push = bytemuck::bytes_of(&push);
        match p.traversal {
            Traversal::RtPipeline => {
                let launch = [groups[0] * GROUP, groups[1] * GROUP, groups[2]];
                rec.trace_rays(&p.pipeline, push, launch, &self.dispatch_uses());
            }
            Traversal::RayQuery | Traversal::Software => {
                rec.dispatch(&p.pipeline, push, groups, &self.dispatch_uses());
            }
        }
    }

    /// Records the pipeline's first dispatch, one that traces nothing (its push names no blocks:
    /// every invocation leaves at once), between timestamps `query` and `query + 1` of
    /// `timestamps`. A driver that compiles lazily (lavapipe's llvmpipe) compiles the shaders in
    /// a pipeline's first dispatch, half a minute on a device's first use: timed apart here,
    /// that stays out of the render's tracing time and rays per second (`Timings::compile_ms`).
    pub(crate) fn record_compile(
        &self,
        rec: &mut Recorder<'_>,
        mode: u32,
        (timestamps, query): (&QueryPool, u32),
    ) {
        let push = TracePush {
            band_origin: 0,
            band_height: 0,
            block_first: 0,
            block_stride: 1,
            block_count: 0,
            sample_begin: 0,
            sample_end: 0,
            mode,
        };
        rec.timestamp(timestamps, vk::PipelineStageFlags::TOP_OF_PIPE, query);
        self.record(rec, push, [1, 1, 1]);
        rec.timestamp(
            timestamps,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            query + 1,
        );
    }
}

/// The compute shader of `traversal` (the ray-tracing pipeline's ray generation stage for
/// `RtPipeline`, which no compute pipeline runs).
fn trace_spirv(traversal: Traversal) -> &'static [u8] {
    match traversal {
        Traversal::RayQuery => shader::TRACE_RAYQUERY_COMP,
        Traversal::Software => shader::TRACE_SOFTWARE_COMP,
        Traversal::RtPipeline => shader::TRACE_RTPIPELINE.raygen,
    }
}
