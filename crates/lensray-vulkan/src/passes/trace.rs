//! The thin-lens compute pass (shaders/passes/trace.comp): camera samples traced with one
//! pipeline per traversal the device was opened for (ray queries, or the software BVH
//! traversal; the one in use is `traversal()`), split into dispatches of bounded size (bands of
//! rows x ranges of samples), several per submission, none waited for until the last. The
//! shader adds to a band's sums in a float buffer, copied in and out of the accumulation's film
//! (`films`), which stays on the device: the host reads it only when asked.
//!
//! The pass and its pipelines and bindings live here; `record` holds what it records into a
//! command buffer, `steps` how one call is split into dispatches, `accumulate` the renderer's
//! entry that submits them and waits, `timings` what the timestamps and ray counter say.

mod accumulate;
mod record;
mod steps;
#[cfg(test)]
mod tests;
mod timings;

pub(crate) use accumulate::RecordSamples;

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::query::QueryPool;
use crate::core::shader;
use crate::passes::aperture::ApertureTable;
use crate::passes::films::DeviceFilms;
use crate::passes::lens::LensBuffer;
use crate::scene::SceneBuffers;
use crate::traversal::Traversal;
use lensray_core::camera::Camera;
use lensray_core::interface::{
    AccumulationGroup, DescriptorSet, HybridTraceGroup, RasterTraceGroup, TlasGroup, TraceGroup,
    TraceParams, TraceRayQuerySet, TraceSoftwareSet,
};

use accumulate::BandSums;
pub use timings::Timings;

/// Pixel-samples of the first dispatches: ~0.03-0.1 s on lavapipe (2 cores, 80k triangles).
const INITIAL_SAMPLES_PER_DISPATCH: u64 = 1 << 16;
/// The most pixel-samples per dispatch, however fast the device.
pub(crate) const MAX_SAMPLES_PER_DISPATCH: u64 = 1 << 22;

/// Most pixels whose sums are held at once (64 MiB); larger images go in bands of rows.
const MAX_BAND_PIXELS: u64 = 1 << 22;

/// The pipeline of one traversal.
struct TracePipeline {
    traversal: Traversal,
    pipeline: Pipeline,
    /// The SURFACE_* bits it is specialized for: those of the scene bound (none before one is).
    surfaces: u32,
    /// Its first dispatch (lazily compiled by some drivers) is timed apart.
    first_dispatch_done: bool,
}

pub(crate) struct TracePass {
    ctx: Arc<Context>,
    /// One per traversal of the device, in `ctx.traversals` order.
    pipelines: Vec<TracePipeline>,
    /// Index of the one in use.
    current: usize,
    params: Buffer,
    counters: Buffer,
    /// The hybrid path's plan (one vec4 per pixel, `HybridTraceGroup`); a placeholder of
    /// one entry while none is set (the binding must be valid in every mode).
    plan: Buffer,
    /// Per pixel of the plan: the camera-space depth of the surface the G-buffer sees (0:
    /// none), from the device plan (`HybridTraceGroup`).
    surface_depth: Buffer,
    /// Pixels of the plan the device plan pass wrote (`use_device_plan`); `None`: no plan.
    plan_pixels: Option<u64>,
    /// The hybrid's lit pre-pass counted rays into the counter's word 2, not yet reported.
    prepass_rays_pending: bool,
    /// Placeholder of the raster path's visibility binding until `bind_visibility`.
    _visibility_placeholder: Buffer,
    /// The visibility and accumulation buffers the pipelines' sets hold now (the recorder
    /// orders the dispatches after their writes).
    bound_visibility: vk::Buffer,
    bound_accum: vk::Buffer,
    /// Placeholder of the accumulation binding until a render or the preview binds one.
    _accum_placeholder: Buffer,
    timestamps: QueryPool,
    /// The band of sums the shader adds to, for the current image size.
    accum: Option<BandSums>,
    /// The accumulations' sums on the device.
    pub films: DeviceFilms,
    /// The aperture image's tables (`ApertureGroup`).
    aperture: ApertureTable,
    /// The real lens (`LensGroup`).
    lens: LensBuffer,
    /// Upper bound of pixel-samples per dispatch (tests lower it to force many submissions).
    pub samples_per_dispatch: u64,
    /// Current size of a dispatch, adapted to the measured speed.
    adaptive_samples: u64,
    pub max_band_pixels: u64,
}

impl TracePass {
    /// Creates a pipeline for each traversal of `ctx.traversals`; the first is in use.
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let pipelines = ctx
            .traversals
            .iter()
            .map(|&t| {
                Ok(TracePipeline {
                    traversal: t,
                    pipeline: Self::pipeline(ctx, t)?,
                    surfaces: 0,
                    first_dispatch_done: false,
                })
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        if pipelines.is_empty() {
            return Err(GpuError::Invalid(
                "the device was opened with no traversal to trace with".into(),
            ));
        }
        let params = Buffer::new(
            ctx,
            "trace params",
            std::mem::size_of::<TraceParams>() as u64,
            // TRANSFER_DST: the preview updates it inside its frames' command buffers.
            vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::CpuToGpu,
        )?;
        let counters = Buffer::new(
            ctx,
            "trace ray counter",
            16,
            // TRANSFER_SRC: the first dispatch's count is copied into the second word.
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let plan = Self::plan_buffer(ctx, 16)?;
        let surface_depth = Self::surface_depth_buffer(ctx, 16)?;
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
        // Until a render or the preview binds its own: the hybrid's lit pre-pass (which does
        // not touch the sums) may run first, and every binding must be valid.
        let accum_placeholder = placeholder("trace accumulation placeholder")?;
        let aperture = ApertureTable::new(ctx)?;
        let lens = LensBuffer::new(ctx)?;
        for p in &pipelines {
            let pipeline = &p.pipeline;
            pipeline.bind_group(&TraceGroup::<Gpu> {
                params: &params,
                counters: &counters,
            });
            pipeline.bind_group(&AccumulationGroup::<Gpu> {
                accum: &accum_placeholder,
            });
            pipeline.bind_group(&HybridTraceGroup::<Gpu> {
                plan: &plan,
                surface_depth: &surface_depth,
            });
            pipeline.bind_group(&RasterTraceGroup::<Gpu> {
                visibility: &visibility,
            });
            aperture.bind(pipeline);
            lens.bind(pipeline);
        }
        let timestamps = QueryPool::new(ctx, vk::QueryType::TIMESTAMP, 2)?;
        Ok(Self {
            ctx: ctx.clone(),
            pipelines,
            current: 0,
            params,
            counters,
            plan,
            surface_depth,
            plan_pixels: None,
            prepass_rays_pending: false,
            bound_visibility: visibility.buffer,
            bound_accum: accum_placeholder.buffer,
            _visibility_placeholder: visibility,
            _accum_placeholder: accum_placeholder,
            timestamps,
            accum: None,
            films: DeviceFilms::new(ctx),
            aperture,
            lens,
            samples_per_dispatch: MAX_SAMPLES_PER_DISPATCH,
            adaptive_samples: INITIAL_SAMPLES_PER_DISPATCH,
            max_band_pixels: MAX_BAND_PIXELS,
        })
    }

    fn plan_buffer(ctx: &Arc<Context>, bytes: u64) -> Result<Buffer, GpuError> {
        // Written by the device plan pass, read (and, lit, completed by
        // the shortcut pre-pass) by the shader; host-visible so that the device plan reads back.
        Buffer::new(
            ctx,
            "hybrid plan",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )
    }

    /// Later `accumulate` calls follow no plan (the hybrid's mode is refused until a new one).
    pub(crate) fn clear_plan(&mut self) {
        self.plan_pixels = None;
    }

    /// Makes the plan buffer hold at least `pixels` entries, and the surface depths as many (new
    /// buffers, bound to every pipeline, when they are smaller). No submission using them may
    /// be pending.
    pub(crate) fn ensure_plan_capacity(&mut self, pixels: u64) -> Result<(), GpuError> {
        let bytes = (pixels * 16).max(16);
        if self.plan.size < bytes {
            self.plan = Self::plan_buffer(&self.ctx, bytes)?;
            self.surface_depth = Self::surface_depth_buffer(&self.ctx, bytes / 4)?;
            for p in &self.pipelines {
                p.pipeline.bind_group(&HybridTraceGroup::<Gpu> {
                    plan: &self.plan,
                    surface_depth: &self.surface_depth,
                });
            }
        }
        Ok(())
    }

    fn surface_depth_buffer(ctx: &Arc<Context>, bytes: u64) -> Result<Buffer, GpuError> {
        // Written by the device plan, read by the hybrid's lit shortcut samples.
        Buffer::new(
            ctx,
            "hybrid surface depth",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )
    }

    /// Points the raster path's visibility binding at `buffer` (one uint per pixel, owned by
    /// the visibility pass, which outlives the pass's use of it).
    pub(crate) fn bind_visibility(&mut self, buffer: &Buffer) {
        self.bound_visibility = buffer.buffer;
        for p in &self.pipelines {
            p.pipeline
                .bind_group(&RasterTraceGroup::<Gpu> { visibility: buffer });
        }
    }

    /// The plan buffer (for the device plan pass to write).
    pub(crate) fn plan_buffer_ref(&self) -> &Buffer {
        &self.plan
    }

    /// The surface depths (for the device plan pass to write).
    pub(crate) fn surface_depth_ref(&self) -> &Buffer {
        &self.surface_depth
    }

    /// Later `accumulate` calls follow the plan of `pixels` entries that the device plan pass
    /// wrote into the plan buffer.
    pub(crate) fn use_device_plan(&mut self, pixels: u64) {
        self.plan_pixels = Some(pixels);
    }

    /// The plan's entries as the device left them (host-visible buffer; the caller waited for
    /// the submissions that wrote it).
    #[cfg(feature = "probes")]
    pub(crate) fn read_plan(&self, pixels: u64) -> Result<Vec<[f32; 4]>, GpuError> {
        let entries: &[[f32; 4]] = bytemuck::cast_slice(self.plan.read()?);
        entries
            .get(..pixels as usize)
            .map(<[_]>::to_vec)
            .ok_or_else(|| GpuError::Invalid(format!("the plan buffer has no {pixels} entries")))
    }

    /// The compute pipeline of `traversal`: the scene arrays, that traversal's structures, and
    /// the pass's own buffers.
    /// Specialized for scenes without textures or alpha tests until `bind_scene` says otherwise.
    fn pipeline(ctx: &Arc<Context>, traversal: Traversal) -> Result<Pipeline, GpuError> {
        let set = match traversal {
            Traversal::RayQuery => TraceRayQuerySet::DECL,
            Traversal::Software => TraceSoftwareSet::DECL,
        };
        Pipeline::compute_specialized(ctx, set, trace_spirv(traversal), Some(0))
    }

    /// The traversals this pass can trace with.
    pub(crate) fn traversals(&self) -> Vec<Traversal> {
        self.pipelines.iter().map(|p| p.traversal).collect()
    }

    /// The traversal in use.
    pub(crate) fn traversal(&self) -> Traversal {
        self.pipelines[self.current].traversal
    }

    /// Uses `traversal` from now on; an error when the device was not opened for it.
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
        Ok(())
    }

    fn pipeline_in_use(&self) -> &Pipeline {
        &self.pipelines[self.current].pipeline
    }

    /// Binds `scene` to every pipeline, first specialized anew where the scene's surfaces
    /// differ from the last one's. No submission using the pipelines may be pending.
    pub(crate) fn bind_scene(&mut self, scene: &SceneBuffers) -> Result<(), GpuError> {
        for p in &mut self.pipelines {
            if p.surfaces != scene.surfaces {
                p.pipeline
                    .respecialize(trace_spirv(p.traversal), scene.surfaces)?;
                p.surfaces = scene.surfaces;
                p.first_dispatch_done = false;
            }
            scene.bind(&p.pipeline);
            match p.traversal {
                Traversal::RayQuery => {
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
        Ok(())
    }

    /// Makes the aperture tables and the real lens those of `camera` (see
    /// `ApertureTable::ensure`, `LensBuffer::ensure`), binding them anew when they change.
    /// Called before recording work with `camera`'s parameters.
    pub(crate) fn ensure_camera_tables(&mut self, camera: &Camera) -> Result<(), GpuError> {
        if self.aperture.ensure(camera)? {
            for p in &self.pipelines {
                self.aperture.bind(&p.pipeline);
            }
        }
        if self.lens.ensure(camera)? {
            for p in &self.pipelines {
                self.lens.bind(&p.pipeline);
            }
        }
        Ok(())
    }

    /// Whether `ensure_camera_tables(camera)` would upload new tables (and wait for the
    /// device).
    pub(crate) fn camera_tables_differ(&self, camera: &Camera) -> bool {
        self.aperture.differs(camera) || self.lens.differs(camera)
    }

    /// Points every pipeline's accumulation binding at `buffer`.
    fn bind_accum_buffer(&mut self, buffer: &Buffer) {
        self.bound_accum = buffer.buffer;
        for p in &self.pipelines {
            p.pipeline
                .bind_group(&AccumulationGroup::<Gpu> { accum: buffer });
        }
    }

    /// Points the pass at an accumulation buffer of the caller's (the preview's, one vec4 per
    /// pixel of the whole image); a later `render` makes and binds its own again.
    pub(crate) fn bind_accumulation(&mut self, buffer: &Buffer) {
        self.accum = None;
        self.bind_accum_buffer(buffer);
    }
}

/// The trace shader of `traversal`.
fn trace_spirv(traversal: Traversal) -> &'static [u8] {
    match traversal {
        Traversal::RayQuery => shader::TRACE_RAYQUERY_COMP,
        Traversal::Software => shader::TRACE_SOFTWARE_COMP,
    }
}
