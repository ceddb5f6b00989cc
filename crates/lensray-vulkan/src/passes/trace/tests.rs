//! The split of a call into dispatches.

use super::steps::Split;

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

/// Every pixel row gets every sample exactly once, in sample order, whatever budget each range
/// of samples is planned with; each band loads first and copies out last.
#[test]
fn a_plan_covers_each_row_and_sample_once_whatever_the_budgets() {
    use super::steps::StepPlan;
    use lensray_core::interface::TRACE_GROUP_SIZE as GROUP;
    for &(w, h, band_rows, ref samples, raster) in &[
        (64u32, 48u32, 20u32, 0u32..6u32, false),
        (3840, 37, 16, 3..9, false),
        (100, 30, 30, 0..4, true),
    ] {
        let mut plan = StepPlan::new((w, h), band_rows, samples.clone(), 0, raster);
        let total = plan.work();
        let budgets = [1000u64, 1 << 14, 300, 1 << 22];
        let mut next_sample = vec![samples.start; h as usize];
        let (mut work, mut i) = (0, 0);
        let mut band_open = false;
        while let Some(step) = plan.next(budgets[i % budgets.len()]) {
            i += 1;
            let p = step.push;
            assert_eq!(step.load, !band_open, "{w}x{h}: step {i} {p:?}");
            band_open = step.copy_out.is_none();
            for b in 0..p.block_count {
                let block = p.block_first + b * p.block_stride;
                let rows = block * GROUP..((block + 1) * GROUP).min(p.band_height);
                for row in rows {
                    let next = &mut next_sample[(p.band_origin + row) as usize];
                    assert_eq!(*next, p.sample_begin, "{w}x{h}: row {row} of {p:?}");
                    *next = p.sample_end;
                }
            }
            work += step.work;
        }
        assert!(plan.is_done() && !band_open);
        // Budgets at or above the first never take more steps than the first alone (the
        // timestamp pool holds that many).
        let fresh = StepPlan::new((w, h), band_rows, samples.clone(), 0, raster);
        let mut growing = fresh.clone();
        let grown = (0..).map_while(|k| growing.next(1000 << (k % 5))).count();
        assert!(grown <= fresh.count(1000), "{w}x{h}: {grown}");
        assert!(next_sample.iter().all(|&s| s == samples.end), "{w}x{h}");
        assert_eq!(work, total, "{w}x{h}");
    }
}
