//! The stratification of the camera's four dimensions, measured exactly: the t-value of digital
//! point sets (Niederreiter). 2^m points with t-value t have 2^t points in every elementary
//! interval of volume 2^(t - m) (boxes with power-of-two sides, aligned), so t = 0 means one
//! point per interval, the best possible. Owen scrambling preserves t-values, so these numbers
//! hold for every pixel and seed. docs/sampler.md tabulates them.

use super::sobol::{lens_index, sobol, SOBOL_MATRICES};

/// A base-2 generator matrix: column j is the point of index 2^j as a 32-bit binary fraction.
pub type GeneratorMatrix = [u32; 32];

/// The matrix of Sobol' dimension `dim` at the lens index: column j is its point of index
/// lens_index(2^j).
pub fn at_lens_index(dim: usize) -> GeneratorMatrix {
    std::array::from_fn(|j| sobol(dim, lens_index(1 << j)))
}

/// Generator matrices of the camera's dimensions: film x, film y, lens x, lens y.
pub fn camera_matrices() -> [GeneratorMatrix; 4] {
    [
        SOBOL_MATRICES[0],
        SOBOL_MATRICES[1],
        at_lens_index(0),
        at_lens_index(1),
    ]
}

/// Rank over GF(2) of bit vectors.
fn rank(vectors: &[u32]) -> usize {
    let mut basis: Vec<u32> = Vec::new();
    for &v in vectors {
        let reduced = basis.iter().fold(v, |x, &b| x.min(x ^ b));
        if reduced != 0 {
            basis.push(reduced);
        }
    }
    basis.len()
}

/// The first `digits` rows of `matrix` restricted to its first `m` columns, as bit vectors.
fn rows(matrix: &GeneratorMatrix, m: u32, digits: u32) -> Vec<u32> {
    (0..digits)
        .map(|r| {
            (0..m).fold(0, |row, c| {
                row | (((matrix[c as usize] >> (31 - r)) & 1) << c)
            })
        })
        .collect()
}

/// Whether every split of `k` digits among the matrices gives independent rows: then each
/// elementary interval of volume 2^-k holds 2^(m-k) of the 2^m points.
fn resolves(matrices: &[&GeneratorMatrix], m: u32, k: u32) -> bool {
    fn splits(matrices: &[&GeneratorMatrix], m: u32, left: u32, taken: &mut Vec<u32>) -> bool {
        if taken.len() + 1 == matrices.len() {
            taken.push(left);
            let vectors: Vec<u32> = matrices
                .iter()
                .zip(taken.iter())
                .flat_map(|(matrix, &d)| rows(matrix, m, d))
                .collect();
            taken.pop();
            return rank(&vectors) == vectors.len();
        }
        (0..=left).all(|d| {
            taken.push(d);
            let ok = splits(matrices, m, left - d, taken);
            taken.pop();
            ok
        })
    }
    splits(matrices, m, k, &mut Vec::new())
}

/// The t-value of the first 2^m points (and of every aligned block of 2^m) of the digital
/// sequence with these generator matrices, one per dimension.
pub fn t_value(matrices: &[&GeneratorMatrix], m: u32) -> u32 {
    assert!(m <= 32 && !matrices.is_empty());
    (0..=m)
        .find(|&t| resolves(matrices, m, m - t))
        .expect("t = m always holds")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_t_values() {
        let [i, p, c3, c4] = SOBOL_MATRICES;
        for m in 1..=12 {
            assert_eq!(t_value(&[&i, &p], m), 0, "Sobol' dimensions 1-2 at m = {m}");
            // A dimension against itself: stratified in 1-D only.
            assert_eq!(t_value(&[&i, &i], m), m - 1);
        }
        // Joe and Kuo's dimensions 3-4 are not a (0, 2)-sequence: t = 1 at m = 2.
        assert_eq!(t_value(&[&c3, &c4], 2), 1);
    }

    #[test]
    fn camera_pairs_are_0_2_and_cross_pairs_nearly() {
        let [fx, fy, lx, ly] = camera_matrices();
        for m in 1..=16 {
            assert_eq!(t_value(&[&fx, &fy], m), 0, "film, m = {m}");
            assert_eq!(t_value(&[&lx, &ly], m), 0, "lens, m = {m}");
            for (name, a, b) in [
                ("film x - lens x", &fx, &lx),
                ("film y - lens y", &fy, &ly),
                ("film x - lens y", &fx, &ly),
                ("film y - lens x", &fy, &lx),
            ] {
                let t = t_value(&[a, b], m);
                assert!(t <= 3, "{name}: t = {t} at m = {m}");
            }
        }
        for m in 1..=10 {
            let t = t_value(&[&fx, &fy, &lx, &ly], m);
            assert!(t <= 4, "4-D: t = {t} at m = {m}");
        }
    }
}
