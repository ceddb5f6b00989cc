//! How one `accumulate` call is split into dispatches (steps): bands of rows, ranges of
//! samples, groups of row blocks, each step sized from the measured speed (`DispatchSizing`).

use std::ops::Range;

use lensray_core::interface::{TracePush, TRACE_GROUP_SIZE as GROUP};

/// Pixel-samples of the first dispatches: ~0.03-0.1 s on lavapipe (2 cores, 80k triangles).
const INITIAL_SAMPLES_PER_DISPATCH: u64 = 1 << 16;
/// The most pixel-samples per dispatch, however fast the device.
const MAX_SAMPLES_PER_DISPATCH: u64 = 1 << 22;
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
    /// The dispatches of one `accumulate` call, in order: band after band; in a band, the
    /// raster path's samples one by one, else ranges of samples of groups of row blocks sized
    /// by `adaptive_samples` (any split adds each pixel's samples in the same order, so the
    /// sums do not depend on it).
    pub(super) fn steps(
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

    /// Sizes the next calls' dispatches from `work` pixel-samples traced in `ms` GPU
    /// milliseconds (nothing measured when either is 0): grows at most 4x per call, shrinks at
    /// once.
    pub(super) fn measured(&mut self, work: u64, ms: f64) {
        if work > 0 && ms > 0.0 {
            let rate = work as f64 / ms;
            self.adaptive_samples = ((rate * TARGET_DISPATCH_MS) as u64)
                .min(4 * self.adaptive_samples)
                .clamp(1024, MAX_SAMPLES_PER_DISPATCH);
        }
    }
}
