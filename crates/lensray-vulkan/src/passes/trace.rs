//! The thin-lens compute pass (shaders/passes/trace.comp): camera samples traced with one
//! pipeline per traversal the device was opened for (ray queries, or the software BVH
//! traversal; the one in use is `traversal()`), split into dispatches of bounded size (bands of
//! rows x ranges of samples), several per submission, none waited for until the last. The
//! shader adds to a band's sums in a float buffer, copied in and out of the accumulation's film
//! (`films`), which stays on the device: the host reads it only when asked.

use std::ops::Range;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::{barrier, barrier_to_host, Buffer};
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::{Binding, Pipeline};
use crate::core::query::QueryPool;
use crate::core::shader;
use crate::passes::aperture::ApertureTable;
use crate::passes::films::DeviceFilms;
use crate::passes::lens::LensBuffer;
use crate::scene::{BvhBuffers, SceneBuffers};
use crate::traversal::Traversal;
use lensray_core::camera::Camera;
use lensray_core::film::Accumulation;
use lensray_core::interface::{
    TraceParams, TracePush, TRACE_BINDING_ACCUM, TRACE_BINDING_APERTURE, TRACE_BINDING_COUNTERS,
    TRACE_BINDING_LENS, TRACE_BINDING_PARAMS, TRACE_BINDING_PLAN, TRACE_BINDING_SURFACE_DEPTH,
    TRACE_BINDING_TLAS, TRACE_BINDING_VISIBILITY, TRACE_GROUP_SIZE as GROUP, TRACE_MODE_ALL,
    TRACE_MODE_HYBRID, TRACE_MODE_RASTER, TRACE_MODE_SHORTCUT,
};
use lensray_core::settings::RenderSettings;

/// Pixel-samples of the first dispatches: ~0.03-0.1 s on lavapipe (2 cores, 80k triangles).
const INITIAL_SAMPLES_PER_DISPATCH: u64 = 1 << 16;
/// The most pixel-samples per dispatch, however fast the device.
pub(crate) const MAX_SAMPLES_PER_DISPATCH: u64 = 1 << 22;
/// Dispatch duration aimed at when sizing the next dispatches from the last one's timestamps
/// (well under the ~0.5 s that a single dispatch should not exceed).
const TARGET_DISPATCH_MS: f64 = 100.0;

/// Steps (dispatches) recorded per command buffer: each submission signals the timeline, whose
/// value the progress reads; none is waited for until the last.
const STEPS_PER_SUBMIT: usize = 8;
/// How often the progress reads the timeline while a render runs.
const PROGRESS_POLL: std::time::Duration = std::time::Duration::from_millis(2);

/// Most pixels whose sums are held at once (64 MiB); larger images go in bands of rows.
const MAX_BAND_PIXELS: u64 = 1 << 22;

/// Timing of the GPU passes, from timestamp queries (milliseconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// GPU time of the acceleration-structure builds (BLAS + TLAS) of the loaded scene. lavapipe
    /// builds on the CPU inside the submission, so see also `accel_build_wall_ms`.
    pub accel_build_gpu_ms: f64,
    /// Wall-clock time of the whole build (uploads, builds, compaction).
    pub accel_build_wall_ms: f64,
    /// GPU time of the very first dispatch of each trace pipeline (drivers may compile lazily;
    /// each traversal's pipeline has its own), summed, excluded from `trace_gpu_ms`.
    pub first_dispatch_ms: Option<f64>,
    /// Rays traced by those first dispatches.
    pub first_dispatch_rays: u64,
    /// GPU time of every later dispatch of the trace pass, summed.
    pub trace_gpu_ms: f64,
    /// Rays (camera + shadow) traced by those dispatches.
    pub rays_traced: u64,
    /// Number of dispatches counted in `trace_gpu_ms`.
    pub dispatches: u64,
    /// The longest of those dispatches.
    pub longest_dispatch_ms: f64,
    /// G-buffer passes drawn, and their GPU time (draw only, no readback), summed.
    pub gbuffer_passes: u64,
    pub gbuffer_gpu_ms: f64,
    /// Bytes of the loaded scene's BLASes before and after compaction.
    pub blas_bytes: u64,
    pub blas_compacted_bytes: u64,
    /// Device bytes of the ray-query structures of the loaded scene (compacted BLASes, TLAS,
    /// instances); 0 without ray queries.
    pub accel_bytes: u64,
    /// Device bytes of the software traversal's BVH (nodes and leaf-ordered triangles); 0 when
    /// the device was opened without the software traversal.
    pub bvh_bytes: u64,
    /// Host time of the BVH build and flattening (upload excluded).
    pub bvh_build_ms: f64,
}

impl Timings {
    /// Rays per second of the trace pass, first dispatch excluded.
    pub fn rays_per_second(&self) -> Option<f64> {
        (self.trace_gpu_ms > 0.0).then(|| self.rays_traced as f64 / (self.trace_gpu_ms * 1e-3))
    }

    /// Device bytes of `traversal`'s structures for the loaded scene (the scene arrays, shared
    /// by both, not counted).
    pub fn traversal_bytes(&self, traversal: Traversal) -> u64 {
        match traversal {
            Traversal::RayQuery => self.accel_bytes,
            Traversal::Software => self.bvh_bytes,
        }
    }
}

/// How one render is split: `samples_per` samples of `rows_per` rows per dispatch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Split {
    pub samples_per: u32,
    pub rows_per: u32,
}

impl Split {
    pub fn new(width: u32, height: u32, spp: u32, budget: u64) -> Self {
        let pixels = u64::from(width) * u64::from(height);
        let samples_per = (budget / pixels.max(1)).clamp(1, u64::from(spp.max(1))) as u32;
        let rows_per = if u64::from(samples_per) * pixels <= budget {
            height
        } else {
            (budget / u64::from(width).max(1)).clamp(1, u64::from(height)) as u32
        };
        Self {
            samples_per,
            rows_per,
        }
    }
}

/// The pipeline of one traversal.
struct TracePipeline {
    traversal: Traversal,
    pipeline: Pipeline,
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
    /// The hybrid path's plan (one vec4 per pixel, see TRACE_BINDING_PLAN); a placeholder of
    /// one entry while none is set (the binding must be valid in every mode).
    plan: Buffer,
    /// Per pixel of the plan: the camera-space depth of the surface the G-buffer sees (0:
    /// none), from the device plan (TRACE_BINDING_SURFACE_DEPTH).
    surface_depth: Buffer,
    /// Pixels of the plan set by `set_plan`; `None`: every sample of every pixel is traced.
    plan_pixels: Option<u64>,
    /// The hybrid's lit pre-pass counted rays into the counter's word 2, not yet reported.
    prepass_rays_pending: bool,
    /// Placeholder of the raster path's visibility binding until `bind_visibility`.
    _visibility_placeholder: Buffer,
    /// Placeholder of the accumulation binding until a render or the preview binds one.
    _accum_placeholder: Buffer,
    timestamps: QueryPool,
    /// The band of sums the shader adds to, for the current image size.
    accum: Option<BandSums>,
    /// The accumulations' sums on the device.
    pub films: DeviceFilms,
    /// The aperture image's tables (TRACE_BINDING_APERTURE).
    aperture: ApertureTable,
    /// The real lens (TRACE_BINDING_LENS).
    lens: LensBuffer,
    /// Upper bound of pixel-samples per dispatch (tests lower it to force many submissions).
    pub samples_per_dispatch: u64,
    /// Current size of a dispatch, adapted to the measured speed.
    adaptive_samples: u64,
    pub max_band_pixels: u64,
}

impl TracePass {
    /// Creates a pipeline for each traversal of `ctx.traversals`; the first is in use.
    pub fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let pipelines = ctx
            .traversals
            .iter()
            .map(|&t| {
                Ok(TracePipeline {
                    traversal: t,
                    pipeline: Self::pipeline(ctx, t)?,
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
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        for p in &pipelines {
            let pipeline = &p.pipeline;
            pipeline.bind_buffer(
                TRACE_BINDING_PARAMS,
                vk::DescriptorType::UNIFORM_BUFFER,
                &params,
            );
            pipeline.bind_buffer(TRACE_BINDING_COUNTERS, storage, &counters);
            pipeline.bind_buffer(TRACE_BINDING_ACCUM, storage, &accum_placeholder);
            pipeline.bind_buffer(TRACE_BINDING_PLAN, storage, &plan);
            pipeline.bind_buffer(TRACE_BINDING_SURFACE_DEPTH, storage, &surface_depth);
            pipeline.bind_buffer(TRACE_BINDING_VISIBILITY, storage, &visibility);
            pipeline.bind_buffer(TRACE_BINDING_APERTURE, storage, &aperture.buffer);
            pipeline.bind_buffer(TRACE_BINDING_LENS, storage, &lens.buffer);
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
        // Written by the host (`set_plan`) or the device plan pass, read (and, lit, completed by
        // the shortcut pre-pass) by the shader; host-visible so that the device plan reads back.
        Buffer::new(
            ctx,
            "hybrid plan",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )
    }

    /// Sets the hybrid path's plan for later `accumulate` calls (one entry per pixel of the
    /// image, row-major: see TRACE_BINDING_PLAN), or `None` to trace every sample again.
    pub fn set_plan(&mut self, plan: Option<&[[f32; 4]]>) -> Result<(), GpuError> {
        let Some(plan) = plan else {
            self.plan_pixels = None;
            return Ok(());
        };
        self.ensure_plan_capacity(plan.len() as u64)?;
        self.plan.write(bytemuck::cast_slice(plan))?;
        self.plan_pixels = Some(plan.len() as u64);
        Ok(())
    }

    /// Makes the plan buffer hold at least `pixels` entries, and the surface depths as many (new
    /// buffers, bound to every pipeline, when they are smaller). No submission using them may
    /// be pending.
    pub fn ensure_plan_capacity(&mut self, pixels: u64) -> Result<(), GpuError> {
        let bytes = (pixels * 16).max(16);
        if self.plan.size < bytes {
            self.plan = Self::plan_buffer(&self.ctx, bytes)?;
            self.surface_depth = Self::surface_depth_buffer(&self.ctx, bytes / 4)?;
            for p in &self.pipelines {
                p.pipeline.bind_buffer(
                    TRACE_BINDING_PLAN,
                    vk::DescriptorType::STORAGE_BUFFER,
                    &self.plan,
                );
                p.pipeline.bind_buffer(
                    TRACE_BINDING_SURFACE_DEPTH,
                    vk::DescriptorType::STORAGE_BUFFER,
                    &self.surface_depth,
                );
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
    pub fn bind_visibility(&self, buffer: &Buffer) {
        for p in &self.pipelines {
            p.pipeline.bind_buffer(
                TRACE_BINDING_VISIBILITY,
                vk::DescriptorType::STORAGE_BUFFER,
                buffer,
            );
        }
    }

    /// The plan buffer (for the device plan pass to write).
    pub fn plan_buffer_ref(&self) -> &Buffer {
        &self.plan
    }

    /// The surface depths (for the device plan pass to write).
    pub fn surface_depth_ref(&self) -> &Buffer {
        &self.surface_depth
    }

    /// Later `accumulate` calls follow the plan of `pixels` entries that the device plan pass
    /// wrote into the plan buffer.
    pub fn use_device_plan(&mut self, pixels: u64) {
        self.plan_pixels = Some(pixels);
    }

    /// The plan's entries as the device left them (host-visible buffer; the caller waited for
    /// the submissions that wrote it).
    pub fn read_plan(&self, pixels: u64) -> Result<Vec<[f32; 4]>, GpuError> {
        let entries: &[[f32; 4]] = bytemuck::cast_slice(self.plan.read()?);
        entries
            .get(..pixels as usize)
            .map(<[_]>::to_vec)
            .ok_or_else(|| GpuError::Invalid(format!("the plan buffer has no {pixels} entries")))
    }

    /// The compute pipeline of `traversal`: the scene arrays, that traversal's structures, and
    /// the pass's own buffers.
    fn pipeline(ctx: &Arc<Context>, traversal: Traversal) -> Result<Pipeline, GpuError> {
        let compute = vk::ShaderStageFlags::COMPUTE;
        let mut bindings: Vec<Binding> = SceneBuffers::bindings(compute).to_vec();
        let spirv = match traversal {
            Traversal::RayQuery => {
                bindings.push((
                    TRACE_BINDING_TLAS,
                    vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
                    compute,
                ));
                shader::TRACE_RAYQUERY_COMP
            }
            Traversal::Software => {
                bindings.extend(BvhBuffers::bindings(compute));
                shader::TRACE_SOFTWARE_COMP
            }
        };
        bindings.extend([
            (
                TRACE_BINDING_ACCUM,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
            (
                TRACE_BINDING_COUNTERS,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
            (
                TRACE_BINDING_PARAMS,
                vk::DescriptorType::UNIFORM_BUFFER,
                compute,
            ),
            (
                TRACE_BINDING_PLAN,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
            (
                TRACE_BINDING_VISIBILITY,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
            (
                TRACE_BINDING_SURFACE_DEPTH,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
            (
                TRACE_BINDING_APERTURE,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
            (
                TRACE_BINDING_LENS,
                vk::DescriptorType::STORAGE_BUFFER,
                compute,
            ),
        ]);
        Pipeline::compute(
            ctx,
            spirv,
            &bindings,
            std::mem::size_of::<TracePush>() as u32,
        )
    }

    /// The traversals this pass can trace with.
    pub fn traversals(&self) -> Vec<Traversal> {
        self.pipelines.iter().map(|p| p.traversal).collect()
    }

    /// The traversal in use.
    pub fn traversal(&self) -> Traversal {
        self.pipelines[self.current].traversal
    }

    /// Uses `traversal` from now on; an error when the device was not opened for it.
    pub fn set_traversal(&mut self, traversal: Traversal) -> Result<(), GpuError> {
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

    pub fn bind_scene(&self, scene: &SceneBuffers) {
        for p in &self.pipelines {
            scene.bind(&p.pipeline);
            match p.traversal {
                Traversal::RayQuery => {
                    if let Some(accel) = &scene.accel {
                        p.pipeline.bind_accel(TRACE_BINDING_TLAS, accel.tlas.handle);
                    }
                }
                Traversal::Software => {
                    if let Some(bvh) = &scene.bvh {
                        bvh.bind(&p.pipeline);
                    }
                }
            }
        }
    }

    /// Makes the aperture tables and the real lens those of `camera` (see
    /// `ApertureTable::ensure`, `LensBuffer::ensure`), binding them anew when they change.
    /// Called before recording work with `camera`'s parameters.
    pub fn ensure_camera_tables(&mut self, camera: &Camera) -> Result<(), GpuError> {
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        if self.aperture.ensure(camera)? {
            for p in &self.pipelines {
                let buffer = &self.aperture.buffer;
                p.pipeline
                    .bind_buffer(TRACE_BINDING_APERTURE, storage, buffer);
            }
        }
        if self.lens.ensure(camera)? {
            for p in &self.pipelines {
                p.pipeline
                    .bind_buffer(TRACE_BINDING_LENS, storage, &self.lens.buffer);
            }
        }
        Ok(())
    }

    /// Whether `ensure_camera_tables(camera)` would upload new tables (and wait for the
    /// device).
    pub fn camera_tables_differ(&self, camera: &Camera) -> bool {
        self.aperture.differs(camera) || self.lens.differs(camera)
    }

    /// Points every pipeline's accumulation binding at `buffer`.
    fn bind_accum_buffer(&self, buffer: &Buffer) {
        for p in &self.pipelines {
            p.pipeline.bind_buffer(
                TRACE_BINDING_ACCUM,
                vk::DescriptorType::STORAGE_BUFFER,
                buffer,
            );
        }
    }

    /// Points the pass at an accumulation buffer of the caller's (the preview's, one vec4 per
    /// pixel of the whole image); a later `render` makes and binds its own again.
    pub fn bind_accumulation(&mut self, buffer: &Buffer) {
        self.accum = None;
        self.bind_accum_buffer(buffer);
    }

    /// Records an update of the uniform parameters, ordered before later dispatches and after
    /// earlier ones (frames in flight share the buffer; the queue orders the updates).
    pub fn record_params(&self, cmd: vk::CommandBuffer, params: &TraceParams) {
        let ctx = &self.ctx;
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::UNIFORM_READ,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        // SAFETY: recording state; the buffer has TRANSFER_DST usage and the data is a
        // multiple of 4 bytes under 64 KiB.
        unsafe {
            ctx.device
                .cmd_update_buffer(cmd, self.params.buffer, 0, bytemuck::bytes_of(params))
        };
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::UNIFORM_READ,
        );
    }

    /// Records the hybrid's lit pre-pass over a `width` x `height` image (TRACE_MODE_SHORTCUT:
    /// each pixel's shortcut value and shadow state into the plan buffer, which must hold the
    /// image), after the parameters of the camera and settings; the plan's steps follow it.
    /// Ordered after earlier transfers and dispatches (parameter updates, clears).
    pub fn record_lit_prepass(&self, cmd: vk::CommandBuffer, width: u32, height: u32) {
        barrier(
            &self.ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        let push = TracePush {
            band_origin: 0,
            band_height: height,
            block_first: 0,
            block_stride: 1,
            block_count: height.div_ceil(GROUP),
            sample_begin: 0,
            sample_end: 0,
            mode: TRACE_MODE_SHORTCUT,
        };
        self.record_dispatch(cmd, push, width);
    }

    /// Records a clear of the ray counter (words 0 and 1: all rays, the first dispatch's);
    /// word 2 keeps the hybrid's lit pre-pass until the next render reads it.
    pub fn record_clear_ray_counter(&self, cmd: vk::CommandBuffer) {
        // SAFETY: recording state; the counters buffer has TRANSFER_DST usage.
        unsafe {
            self.ctx
                .device
                .cmd_fill_buffer(cmd, self.counters.buffer, 0, 8, 0)
        };
    }

    /// Records a copy of the rays counted so far (the hybrid's lit pre-pass) into word 2, which
    /// the next `accumulate` adds to its report: the plan is not waited for.
    pub fn record_keep_prepass_rays(&mut self, cmd: vk::CommandBuffer) {
        self.record_copy_counter(cmd, 8);
        self.prepass_rays_pending = true;
    }

    /// Records one dispatch of the blocks and samples `push` names, over an image `width`
    /// pixels wide (parameters and accumulation bound and ordered by the caller).
    pub fn record_dispatch(&self, cmd: vk::CommandBuffer, push: TracePush, width: u32) {
        self.pipeline_in_use().bind(cmd, bytemuck::bytes_of(&push));
        // SAFETY: compute pipeline and its complete descriptor set are bound.
        unsafe {
            self.ctx
                .device
                .cmd_dispatch(cmd, width.div_ceil(GROUP), push.block_count, 1)
        };
    }

    /// Adds samples `samples` of every pixel to `accumulation` (of the camera's size), with the
    /// scene last bound by `bind_scene`. The sums stay on the device (`films`); the shader adds
    /// sample after sample to them, so any split of a range gives the same sums.
    pub fn accumulate(
        &mut self,
        (camera, settings): (&Camera, &RenderSettings),
        samples: Range<u32>,
        accumulation: &mut Accumulation,
        timings: &mut Timings,
        raster: Option<&RecordSample<'_>>,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(), GpuError> {
        let (width, height) = (camera.width, camera.height);
        let pixels = u64::from(width) * u64::from(height);
        if (accumulation.width, accumulation.height) != (width, height) {
            return Err(GpuError::Invalid(format!(
                "accumulation {}x{} does not match the {width}x{height} image",
                accumulation.width, accumulation.height
            )));
        }
        if samples.is_empty() {
            return Ok(());
        }
        let mode = match self.plan_pixels {
            None if raster.is_some() => TRACE_MODE_RASTER,
            None => TRACE_MODE_ALL,
            Some(_) if raster.is_some() => {
                return Err(GpuError::Invalid(
                    "the raster path does not follow a hybrid plan".into(),
                ))
            }
            Some(n) if n == pixels => TRACE_MODE_HYBRID,
            Some(n) => {
                return Err(GpuError::Invalid(format!(
                    "the hybrid plan has {n} pixels, the image {pixels}"
                )))
            }
        };
        let band_rows = self.ensure_accumulation(width, height)?;
        self.ensure_camera_tables(camera)?;
        let (film, start) = self.films.take(accumulation)?;
        self.films.prepare_finish(film)?;
        // The parameters go up in the first submission (a pending one may still read them).
        let params = crate::upload::trace_params(camera, settings);

        let steps = self.plan_steps(width, height, band_rows, &samples, mode, raster.is_some());
        let total: u64 = steps.iter().map(|s| s.work).sum();
        progress(0, total);
        self.ensure_timestamps(2 * steps.len() as u32)?;

        // Every step is recorded and submitted before any wait: batches of steps per command
        // buffer, each signalling the device's timeline, which the progress reads.
        let first_dispatch = !self.pipelines[self.current].first_dispatch_done;
        let mut batches = Vec::new();
        for (batch, chunk) in steps.chunks(STEPS_PER_SUBMIT).enumerate() {
            let first = batch * STEPS_PER_SUBMIT;
            let value = self.ctx.submit(|cmd| {
                if first == 0 {
                    self.timestamps.reset(cmd);
                    self.record_params(cmd, &params);
                    self.record_clear_ray_counter(cmd);
                    self.films.record_start(cmd, film, start);
                }
                for (i, step) in chunk.iter().enumerate() {
                    let index = (first + i) as u32;
                    let record = raster
                        .zip(step.raster_sample)
                        .map(|(record, sample)| move |cmd| record(cmd, sample));
                    let before = record.as_ref().map(|r| r as _);
                    self.record_step(cmd, step, (film, width), index, before);
                    if index == 0 && first_dispatch {
                        // The pipeline's first dispatch is reported apart: its rays too.
                        self.record_copy_first_rays(cmd);
                    }
                }
                if first + chunk.len() == steps.len() {
                    self.films.record_finish(cmd, film);
                    barrier_to_host(
                        &self.ctx,
                        cmd,
                        vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
                        vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE,
                    );
                }
                Ok(())
            })?;
            let work: u64 = chunk.iter().map(|s| s.work).sum();
            batches.push((value, work));
        }
        let last = batches.last().map_or(0, |b| b.0);
        let mut reported = 0;
        loop {
            let completed = self.ctx.completed()?;
            let done: u64 = batches
                .iter()
                .filter(|(value, _)| *value <= completed)
                .map(|(_, work)| work)
                .sum();
            if done > reported {
                reported = done;
                progress(done, total);
            }
            // One batch has no progress to show before its end.
            if completed >= last || batches.len() <= 1 {
                break;
            }
            std::thread::sleep(PROGRESS_POLL);
        }
        self.ctx.wait_until(last)?;
        if reported < total {
            progress(total, total);
        }
        self.films.finished(film);
        self.record_timings(&steps, first_dispatch, timings)
    }

    /// The band buffer for a `width` x `height` image (made anew, and bound, when the size
    /// changes), and the rows of a band. The shader adds to a storage buffer covering a band of
    /// rows, bounded by the device's storage-buffer range (128 MiB on lavapipe); each band is
    /// copied in from the film and back.
    pub fn ensure_accumulation(&mut self, width: u32, height: u32) -> Result<u32, GpuError> {
        let max_band_pixels = (u64::from(self.ctx.report.max_storage_buffer_range) / 16)
            .min(self.max_band_pixels)
            .max(u64::from(width));
        let band_rows = (max_band_pixels / u64::from(width)).clamp(1, u64::from(height)) as u32;
        let bytes = u64::from(band_rows) * u64::from(width) * 16;
        if self.accum.as_ref().is_none_or(|a| a.bytes != bytes) {
            // A pending submission (the hybrid's plan) binds the old buffer: it finishes first.
            self.ctx.wait_all()?;
            self.accum = None;
            let buffer = Buffer::new(
                &self.ctx,
                "trace band sums",
                bytes,
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )?;
            self.bind_accum_buffer(&buffer);
            self.accum = Some(BandSums { buffer, bytes });
        }
        Ok(band_rows)
    }

    /// The dispatches of one `accumulate` call, in order: band after band; in a band, the
    /// raster path's samples one by one, else ranges of samples of groups of row blocks sized
    /// by `adaptive_samples` (any split adds each pixel's samples in the same order, so the
    /// sums do not depend on it).
    fn plan_steps(
        &self,
        width: u32,
        height: u32,
        band_rows: u32,
        samples: &Range<u32>,
        mode: u32,
        raster: bool,
    ) -> Vec<Step> {
        let (first_sample, spp) = (samples.start, samples.end);
        let mut steps = Vec::new();
        let mut band_origin = 0;
        while band_origin < height {
            let band_height = band_rows.min(height - band_origin);
            let band_bytes = u64::from(band_height) * u64::from(width) * 16;
            let band_start = steps.len();
            if raster {
                for sample in first_sample..spp {
                    steps.push(Step {
                        push: TracePush {
                            band_origin,
                            band_height,
                            block_first: 0,
                            block_stride: 1,
                            block_count: band_height.div_ceil(GROUP),
                            sample_begin: sample,
                            sample_end: sample + 1,
                            mode,
                        },
                        load: false,
                        copy_out: None,
                        raster_sample: Some(sample),
                        work: u64::from(band_height) * u64::from(width),
                    });
                }
            } else {
                let mut sample_begin = first_sample;
                while sample_begin < spp {
                    let budget = self.adaptive_samples.min(self.samples_per_dispatch);
                    let split = Split::new(width, band_height, spp - sample_begin, budget);
                    let sample_end = (sample_begin + split.samples_per).min(spp);
                    // The band's blocks of GROUP rows are dealt out to `groups` dispatches with
                    // a stride, so each dispatch covers the whole band evenly (similar cost per
                    // dispatch, sky and geometry mixed alike) while each workgroup still traces
                    // a coherent 8x8 tile.
                    let blocks = band_height.div_ceil(GROUP);
                    let blocks_per = (split.rows_per / GROUP).max(1);
                    let groups = blocks.div_ceil(blocks_per);
                    for group in 0..groups {
                        let block_count = (blocks - group).div_ceil(groups);
                        let rows: u32 = (0..block_count)
                            .map(|b| GROUP.min(band_height - (group + b * groups) * GROUP))
                            .sum();
                        steps.push(Step {
                            push: TracePush {
                                band_origin,
                                band_height,
                                block_first: group,
                                block_stride: groups,
                                block_count,
                                sample_begin,
                                sample_end,
                                mode,
                            },
                            load: false,
                            copy_out: None,
                            raster_sample: None,
                            work: u64::from(rows)
                                * u64::from(width)
                                * u64::from(sample_end - sample_begin),
                        });
                    }
                    sample_begin = sample_end;
                }
            }
            steps[band_start].load = true;
            steps.last_mut().expect("a band has a step").copy_out = Some(band_bytes);
            band_origin += band_height;
        }
        steps
    }

    /// A timestamp pool with at least `queries` queries (made anew when it is smaller; no
    /// submission uses the old one: every `accumulate` waits for its own).
    fn ensure_timestamps(&mut self, queries: u32) -> Result<(), GpuError> {
        if self.timestamps.count() < queries {
            self.timestamps = QueryPool::new(&self.ctx, vk::QueryType::TIMESTAMP, queries)?;
        }
        Ok(())
    }

    /// Keeps the rays counted so far (the pipeline's first dispatch) in the counter's second
    /// word.
    fn record_copy_first_rays(&self, cmd: vk::CommandBuffer) {
        self.record_copy_counter(cmd, 4);
    }

    /// Copies the counter's word 0 (rays so far) to the byte offset `to`.
    fn record_copy_counter(&self, cmd: vk::CommandBuffer, to: u64) {
        let ctx = &self.ctx;
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_READ,
        );
        let copy = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(to)
            .size(4);
        // SAFETY: recording state; the counters buffer (16 bytes, TRANSFER usages) holds both
        // words (`to` is 4 or 8), which do not overlap.
        unsafe {
            ctx.device
                .cmd_copy_buffer(cmd, self.counters.buffer, self.counters.buffer, &[copy])
        };
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
    }

    /// After a call's wait: each step's GPU time (the pipeline's first dispatch apart), the
    /// rays counted, and the size of the next calls' dispatches from the measured speed.
    fn record_timings(
        &mut self,
        steps: &[Step],
        first_dispatch: bool,
        timings: &mut Timings,
    ) -> Result<(), GpuError> {
        let ticks = self.timestamps.results_of(2 * steps.len() as u32)?;
        let words = bytemuck::cast_slice::<u8, u32>(self.counters.read()?);
        let (all_rays, first_rays) = (u64::from(words[0]), u64::from(words[1]));
        if std::mem::take(&mut self.prepass_rays_pending) {
            timings.rays_traced += u64::from(words[2]);
        }
        let (mut work, mut ms) = (0u64, 0.0f64);
        for (i, step) in steps.iter().enumerate() {
            let gpu_ms = self.ctx.elapsed_ns(ticks[2 * i], ticks[2 * i + 1]) * 1e-6;
            if i == 0 && first_dispatch {
                timings.first_dispatch_ms = Some(timings.first_dispatch_ms.unwrap_or(0.0) + gpu_ms);
                continue;
            }
            timings.trace_gpu_ms += gpu_ms;
            timings.longest_dispatch_ms = timings.longest_dispatch_ms.max(gpu_ms);
            timings.dispatches += 1;
            if step.raster_sample.is_none() {
                work += step.work;
                ms += gpu_ms;
            }
        }
        if first_dispatch {
            // Summed over the pipelines (one per traversal), so that reports can subtract.
            timings.first_dispatch_rays += first_rays;
            timings.rays_traced += all_rays - first_rays;
            self.pipelines[self.current].first_dispatch_done = true;
        } else {
            timings.rays_traced += all_rays;
        }
        if work > 0 && ms > 0.0 {
            // Grows at most 4x per call; shrinks at once.
            let rate = work as f64 / ms;
            self.adaptive_samples = ((rate * TARGET_DISPATCH_MS) as u64)
                .min(4 * self.adaptive_samples)
                .clamp(1024, MAX_SAMPLES_PER_DISPATCH);
        }
        Ok(())
    }

    /// Records one step: the band's sums in from film `film` first (`load`), then one
    /// dispatch between timestamps `2 index` and `2 index + 1` (after what `before` records:
    /// the raster path's pass), then the band's sums back to the film (`copy_out`).
    /// The dispatch covers the blocks of GROUP rows `block_first + i * block_stride`,
    /// i < block_count, of the band.
    fn record_step(
        &self,
        cmd: vk::CommandBuffer,
        step: &Step,
        (film, width): (usize, u32),
        index: u32,
        before: Option<&dyn Fn(vk::CommandBuffer)>,
    ) {
        let ctx = &self.ctx;
        let band_sums = &self.accum.as_ref().expect("band buffer").buffer;
        let film = self.films.sums(film);
        let push = step.push;
        // Earlier steps and submissions (the previous dispatch, copies, clears) first.
        barrier(
            ctx,
            cmd,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_WRITE,
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        let band = vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(u64::from(push.band_origin) * u64::from(width) * 16)
            .size(u64::from(push.band_height) * u64::from(width) * 16);
        if step.load {
            let up = vk::BufferCopy::default()
                .src_offset(band.dst_offset)
                .dst_offset(0)
                .size(band.size);
            // SAFETY: recording state; the buffers have the TRANSFER usages used and the
            // band's sums fit both (sizes computed in `accumulate`).
            unsafe {
                ctx.device
                    .cmd_copy_buffer(cmd, film.buffer, band_sums.buffer, &[up])
            };
            barrier(
                ctx,
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
            );
        }
        self.timestamps
            .write(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, 2 * index);
        if let Some(record) = before {
            record(cmd);
        }
        self.record_dispatch(cmd, push, width);
        self.timestamps
            .write(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, 2 * index + 1);
        if let Some(bytes) = step.copy_out {
            barrier(
                ctx,
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_WRITE,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_READ,
            );
            // SAFETY: the band's sums fit both buffers (sizes computed in `accumulate`).
            unsafe {
                ctx.device
                    .cmd_copy_buffer(cmd, band_sums.buffer, film.buffer, &[band.size(bytes)])
            };
        }
    }
}

/// One dispatch of an `accumulate` call and what comes with it.
struct Step {
    push: TracePush,
    /// The first step of a band: the band's sums come in from the film first.
    load: bool,
    /// The last step of a band: its sums (bytes) go back to the film after.
    copy_out: Option<u64>,
    /// The raster path's sample, whose raster pass is recorded before the dispatch.
    raster_sample: Option<u32>,
    /// Pixel-samples (progress, speed).
    work: u64,
}

/// Records the raster pass of one sample (the raster path), before that sample's shading.
pub(crate) type RecordSample<'a> = dyn Fn(vk::CommandBuffer, u32) + 'a;

/// The sums of one band of rows.
struct BandSums {
    buffer: Buffer,
    bytes: u64,
}

#[cfg(test)]
mod tests {
    use super::Split;

    #[test]
    fn split_stays_within_budget() {
        for &(w, h, spp, budget) in &[
            (640u32, 480u32, 16u32, 1u64 << 18),
            (64, 48, 4, 1 << 18),
            (4000, 3000, 1, 1 << 18),
            (1, 1, 1000, 1 << 18),
            (100_000, 2, 3, 1000),
        ] {
            let s = Split::new(w, h, spp, budget);
            assert!(s.samples_per >= 1 && s.samples_per <= spp);
            assert!(s.rows_per >= 1 && s.rows_per <= h);
            let per = u64::from(s.samples_per) * u64::from(s.rows_per) * u64::from(w);
            assert!(per <= budget.max(u64::from(w)), "{w}x{h} spp {spp}: {s:?}");
        }
    }
}
