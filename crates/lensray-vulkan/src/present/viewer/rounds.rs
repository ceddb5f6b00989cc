//! Adaptive sampling in the preview (`--noise-threshold`, docs/adaptive.md): the rounds of a
//! render (`film::adaptive`, which decides both) with the traced estimator. A restart clears
//! the plan buffer's entries with the accumulation (every pixel active from 0); the frames add
//! the round's samples in `TRACE_MODE_ADAPTIVE` as the schedule deals them, up to the round's
//! end; once the schedule reaches it, before the next frame and with every frame finished, the
//! host reads the sums and the class A sums back, marks the pixels that go on, uploads their
//! entries and resumes the schedule from the count of the one furthest behind. A pixel's
//! samples are its indices 0..n in order, as in a render, so the converged preview is the
//! render's image. The other estimators (and the CPU's samples) ignore the threshold.

use glam::Vec3;

use super::{FrameRequest, Viewer};
use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::renderer::adaptive::round_entries;
use crate::Estimator;
use lensray_core::film::adaptive::{min_samples, pixel_range, AdaptiveState, STEP};
use lensray_core::film::Sums;

/// The rounds of the current accumulation.
pub(super) struct Rounds {
    threshold: f32,
    spp: u32,
    /// Where the current round ends.
    pub(super) end: u32,
    state: AdaptiveState,
    /// Pixels that take samples in the current round (every pixel in the first).
    pub(super) active: usize,
    /// No pixel takes more samples.
    pub(super) done: bool,
}

impl Rounds {
    fn new(threshold: f32, spp: u32, (width, height): (u32, u32)) -> Self {
        Self {
            threshold,
            spp,
            end: min_samples(threshold, spp),
            state: AdaptiveState::new(width, height),
            active: width as usize * height as usize,
            done: false,
        }
    }

    fn of(&self, threshold: f32, spp: u32, (width, height): (u32, u32)) -> bool {
        (self.threshold, self.spp) == (threshold, spp)
            && (self.state.width, self.state.height) == (width, height)
    }
}

impl Viewer {
    /// Before a frame: starts the rounds anew (making `request` restart the accumulation) when
    /// the accumulation restarts or the threshold, the cap or the size changed, or ends a round
    /// whose samples are all recorded. Nothing when the frame does not sample adaptively.
    pub(super) fn adaptive_step(&mut self, request: &mut FrameRequest<'_>) -> Result<(), GpuError> {
        let render = &request.shot.render;
        let threshold = render
            .noise_threshold
            .filter(|_| self.estimator == Estimator::Traced && request.host.is_none())
            .filter(|_| !render.shading.is_aov());
        let Some(accum) = self.accum.as_mut() else {
            return Ok(());
        };
        let Some(threshold) = threshold else {
            accum.rounds = None;
            return Ok(());
        };
        let size = (request.shot.camera.width, request.shot.camera.height);
        let pixels = u64::from(size.0) * u64::from(size.1);
        let spp = request.target_spp;
        let current = accum.rounds.as_ref().filter(|r| r.of(threshold, spp, size));
        if request.restart || current.is_none() {
            if !self.gpu.adaptive_entries_fit(pixels) {
                // The plan buffer is replaced: frames in flight bind the old one.
                self.gpu.ctx().wait_idle()?;
                self.gpu.ensure_adaptive_entries(pixels)?;
            }
            accum.rounds = Some(Rounds::new(threshold, spp, size));
            request.restart = true;
            return Ok(());
        }
        let rounds = accum.rounds.as_mut().expect("checked above");
        if rounds.done || !accum.schedule.converged() {
            return Ok(());
        }
        // The round's samples are all recorded: the host decides once they are added.
        let ctx = self.gpu.ctx().clone();
        ctx.wait_idle()?;
        let mut sums = Sums::new(size.0, size.1);
        sums.pixels = read_sums(&ctx, &accum.buffer, pixels)?;
        let entries = self.gpu.read_adaptive_entries(pixels)?;
        for (a, e) in rounds.state.class_a.iter_mut().zip(&entries) {
            *a = Vec3::new(e[0], e[1], e[2]);
        }
        rounds.active = rounds.state.mark_active(&sums, threshold, spp);
        if rounds.active == 0 || rounds.end >= spp {
            rounds.active = 0;
            rounds.done = true;
            return Ok(());
        }
        rounds.end = (rounds.end + STEP).min(spp);
        let state = &rounds.state;
        let begin = sums
            .pixels
            .iter()
            .zip(&state.active)
            .filter(|(_, &on)| on)
            .map(|(sum, _)| pixel_range(sum[3], rounds.end).start)
            .min()
            .unwrap_or(rounds.end);
        let entries = round_entries(&sums, &state.class_a, &state.active);
        self.gpu.upload_adaptive_entries(&entries)?;
        accum.schedule.resume(begin, rounds.end);
        Ok(())
    }
}

/// The first `pixels` sums of `accumulation`, copied to the host in a submission of their own,
/// waited for.
pub(super) fn read_sums(
    ctx: &std::sync::Arc<Context>,
    accumulation: &Buffer,
    pixels: u64,
) -> Result<Vec<[f32; 4]>, GpuError> {
    let readback = Buffer::new(
        ctx,
        "preview accumulation readback",
        accumulation.size,
        ash::vk::BufferUsageFlags::TRANSFER_DST,
        gpu_allocator::MemoryLocation::GpuToCpu,
    )?;
    ctx.submit_and_wait(|rec| {
        let region = ash::vk::BufferCopy::default().size(accumulation.size);
        rec.copy_buffer(accumulation, &readback, &[region]);
        rec.read_on_host(&[&readback]);
        Ok(())
    })?;
    let sums: &[[f32; 4]] = bytemuck::cast_slice(readback.read()?);
    Ok(sums[..pixels as usize].to_vec())
}
