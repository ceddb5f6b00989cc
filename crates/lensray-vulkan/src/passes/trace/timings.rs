//! What a trace call measured: GPU times from its timestamps, rays from the ray counter, and
//! the size of later dispatches from the measured speed.

use ash::vk;

use super::accumulate::{Submitted, FIRST_STEP_QUERY};
use super::TracePass;
use crate::core::error::GpuError;
use crate::core::query::QueryPool;
use crate::traversal::Traversal;
use lensray_core::interface::TRACE_MODE_RASTER;

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
    /// GPU time of each trace pipeline's empty dispatch before its first (`record_compile`):
    /// the driver's lazy compilation of the shaders, where it compiles lazily.
    pub compile_ms: f64,
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
            Traversal::RayQuery | Traversal::RtPipeline => self.accel_bytes,
            Traversal::Software => self.bvh_bytes,
        }
    }
}

impl TracePass {
    /// A timestamp pool with at least `queries` queries (made anew when it is smaller; no
    /// submission uses the old one: every `accumulate` waits for its own).
    pub(super) fn ensure_timestamps(&mut self, queries: u32) -> Result<(), GpuError> {
        if self.timestamps.count() < queries {
            self.timestamps = QueryPool::new(&self.ctx, vk::QueryType::TIMESTAMP, queries)?;
        }
        Ok(())
    }

    /// Takes the timestamps of the batches of `submitted` that signal `completed` or less (they
    /// finished): each step's GPU time (the pipeline's first dispatch apart), and the size of
    /// the dispatches still to plan from the measured speed.
    pub(super) fn take_timings(
        &mut self,
        submitted: &mut Submitted,
        completed: u64,
        timings: &mut Timings,
    ) -> Result<(), GpuError> {
        let finished = submitted.batches[submitted.finished..]
            .iter()
            .take_while(|b| b.value <= completed)
            .count();
        if finished == 0 {
            return Ok(());
        }
        let batches = &submitted.batches[submitted.finished..submitted.finished + finished];
        let steps = batches[0].steps.start..batches[finished - 1].steps.end;
        submitted.finished += finished;
        let first = FIRST_STEP_QUERY + 2 * steps.start as u32;
        let ticks = self.timestamps.results_in(first, 2 * steps.len() as u32)?;
        let (mut work, mut ms) = (0u64, 0.0f64);
        for (k, step) in submitted.steps[steps.clone()].iter().enumerate() {
            submitted.done += step.work;
            let gpu_ms = self.ctx.elapsed_ns(ticks[2 * k], ticks[2 * k + 1]) * 1e-6;
            if steps.start + k == 0 && submitted.first_dispatch {
                timings.first_dispatch_ms = Some(timings.first_dispatch_ms.unwrap_or(0.0) + gpu_ms);
                continue;
            }
            timings.trace_gpu_ms += gpu_ms;
            timings.longest_dispatch_ms = timings.longest_dispatch_ms.max(gpu_ms);
            timings.dispatches += 1;
            // The raster path's steps include its raster passes: they do not size dispatches.
            if step.push.mode != TRACE_MODE_RASTER {
                work += step.work;
                ms += gpu_ms;
            }
        }
        self.sizing.measured(work, ms);
        Ok(())
    }

    /// After a call's last wait: the rays counted, and the pipeline's compilation when the
    /// call made its first dispatch.
    pub(super) fn finish_timings(
        &mut self,
        first_dispatch: bool,
        timings: &mut Timings,
    ) -> Result<(), GpuError> {
        if first_dispatch {
            let ticks = self.timestamps.results_in(0, 2)?;
            timings.compile_ms += self.ctx.elapsed_ns(ticks[0], ticks[1]) * 1e-6;
        }
        let rays = self.rays.read()?;
        timings.rays_traced += rays.prepass;
        if first_dispatch {
            // Summed over the pipelines (one per traversal), so that reports can subtract.
            timings.first_dispatch_rays += rays.first;
            timings.rays_traced += rays.all - rays.first;
            self.pipelines.first_dispatch_timed();
        } else {
            timings.rays_traced += rays.all;
        }
        Ok(())
    }
}
