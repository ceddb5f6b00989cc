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
