//! Adaptive sampling on the device (`--noise-threshold`, docs/adaptive.md): lensray-core's
//! `film::adaptive::render_adaptive` decides every round on the host, as for the CPU reference;
//! each round here is one trace pass call in `TRACE_MODE_ADAPTIVE`. The pixels' counts (or
//! `ADAPTIVE_IDLE` for those that rest) and class A sums go up in the hybrid's plan buffer,
//! which the traced path leaves unused; the shader adds an active pixel's samples from its
//! count to the round's end, its class A samples to the entry's sum too. The sums and the
//! entries come back after each round: the host's rule needs them all. The preview's rounds
//! (`present::viewer::rounds`) use the same entries through the helpers at the end.

use glam::Vec3;

use super::batch::SampleBatch;
use super::{check_samples, GpuRenderer};
use crate::core::error::GpuError;
use crate::core::recorder::Recorder;
use crate::Estimator;
use lensray_core::film::adaptive::{self, AdaptiveReport};
use lensray_core::film::{Accumulation, Progress, Sums};
use lensray_core::interface::ADAPTIVE_IDLE;
use lensray_core::settings::Shot;

/// The plan entries of a round: each pixel's count where `active` (else `ADAPTIVE_IDLE`) and
/// its class A sum.
pub(crate) fn round_entries(sums: &Sums, class_a: &[Vec3], active: &[bool]) -> Vec<[f32; 4]> {
    sums.pixels
        .iter()
        .zip(class_a)
        .zip(active)
        .map(|((sum, a), &on)| [a.x, a.y, a.z, if on { sum[3] } else { ADAPTIVE_IDLE }])
        .collect()
}

impl GpuRenderer {
    /// Renders `shot` (`Unlit` or `Lit`, with a noise threshold) adaptively into
    /// `accumulation`, new and of the camera's size, with the traced estimator: the rounds of
    /// `film::adaptive`, which the CPU reference follows too, so that both take the same samples
    /// wherever their sums agree on which pixels go on. The sums stay on the device as after
    /// `add_samples`, their host copy current. `progress` follows the rounds.
    pub fn add_adaptive(
        &mut self,
        shot: &Shot,
        accumulation: &mut Accumulation,
        progress: &mut Progress,
    ) -> Result<AdaptiveReport, GpuError> {
        check_samples(shot)?;
        let threshold = shot.render.noise_threshold.ok_or_else(|| {
            GpuError::Invalid("an adaptive render needs a noise threshold".into())
        })?;
        if self.scene.is_none() {
            return Err(GpuError::NoScene);
        }
        let (width, height) = (shot.camera.width, shot.camera.height);
        if !accumulation.is_empty() || (accumulation.width, accumulation.height) != (width, height)
        {
            return Err(GpuError::Invalid(format!(
                "an adaptive render starts from a new {width}x{height} accumulation"
            )));
        }
        // The plan buffer is replaced when it grows: nothing pending may use it.
        self.ctx.wait_all()?;
        self.trace
            .ensure_plan_capacity(u64::from(width) * u64::from(height))?;
        let mut sums = Sums::new(width, height);
        let rendered = adaptive::render_adaptive(
            threshold,
            shot.render.spp,
            &mut sums,
            progress,
            |end, active, sums, class_a| {
                self.adaptive_round(shot, end, active, accumulation, sums, class_a)
            },
        );
        self.trace.plan.clear();
        rendered
    }

    /// One round: every pixel marked in `active` from its count in `sums` to `end`, its class A
    /// samples added to `class_a`; `sums` and `class_a` are the device's afterwards.
    fn adaptive_round(
        &mut self,
        shot: &Shot,
        end: u32,
        active: &[bool],
        accumulation: &mut Accumulation,
        sums: &mut Sums,
        class_a: &mut [Vec3],
    ) -> Result<(), GpuError> {
        let entries = round_entries(sums, class_a, active);
        // The call covers the samples of the pixel furthest behind; each pixel starts at its own.
        let begin = sums
            .pixels
            .iter()
            .zip(active)
            .filter(|(_, &on)| on)
            .map(|(sum, _)| adaptive::pixel_range(sum[3], end).start)
            .min();
        let Some(begin) = begin else {
            return Ok(());
        };
        self.trace.plan.upload(&entries)?;
        let scene = self.scene.as_ref().ok_or(GpuError::NoScene)?;
        let batch = SampleBatch::new(Estimator::Traced, shot, None, scene)?.adaptive()?;
        self.trace.accumulate(
            batch.shot(),
            begin..end,
            accumulation,
            &mut self.timings,
            &batch,
            &mut |_, _| {},
        )?;
        self.trace.films.read(accumulation)?;
        sums.pixels.copy_from_slice(&accumulation.host()?.pixels);
        let entries = self.trace.plan.read(entries.len() as u64)?;
        for (a, entry) in class_a.iter_mut().zip(entries) {
            *a = Vec3::new(entry[0], entry[1], entry[2]);
        }
        Ok(())
    }
}

/// The preview's side: its frames record the rounds' samples into their own command buffers
/// (`SampleBatch::adaptive`), the viewer decides between rounds with every frame finished.
impl GpuRenderer {
    /// Whether the plan buffer holds the entries of `pixels` pixels (else
    /// `ensure_adaptive_entries` replaces it, with no frame in flight).
    pub(crate) fn adaptive_entries_fit(&self, pixels: u64) -> bool {
        self.trace.plan.plan().size >= pixels * 16
    }

    /// Makes the plan buffer hold the entries of `pixels` pixels. No submission using it may
    /// be pending.
    pub(crate) fn ensure_adaptive_entries(&mut self, pixels: u64) -> Result<(), GpuError> {
        self.trace.ensure_plan_capacity(pixels)
    }

    /// Records the first round's entries: every pixel active from 0, its class A sum 0 (the
    /// accumulation is cleared in the same frame).
    pub(crate) fn record_adaptive_start(&self, rec: &mut Recorder<'_>) {
        rec.fill_buffer(self.trace.plan.plan(), 0, ash::vk::WHOLE_SIZE, 0);
    }

    /// The first `pixels` entries as the device left them (waited for).
    pub(crate) fn read_adaptive_entries(&self, pixels: u64) -> Result<Vec<[f32; 4]>, GpuError> {
        self.trace.plan.read(pixels)
    }

    /// Writes the next round's entries (waited for).
    pub(crate) fn upload_adaptive_entries(&mut self, entries: &[[f32; 4]]) -> Result<(), GpuError> {
        self.trace.plan.upload(entries)
    }
}
