//! How one `accumulate` call is split into dispatches (steps): bands of rows, ranges of
//! samples, groups of row blocks, each range of samples sized from the speed measured so far
//! (`DispatchSizing`), the call's own dispatches included: `StepPlan` plans the steps one at a
//! time, so a sample pass costs the host the same few dispatches whatever the image's size
//! once the speed is known.

use std::ops::Range;

use lensray_core::interface::{TracePush, TRACE_GROUP_SIZE as GROUP};

/// Pixel-samples of the first dispatches: ~0.03-0.1 s on lavapipe (2 cores, 80k triangles).
const INITIAL_SAMPLES_PER_DISPATCH: u64 = 1 << 16;
/// The most pixel-samples per dispatch, however fast the device: ~14 ms on an NVIDIA H200
/// (4.7 G samples/s, default scene), where a smaller cap made each 4K sample pass two
/// dispatches and the host's time per dispatch 40 % of the tracing.
const MAX_SAMPLES_PER_DISPATCH: u64 = 1 << 26;
/// Dispatch duration aimed at when sizing the next dispatches from the last one's timestamps
/// (well under the ~0.5 s that a single dispatch should not exceed).
const TARGET_DISPATCH_MS: f64 = 100.0;

/// How large the dispatches of the next calls are: sized from the measured speed, capped.
pub(crate) struct DispatchSizing {
    /// Upper bound of pixel-samples per dispatch (tests lower it to force many submissions).
    pub samples_per_dispatch: u64,
    /// Current size of a dispatch, adapted to the measured speed.
    adaptive_samples: u64,
}

impl Default for DispatchSizing {
    fn default() -> Self {
        Self {
            samples_per_dispatch: MAX_SAMPLES_PER_DISPATCH,
            adaptive_samples: INITIAL_SAMPLES_PER_DISPATCH,
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
    pub(super) fn new(width: u32, height: u32, spp: u32, budget: u64) -> Self {
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

/// One dispatch of an `accumulate` call and what comes with it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Step {
    pub(super) push: TracePush,
    /// The first step of a band: the band's sums come in from the film first.
    pub(super) load: bool,
    /// The last step of a band: its sums (bytes) go back to the film after.
    pub(super) copy_out: Option<u64>,
    /// Pixel-samples (progress, speed).
    pub(super) work: u64,
}

impl DispatchSizing {
    /// Pixel-samples of the next sample range's dispatches: the measured size, capped.
    pub(super) fn budget(&self) -> u64 {
        self.adaptive_samples.min(self.samples_per_dispatch)
    }

    /// Sizes the next dispatches from `work` pixel-samples traced in `ms` GPU milliseconds
    /// (nothing measured when either is 0): grows at most 4x per measurement, shrinks at once.
    pub(super) fn measured(&mut self, work: u64, ms: f64) {
        if work > 0 && ms > 0.0 {
            let rate = work as f64 / ms;
            self.adaptive_samples = ((rate * TARGET_DISPATCH_MS) as u64)
                .min(4 * self.adaptive_samples)
                .clamp(1024, MAX_SAMPLES_PER_DISPATCH);
        }
    }
}

/// The steps of one `accumulate` call, planned one at a time: band after band; in a band, the
/// raster path's samples one by one, else ranges of samples of groups of row blocks, each range
/// sized by the budget given when it starts (any split adds each pixel's samples in the same
/// order, so the sums do not depend on it).
#[derive(Clone, Debug)]
pub(super) struct StepPlan {
    width: u32,
    height: u32,
    band_rows: u32,
    samples: Range<u32>,
    mode: u32,
    raster: bool,
    band_origin: u32,
    sample_begin: u32,
    range: Option<SampleRange>,
}

/// The range of samples being planned in the current band and how its row blocks are dealt.
#[derive(Clone, Copy, Debug)]
struct SampleRange {
    sample_end: u32,
    blocks: u32,
    groups: u32,
    next_group: u32,
}

impl StepPlan {
    pub(super) fn new(
        (width, height): (u32, u32),
        band_rows: u32,
        samples: Range<u32>,
        mode: u32,
        raster: bool,
    ) -> Self {
        Self {
            width,
            height,
            band_rows: band_rows.max(1),
            sample_begin: samples.start,
            samples,
            mode,
            raster,
            band_origin: 0,
            range: None,
        }
    }

    /// Pixel-samples of the whole call (the progress's total).
    pub(super) fn work(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height) * u64::from(self.samples.len() as u32)
    }

    /// Every step is planned.
    pub(super) fn is_done(&self) -> bool {
        self.samples.is_empty() || self.band_origin >= self.height
    }

    /// How many steps the rest of the call takes with `budget` for every range.
    pub(super) fn count(&self, budget: u64) -> usize {
        let mut plan = self.clone();
        std::iter::from_fn(|| plan.next(budget)).count()
    }

    /// The next step; a range of samples that starts with it is sized by `budget`.
    pub(super) fn next(&mut self, budget: u64) -> Option<Step> {
        if self.is_done() {
            return None;
        }
        let (width, band_origin) = (self.width, self.band_origin);
        let band_height = self.band_rows.min(self.height - band_origin);
        let sample_begin = self.sample_begin;
        let range = *self.range.get_or_insert_with(|| {
            let (sample_end, groups, blocks) = if self.raster {
                (sample_begin + 1, 1, band_height.div_ceil(GROUP))
            } else {
                let spp = self.samples.end;
                let split = Split::new(width, band_height, spp - sample_begin, budget);
                // The band's blocks of GROUP rows are dealt out to `groups` dispatches with a
                // stride, so each dispatch covers the whole band evenly (similar cost per
                // dispatch, sky and geometry mixed alike) while each workgroup still traces a
                // coherent 8x8 tile.
                let blocks = band_height.div_ceil(GROUP);
                let blocks_per = (split.rows_per / GROUP).max(1);
                let end = (sample_begin + split.samples_per).min(spp);
                (end, blocks.div_ceil(blocks_per), blocks)
            };
            SampleRange {
                sample_end,
                blocks,
                groups,
                next_group: 0,
            }
        });
        let group = range.next_group;
        let (block_count, rows) = if self.raster {
            (range.blocks, band_height)
        } else {
            let block_count = (range.blocks - group).div_ceil(range.groups);
            let rows = (0..block_count)
                .map(|b| GROUP.min(band_height - (group + b * range.groups) * GROUP))
                .sum();
            (block_count, rows)
        };
        let mut step = Step {
            push: TracePush {
                band_origin,
                band_height,
                block_first: group,
                block_stride: range.groups,
                block_count,
                sample_begin,
                sample_end: range.sample_end,
                mode: self.mode,
            },
            load: sample_begin == self.samples.start && group == 0,
            copy_out: None,
            work: u64::from(rows) * u64::from(width) * u64::from(range.sample_end - sample_begin),
        };
        if group + 1 < range.groups {
            self.range = Some(SampleRange {
                next_group: group + 1,
                ..range
            });
        } else {
            self.range = None;
            self.sample_begin = range.sample_end;
            if self.sample_begin >= self.samples.end {
                step.copy_out = Some(u64::from(band_height) * u64::from(width) * 16);
                self.band_origin += band_height;
                self.sample_begin = self.samples.start;
            }
        }
        Some(step)
    }
}
