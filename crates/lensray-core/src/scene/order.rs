//! A spatial order of a mesh's triangles: a balanced median split of their centroids.
//!
//! Acceleration-structure builders that take triangles in the order given build far worse trees
//! from a scattered order. lavapipe's is one: it halves the list at its middle index, again and
//! again, and bounds each half, so a node is tight only where its range of the list is compact in
//! space (`cargo bench --bench order`, docs/scenes-bench.md: a 100k-triangle mesh shuffled traces
//! 300x slower than sorted without this order). The order here is the one that builder needs:
//! the centroids split at their median along the longest side of their bounds, each half in front
//! of the other and split the same way, with lavapipe's sizes (the first half takes the middle
//! one). A Morton order is compact at its aligned power-of-two ranges only, and on a flat mesh
//! interleaves far-apart rows; it traced the same mesh 3x slower. The GPU upload hands every
//! builder the triangles in this order, so the speed of a render does not depend on how the file
//! happened to list them.

use glam::Vec3;

/// A mesh's triangles as every path numbers them: in [`spatial_order`], the double-sided ones
/// (`single_sided(t)` false) first, then the single-sided ones. The GPU's acceleration
/// structures cull back faces per range of triangles (an instance), so each side's triangles of
/// a mesh are one range; a mesh of one kind keeps its spatial order.
pub fn sided_order(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    single_sided: impl Fn(usize) -> bool,
) -> Vec<u32> {
    let (mut order, single): (Vec<u32>, Vec<u32>) = spatial_order(positions, triangles)
        .into_iter()
        .partition(|&t| !single_sided(t as usize));
    order.extend(single);
    order
}

/// The triangles' indices in the order of a balanced median split of their centroids (ties,
/// equal coordinates, broken by index, so the order depends on the positions and the list's order
/// only through them).
pub fn spatial_order(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<u32> {
    let centroids: Vec<Vec3> = triangles
        .iter()
        .map(|t| t.iter().map(|&i| positions[i as usize]).sum::<Vec3>() / 3.0)
        .collect();
    let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
    split(&centroids, &mut order);
    order
}

/// Orders `order` (indices of `centroids`): the first ceil(n / 2) are those below the median
/// along the longest side of their bounds, then each half the same way.
fn split(centroids: &[Vec3], order: &mut [u32]) {
    if order.len() < 2 {
        return;
    }
    let (lo, hi) = order
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &i| {
            let c = centroids[i as usize];
            (lo.min(c), hi.max(c))
        });
    let axis = (hi - lo).max_position();
    let mid = order.len().div_ceil(2);
    order.select_nth_unstable_by(mid - 1, |&a, &b| {
        centroids[a as usize][axis]
            .total_cmp(&centroids[b as usize][axis])
            .then(a.cmp(&b))
    });
    let (first, second) = order.split_at_mut(mid);
    split(centroids, first);
    split(centroids, second);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small triangle at each of `corners`, in that order.
    fn triangles_at(corners: &[Vec3]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for (t, &c) in corners.iter().enumerate() {
            let base = 3 * t as u32;
            positions.extend([c, c + Vec3::X * 0.5, c + Vec3::Y * 0.5]);
            triangles.push([base, base + 1, base + 2]);
        }
        (positions, triangles)
    }

    /// A row of triangles along x given in shuffled order comes back sorted by x, and the
    /// order is a permutation.
    #[test]
    fn sorts_a_row_by_position() {
        let xs = [5.0, 1.0, 7.0, 0.0, 3.0, 6.0, 2.0, 4.0, 8.0];
        let corners: Vec<Vec3> = xs.iter().map(|&x| Vec3::new(x, 0.0, 0.0)).collect();
        let (positions, triangles) = triangles_at(&corners);
        let order = spatial_order(&positions, &triangles);
        let sorted: Vec<f32> = order.iter().map(|&i| xs[i as usize]).collect();
        assert_eq!(sorted, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
    }

    /// Four corners of a rectangle: the first split halves its longer side, then each half is
    /// split along the shorter one.
    #[test]
    fn splits_the_longest_side_first() {
        let (x, z) = (Vec3::X, Vec3::Z);
        let (positions, triangles) =
            triangles_at(&[Vec3::ZERO, 10.0 * x, 5.0 * z, 10.0 * x + 5.0 * z]);
        assert_eq!(spatial_order(&positions, &triangles), [0, 2, 1, 3]);
        let (positions, triangles) =
            triangles_at(&[Vec3::ZERO, 5.0 * x, 10.0 * z, 5.0 * x + 10.0 * z]);
        assert_eq!(spatial_order(&positions, &triangles), [0, 1, 2, 3]);
    }

    #[test]
    fn degenerate_bounds_keep_every_triangle() {
        let positions = vec![Vec3::ONE; 3];
        let order = spatial_order(&positions, &[[0, 1, 2]; 4]);
        assert_eq!(order, [0, 1, 2, 3]);
        assert!(spatial_order(&positions, &[]).is_empty());
    }
}
