//! Progressive rendering: which samples of which pixels to trace next, so an accumulation keeps
//! converging a little every frame. Work goes by sample index: sample s of every pixel before
//! sample s + 1 of any, so each pixel adds its samples in the order a one-shot render does
//! (the same sums, bit for bit). When one sample of the whole image is more than a frame's
//! budget, it is split into groups of row blocks dealt out with a stride, so every frame
//! touches the whole image evenly.

/// Samples `sample_begin..sample_end` of the row blocks `block_first + i * block_stride`,
/// `i < block_count` (a block is `block_rows` rows).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WorkItem {
    pub sample_begin: u32,
    pub sample_end: u32,
    pub block_first: u32,
    pub block_stride: u32,
    pub block_count: u32,
    /// Pixels times samples.
    pub pixel_samples: u64,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgressiveSchedule {
    width: u32,
    height: u32,
    block_rows: u32,
    target: u32,
    /// Every pixel has samples 0..next_sample; sample next_sample is under way in groups.
    next_sample: u32,
    /// The next group of the sample under way, of `groups`.
    group: u32,
    groups: u32,
}

impl ProgressiveSchedule {
    pub fn new(width: u32, height: u32, block_rows: u32, target_spp: u32) -> Self {
        Self {
            width,
            height,
            block_rows: block_rows.max(1),
            target: target_spp,
            next_sample: 0,
            group: 0,
            groups: 1,
        }
    }

    /// Starts over (the camera or the scene changed).
    pub fn restart(&mut self) {
        self.next_sample = 0;
        self.group = 0;
        self.groups = 1;
    }

    /// Goes on from sample `next_sample` of every pixel to `target` (adaptive sampling's next
    /// round: the shader skips the samples each pixel already has, `film::adaptive`).
    pub fn resume(&mut self, next_sample: u32, target: u32) {
        self.next_sample = next_sample;
        self.group = 0;
        self.groups = 1;
        self.target = target;
    }

    /// A new target: raising it continues where the accumulation is.
    pub fn set_target(&mut self, spp: u32) {
        self.target = spp;
    }

    pub fn target(&self) -> u32 {
        self.target
    }

    /// Samples every pixel has.
    pub fn samples_complete(&self) -> u32 {
        self.next_sample
    }

    pub fn converged(&self) -> bool {
        self.next_sample >= self.target
    }

    fn blocks(&self) -> u32 {
        self.height.div_ceil(self.block_rows)
    }

    fn rows_of_group(&self, group: u32, groups: u32) -> u32 {
        let blocks = self.blocks();
        let count = (blocks - group).div_ceil(groups);
        (0..count)
            .map(|i| {
                let first = (group + i * groups) * self.block_rows;
                self.block_rows.min(self.height - first)
            })
            .sum()
    }

    /// The work of the next frame: about `budget` pixel-samples, give or take half a group (at
    /// least one item while not converged), at most `max_items` items.
    pub fn plan(&mut self, budget: u64, max_items: usize) -> Vec<WorkItem> {
        let pixels = u64::from(self.width) * u64::from(self.height);
        let blocks = self.blocks();
        let mut items = Vec::new();
        let mut left = budget as i128;
        while !self.converged() && left > 0 && items.len() < max_items && pixels > 0 {
            if self.group == 0 {
                let whole = budget / pixels;
                if whole >= 1 || u64::from(blocks) == 1 {
                    // Whole samples of the whole image fit.
                    let count = (whole.max(1) as u32).min(self.target - self.next_sample);
                    let work = pixels * u64::from(count);
                    items.push(WorkItem {
                        sample_begin: self.next_sample,
                        sample_end: self.next_sample + count,
                        block_first: 0,
                        block_stride: 1,
                        block_count: blocks,
                        pixel_samples: work,
                    });
                    self.next_sample += count;
                    left -= work as i128;
                    continue;
                }
                self.groups = (pixels.div_ceil(budget.max(1)) as u32).clamp(1, blocks);
            }
            let rows = self.rows_of_group(self.group, self.groups);
            let work = u64::from(rows) * u64::from(self.width);
            // Past the budget by more than half a group: leave it to the next frame.
            if !items.is_empty() && 2 * left < work as i128 {
                break;
            }
            items.push(WorkItem {
                sample_begin: self.next_sample,
                sample_end: self.next_sample + 1,
                block_first: self.group,
                block_stride: self.groups,
                block_count: (blocks - self.group).div_ceil(self.groups),
                pixel_samples: work,
            });
            left -= work as i128;
            self.group += 1;
            if self.group == self.groups {
                self.group = 0;
                self.next_sample += 1;
            }
        }
        items
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Replays a schedule: the samples each row receives, in order.
    fn replay(s: &mut ProgressiveSchedule, budgets: impl Iterator<Item = u64>) -> Vec<Vec<u32>> {
        let mut rows = vec![Vec::new(); s.height as usize];
        for budget in budgets {
            for item in s.plan(budget, 64) {
                for i in 0..item.block_count {
                    let first = (item.block_first + i * item.block_stride) * s.block_rows;
                    for row in first..(first + s.block_rows).min(s.height) {
                        rows[row as usize].extend(item.sample_begin..item.sample_end);
                    }
                }
            }
        }
        rows
    }

    #[test]
    fn every_pixel_gets_each_sample_once_in_order() {
        // Budgets from a tenth of a sample to several samples of the image, varying per frame.
        for (width, height, target) in [(37, 29, 7), (64, 64, 16), (5, 3, 3), (100, 8, 5)] {
            let mut s = ProgressiveSchedule::new(width, height, 8, target);
            let pixels = u64::from(width * height);
            let budgets = (0..10_000u64).map(|f| (pixels / 10 + 1) * (1 + f % 37));
            let rows = replay(&mut s, budgets);
            assert!(s.converged());
            for (r, samples) in rows.iter().enumerate() {
                assert_eq!(
                    samples,
                    &(0..target).collect::<Vec<_>>(),
                    "{width}x{height} row {r}"
                );
            }
        }
    }

    #[test]
    fn a_frame_stays_near_its_budget() {
        let mut s = ProgressiveSchedule::new(1280, 720, 8, 64);
        let budget = 100_000;
        for _ in 0..50 {
            let work: u64 = s.plan(budget, 64).iter().map(|i| i.pixel_samples).sum();
            // Within half a group (here 72 rows) of the budget.
            assert!(work > 0 && work.abs_diff(budget) <= 1280 * 36, "{work}");
        }
        assert!(s.samples_complete() >= 5);
        // A big budget takes whole samples at once.
        let mut s = ProgressiveSchedule::new(64, 64, 8, 64);
        let items = s.plan(64 * 64 * 10, 64);
        assert_eq!(items.len(), 1);
        assert_eq!((items[0].sample_begin, items[0].sample_end), (0, 10));
    }

    #[test]
    fn restart_and_raising_the_target() {
        let mut s = ProgressiveSchedule::new(16, 16, 8, 4);
        s.plan(u64::MAX / 4, 64);
        assert!(s.converged() && s.samples_complete() == 4);
        assert!(s.plan(1 << 20, 64).is_empty());
        s.set_target(6);
        let items = s.plan(u64::MAX / 4, 64);
        assert_eq!((items[0].sample_begin, items[0].sample_end), (4, 6));
        s.restart();
        assert_eq!(s.samples_complete(), 0);
        assert!(!s.converged());
    }

    #[test]
    fn resume_goes_on_from_a_sample_to_a_new_target() {
        let mut s = ProgressiveSchedule::new(16, 16, 8, 32);
        s.plan(u64::MAX / 4, 64);
        assert!(s.converged());
        // An adaptive round: the pixel furthest behind has 16, the round ends at 48.
        s.resume(16, 48);
        assert!(!s.converged());
        let items = s.plan(u64::MAX / 4, 64);
        assert_eq!((items[0].sample_begin, items[0].sample_end), (16, 48));
        assert!(s.converged() && s.samples_complete() == 48);
    }
}
