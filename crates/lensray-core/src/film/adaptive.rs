//! Adaptive sampling (`--noise-threshold`): samples go, round after round, only to the pixels
//! whose estimated error is still above the threshold, up to `spp` each.
//!
//! - **Error estimate**: besides its sum of all samples, each pixel keeps the sum of its
//!   *class A* samples (half of every aligned block of four indices, [`is_class_a`]). The error
//!   is Cycles' (`adaptive_sampling_convergence_check`): the difference between the mean of all
//!   samples and the mean of the class A half, summed over red, green and blue, over the square
//!   root of the mean's sum (noise relative to the square root of the brightness, as the eye
//!   sees it), [`pixel_error`].
//! - **Neighbourhood**: a pixel takes more samples while its own error or that of one of its
//!   four neighbours is at or above the threshold, so that a noisy pixel whose two halves
//!   happen to agree is not left behind alone.
//! - **Rounds**: every pixel first takes [`min_samples`] samples (half Cycles' automatic
//!   minimum, 8 / T^0.3 rounded up to a whole step: 16 at T = 0.1, 32 at 0.01, 64 at 0.001;
//!   Cycles' own minimum, twice that, leaves the default scene only 1.7x faster than uniform
//!   64 spp at its error, docs/adaptive.md), then [`STEP`] more each round while it is active. A pixel's samples are always its sampler's
//!   indices 0..n: a pixel that stopped at n samples holds, float for float, what a uniform
//!   render at n spp holds there.
//! - **Deterministic**: which pixels are active after a round depends only on the sums, which
//!   depend only on each pixel's sample count; the same settings give the same image.

use std::ops::Range;

use glam::Vec3;

use super::Sums;

/// Samples a pixel takes in a round after the first: a whole packet of the CPU reference and
/// a multiple of four, so each round adds as many class A samples as others.
pub const STEP: u32 = 16;

/// Whether sample `index` is in the class A half that the error estimate compares with the
/// whole: the parity of its odd bits (Christensen et al., "Progressive Multi-Jittered Sample
/// Sequences", 10.2.1, as Cycles takes it). Two of every aligned four indices are, and each half
/// of an Owen-scrambled Sobol' sequence stays spread over the whole pixel (even against odd
/// indices would split the film's first dimension into its two halves).
pub fn is_class_a(index: u32) -> bool {
    (index & 0xaaaa_aaaa).count_ones() & 1 == 1
}

/// The samples every pixel takes before its error is first looked at: 8 / threshold^0.3,
/// rounded up to a multiple of [`STEP`] (at least one), at most `spp`.
pub fn min_samples(threshold: f32, spp: u32) -> u32 {
    let guess = (8.0 / threshold.powf(0.3)).ceil();
    // A threshold of 1e-30 asks for a billion: `spp` caps it anyway.
    let guess = if guess < (u32::MAX / 2) as f32 {
        guess as u32
    } else {
        u32::MAX / 2
    };
    guess.div_ceil(STEP).saturating_mul(STEP).max(STEP).min(spp)
}

/// The error of a pixel whose sum of `count` samples is `sum` and whose class A samples sum to
/// `class_a`: |mean - class A mean| summed over the channels, over sqrt(sum of the mean).
pub fn pixel_error(sum: Vec3, class_a: Vec3, count: f32) -> f32 {
    if count < 2.0 {
        return f32::INFINITY;
    }
    let mean = sum / count;
    let half_mean = class_a / (count * 0.5);
    let difference = (mean - half_mean).abs().element_sum();
    // The small constant keeps black pixels finite (Cycles' 0.0001).
    difference / (1e-4 + mean.element_sum().max(0.0).sqrt())
}

/// What an adaptive render keeps beside its sums: each pixel's class A sum and whether it takes
/// samples in the next round.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveState {
    pub width: u32,
    pub height: u32,
    /// Per pixel, row-major: the sum of its class A samples.
    pub class_a: Vec<Vec3>,
    /// Per pixel: it takes samples in the next round.
    pub active: Vec<bool>,
}

impl AdaptiveState {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            class_a: vec![Vec3::ZERO; n],
            active: vec![true; n],
        }
    }

    /// After a round: marks the pixels that take samples in the next one (error at or above
    /// `threshold` at the pixel or a 4-neighbour, and fewer than `spp` samples). Returns how
    /// many are.
    pub fn mark_active(&mut self, sums: &Sums, threshold: f32, spp: u32) -> usize {
        let (w, h) = (self.width as usize, self.height as usize);
        let noisy: Vec<bool> = sums
            .pixels
            .iter()
            .zip(&self.class_a)
            .map(|(&[r, g, b, n], &a)| pixel_error(Vec3::new(r, g, b), a, n) >= threshold)
            .collect();
        let mut count = 0;
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let near = noisy[i]
                    || (x > 0 && noisy[i - 1])
                    || (x + 1 < w && noisy[i + 1])
                    || (y > 0 && noisy[i - w])
                    || (y + 1 < h && noisy[i + w]);
                self.active[i] = near && (sums.pixels[i][3] as u32) < spp;
                count += self.active[i] as usize;
            }
        }
        count
    }
}

/// What an adaptive render did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdaptiveReport {
    /// Rounds of samples, the first (every pixel's minimum) included.
    pub rounds: u32,
    /// Samples taken over the whole image.
    pub samples: u64,
}

/// Renders adaptively into `sums` (new, the camera's size): `add(end, active, sums, class_a)`
/// brings every pixel marked in `active` from the samples it has to `end` (its indices
/// `count..end`, [`pixel_range`]), adding its class A samples to its `class_a`. Rounds end at [`min_samples`], then every [`STEP`]
/// samples, up to `spp`; `progress(samples_so_far, spp)` follows the rounds' ends.
pub fn render_adaptive<E>(
    threshold: f32,
    spp: u32,
    sums: &mut Sums,
    progress: &mut super::Progress<'_>,
    mut add: impl FnMut(u32, &[bool], &mut Sums, &mut [Vec3]) -> Result<(), E>,
) -> Result<AdaptiveReport, E> {
    let mut state = AdaptiveState::new(sums.width, sums.height);
    let mut report = AdaptiveReport::default();
    for end in round_ends(threshold, spp) {
        add(end, &state.active, sums, &mut state.class_a)?;
        report.rounds += 1;
        progress(end as u64, spp as u64);
        if state.mark_active(sums, threshold, spp) == 0 {
            break;
        }
    }
    report.samples = sums.pixels.iter().map(|p| p[3] as u64).sum();
    progress(spp as u64, spp as u64);
    Ok(report)
}

/// Where the rounds end: [`min_samples`], then every [`STEP`], then `spp`.
pub fn round_ends(threshold: f32, spp: u32) -> impl Iterator<Item = u32> {
    let first = min_samples(threshold, spp);
    std::iter::successors(Some(first), move |&end| {
        (end < spp).then(|| (end + STEP).min(spp))
    })
}

/// The range of samples an active pixel with `count` samples adds in a round ending at `end`.
pub fn pixel_range(count: f32, end: u32) -> Range<u32> {
    (count as u32).min(end)..end
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn class_a_is_half_of_every_aligned_four() {
        for block in 0..1024u32 {
            let a = (4 * block..4 * block + 4)
                .filter(|&i| is_class_a(i))
                .count();
            assert_eq!(a, 2, "block {block}");
        }
    }

    #[test]
    fn minimum_is_half_cycles_and_capped() {
        assert_eq!(min_samples(0.2, 4096), 16);
        assert_eq!(min_samples(0.1, 4096), 16);
        assert_eq!(min_samples(0.05, 4096), 32);
        assert_eq!(min_samples(0.01, 4096), 32);
        assert_eq!(min_samples(0.001, 4096), 64);
        assert_eq!(min_samples(0.01, 20), 20);
        assert_eq!(min_samples(1e-30, 4096), 4096);
        assert_eq!(min_samples(10.0, 8), 8);
    }

    #[test]
    fn rounds_step_to_the_cap() {
        let ends: Vec<u32> = round_ends(0.01, 70).collect();
        assert_eq!(ends, [32, 48, 64, 70]);
        assert_eq!(round_ends(0.01, 32).collect::<Vec<_>>(), [32]);
    }

    #[test]
    fn error_is_zero_for_equal_halves_and_grows_with_their_difference() {
        let flat = pixel_error(Vec3::splat(8.0), Vec3::splat(4.0), 8.0);
        assert_eq!(flat, 0.0);
        // Mean 1, class A mean 1.5: 0.5 per channel, over sqrt(3).
        let noisy = pixel_error(Vec3::splat(8.0), Vec3::splat(6.0), 8.0);
        assert!((noisy - 1.5 / (1e-4 + 3f32.sqrt())).abs() < 1e-6, "{noisy}");
    }

    #[test]
    fn a_noisy_pixel_keeps_its_neighbours_active() {
        let mut sums = Sums::new(4, 3);
        let mut state = AdaptiveState::new(4, 3);
        for (p, a) in sums.pixels.iter_mut().zip(&mut state.class_a) {
            *p = [16.0, 16.0, 16.0, 16.0];
            *a = Vec3::splat(8.0);
        }
        state.class_a[5] = Vec3::splat(12.0); // pixel (1, 1)
        let active = state.mark_active(&sums, 0.01, 64);
        let expected = [1, 4, 5, 6, 9];
        assert_eq!(active, expected.len());
        for i in 0..12 {
            assert_eq!(state.active[i], expected.contains(&i), "pixel {i}");
        }
        // At the cap, no pixel takes more.
        assert_eq!(state.mark_active(&sums, 0.01, 16), 0);
    }
}
