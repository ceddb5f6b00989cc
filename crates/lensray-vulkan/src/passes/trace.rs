//! The thin-lens compute pass (shaders/passes/trace.comp): camera samples traced with one
//! pipeline per traversal the device was opened for (ray queries, or the software BVH
//! traversal; the one in use is `pipelines.traversal()`), split into dispatches of bounded size
//! (bands of rows x ranges of samples) sized as the call goes by the speed measured so far,
//! several per submission, a few submissions in flight, none waited for until the last.
//! The shader adds to a band's sums in a float buffer, copied in and out of the accumulation's
//! film (`films`), which stays on the device: the host reads it only when asked.
//!
//! [`TracePass`] composes the owners of its parts: `pipelines` (the dispatch of an estimator:
//! the pipeline in use, what the sets hold, the recording of dispatches), `steps` (the dispatch
//! sizing: how one call is split), `films` (the accumulations' sums and bands), `camera_tables`
//! (aperture and lens), `plan` (the hybrid's plan buffers) and `rays` (the ray counter).
//! `accumulate` holds the renderer's entry that plans, records and submits the steps and waits;
//! `timings` what the timestamps and ray counter say.

mod accumulate;
mod camera_tables;
mod pipelines;
mod plan;
mod rays;
mod steps;
#[cfg(test)]
mod tests;
mod timings;

pub(crate) use accumulate::RecordSamples;
pub(crate) use pipelines::TracePipelines;

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::query::QueryPool;
use crate::core::recorder::Recorder;
use crate::passes::films::DeviceFilms;
use lensray_core::camera::Camera;
use lensray_core::interface::{TraceParams, ENVIRONMENT_MAP_NONE};

use camera_tables::CameraTables;
use plan::PlanBuffers;
use rays::RayCounter;
use steps::DispatchSizing;
pub use timings::Timings;

pub(crate) struct TracePass {
    ctx: Arc<Context>,
    /// The dispatch of an estimator: the pipelines, the one in use, what their sets hold.
    pub(crate) pipelines: TracePipelines,
    /// How calls are split into dispatches.
    pub(crate) sizing: DispatchSizing,
    /// The uniform parameters (`TraceGroup`).
    params: Buffer,
    pub(crate) rays: RayCounter,
    timestamps: QueryPool,
    /// The hybrid's plan buffers.
    pub(crate) plan: PlanBuffers,
    /// The accumulations' sums on the device, and the band the shader adds to.
    pub(crate) films: DeviceFilms,
    /// The aperture and lens tables of the camera last traced.
    pub(crate) tables: CameraTables,
}

impl TracePass {
    /// The pipelines of the device's traversals (the first in use) and the buffers they bind.
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        let mut pipelines = TracePipelines::new(ctx)?;
        let params = Buffer::new(
            ctx,
            "trace params",
            std::mem::size_of::<TraceParams>() as u64,
            // TRANSFER_DST: the preview updates it inside its frames' command buffers.
            vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::CpuToGpu,
        )?;
        let rays = RayCounter::new(ctx)?;
        pipelines.bind_parameters(&params, rays.buffer());
        let plan = PlanBuffers::new(ctx)?;
        pipelines.bind_plan(plan.plan(), plan.surface_depth());
        let tables = CameraTables::new(ctx)?;
        pipelines.bind_each(|p| tables.bind(p));
        Ok(Self {
            ctx: ctx.clone(),
            pipelines,
            sizing: DispatchSizing::default(),
            params,
            rays,
            timestamps: QueryPool::new(ctx, vk::QueryType::TIMESTAMP, 2)?,
            plan,
            films: DeviceFilms::new(ctx),
            tables,
        })
    }

    /// Makes the plan buffers hold at least `pixels` entries (new buffers, bound to every
    /// pipeline, when they are smaller). No submission using them may be pending.
    pub(crate) fn ensure_plan_capacity(&mut self, pixels: u64) -> Result<(), GpuError> {
        if self.plan.ensure_capacity(pixels)? {
            let plan = &self.plan;
            self.pipelines.bind_plan(plan.plan(), plan.surface_depth());
        }
        Ok(())
    }

    /// Makes the aperture tables and the real lens those of `camera`, binding them anew when
    /// they change. Called before recording work with `camera`'s parameters.
    pub(crate) fn ensure_camera_tables(&mut self, camera: &Camera) -> Result<(), GpuError> {
        self.tables.ensure(camera, &self.pipelines)
    }

    /// The band buffer for a `width` x `height` image (made anew, and bound, when the size
    /// changes), and the rows of a band (`DeviceFilms::ensure_band`).
    pub(crate) fn ensure_accumulation(&mut self, width: u32, height: u32) -> Result<u32, GpuError> {
        let (band_rows, new) = self.films.ensure_band(width, height)?;
        if let Some(band) = new {
            self.pipelines.bind_accumulation(band);
        }
        Ok(band_rows)
    }

    /// Points the pass at an accumulation buffer of the caller's (the preview's, one vec4 per
    /// pixel of the whole image); a later `accumulate` makes and binds its band again.
    pub(crate) fn bind_accumulation(&mut self, buffer: &Buffer) {
        self.films.drop_band();
        self.pipelines.bind_accumulation(buffer);
    }

    /// Records an update of the uniform parameters (frames in flight share the buffer; the
    /// queue orders the updates), with no environment map where the bound scene has none.
    pub(crate) fn record_params(&self, rec: &mut Recorder<'_>, params: &TraceParams) {
        let mut params = *params;
        if !self.pipelines.environment_map {
            params.environment_map = ENVIRONMENT_MAP_NONE;
        }
        rec.update_buffer(&self.params, bytemuck::bytes_of(&params));
    }
}
