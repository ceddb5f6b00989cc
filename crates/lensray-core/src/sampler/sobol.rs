//! The Sobol' sequence in base 2: point i of dimension d is the generator matrix C_d times the
//! binary digits of i. Generator matrices of the first four dimensions come from S. Joe and
//! F. Y. Kuo's direction numbers ("Constructing Sobol sequences with better two-dimensional
//! projections", 2008; file new-joe-kuo-6.21201): dimension 1 is van der Corput's (the identity),
//! dimensions 2-4 have `(s, a, m)` = `(1, 0, [1])`, `(2, 1, [1, 3])`, `(3, 1, [1, 3, 1])`.
//!
//! The sampler uses the first two dimensions, a (0, 2)-sequence (every aligned block of 2^k points
//! has one point in each of the 2^k elementary intervals of area 2^-k), twice: at the sample
//! index for the film and at [`lens_index`] of it for the lens. Both dimensions have closed forms
//! in the reversed digit order that Owen scrambling works in ([`sobol_reversed`]); the matrices
//! define them and test them, and serve the Joe-Kuo 4-D variant measured in `benches/sampler.rs`.

/// Joe-Kuo (s, a, m_1..m_s) of dimensions 2, 3, 4 (dimension 1 is the identity).
const JOE_KUO: [(u32, u32, [u32; 3]); 3] =
    [(1, 0, [1, 0, 0]), (2, 1, [1, 3, 0]), (3, 1, [1, 3, 1])];

/// Dimensions with generator matrices here.
pub const SOBOL_DIMENSIONS: usize = 4;

/// Column j of dimension d's generator matrix: the direction number v_(j+1) as a 32-bit binary
/// fraction (bit 31 = 1/2). Point i is the XOR of the columns of i's set bits.
pub const SOBOL_MATRICES: [[u32; 32]; SOBOL_DIMENSIONS] = sobol_matrices();

const fn sobol_matrices() -> [[u32; 32]; SOBOL_DIMENSIONS] {
    let mut out = [[0u32; 32]; SOBOL_DIMENSIONS];
    let mut j = 0;
    while j < 32 {
        out[0][j] = 1 << (31 - j);
        j += 1;
    }
    let mut d = 1;
    while d < SOBOL_DIMENSIONS {
        let (s, a, m) = JOE_KUO[d - 1];
        let s = s as usize;
        let v = &mut out[d];
        let mut j = 0;
        while j < 32 {
            v[j] = if j < s {
                m[j] << (31 - j)
            } else {
                // Bratley and Fox's recurrence on the primitive polynomial's coefficients a.
                let mut x = v[j - s] ^ (v[j - s] >> s);
                let mut k = 1;
                while k < s {
                    if (a >> (s - 1 - k)) & 1 == 1 {
                        x ^= v[j - k];
                    }
                    k += 1;
                }
                x
            };
            j += 1;
        }
        d += 1;
    }
    out
}

/// Point `index` of Sobol' dimension `dim` (< [`SOBOL_DIMENSIONS`]) as a 32-bit binary fraction.
#[inline]
pub fn sobol(dim: usize, index: u32) -> u32 {
    let matrix = &SOBOL_MATRICES[dim];
    let mut bits = index;
    let mut out = 0;
    while bits != 0 {
        let j = bits.trailing_zeros();
        out ^= matrix[j as usize];
        bits &= bits - 1;
    }
    out
}

/// Point `index` of Sobol' dimension `dim` (0 or 1) with its binary digits reversed (bit 0 is
/// the most significant), in O(1): dimension 0 is the index itself, and dimension 1's matrix is
/// Pascal's triangle mod 2, whose digit r is, by Lucas' theorem, the XOR of the index bits c
/// with c ⊇ r (as bit sets): five shift-and-mask steps, one per bit of r.
#[inline]
pub fn sobol_reversed(dim: u32, index: u32) -> u32 {
    let mut x = index;
    if dim == 1 {
        x ^= (x >> 1) & 0x5555_5555;
        x ^= (x >> 2) & 0x3333_3333;
        x ^= (x >> 4) & 0x0f0f_0f0f;
        x ^= (x >> 8) & 0x00ff_00ff;
        x ^= x >> 16;
    }
    x
}

/// Columns 0..16 of U, the linear map from a sample's index to its lens index: column c is the
/// lens index of sample 2^c (bit c set, and lower bits only, so bit c of a lens index depends on
/// the index's bits c and up: U maps every aligned block of 2^k indices onto an aligned block).
/// Higher index bits map to themselves. The lens pair is thus
/// the same (0, 2)-sequence as the film pair, with generator matrices (I U, P U), and U was
/// chosen so that the four film-lens pairs and the whole 4-D set are also well stratified:
/// hill climbing over U's free bits minimising a weighted sum of t-values for 2^1..2^16 points
/// (`cargo bench --bench sampler -- --search-lens-index`; t-values in docs/sampler.md).
/// Defined with what the shaders share (`crate::interface`).
pub use crate::interface::LENS_INDEX_COLUMNS;

/// The lens pair's index of sample `index`: U times the index's bits (see
/// [`LENS_INDEX_COLUMNS`]), branch-free so that it vectorizes.
#[inline]
pub fn lens_index(index: u32) -> u32 {
    let mut lens = index & 0xffff_0000;
    for (bit, &column) in LENS_INDEX_COLUMNS.iter().enumerate() {
        lens ^= column & 0u32.wrapping_sub((index >> bit) & 1);
    }
    lens
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_points_are_the_published_ones() {
        // In eighths, in natural (not Gray-code) order: direction numbers 1/2, 3/4, 5/8 for
        // dimension 2 and 1/2, 3/4, 3/8 for dimension 3 (m_3 = 3 from the recurrence).
        let eighths = |d: usize| (0..8).map(|i| sobol(d, i) >> 29).collect::<Vec<_>>();
        assert_eq!(eighths(0), [0, 4, 2, 6, 1, 5, 3, 7]);
        assert_eq!(eighths(1), [0, 4, 6, 2, 5, 1, 3, 7]);
        assert_eq!(eighths(2), [0, 4, 6, 2, 3, 7, 5, 1]);
        assert_eq!(
            SOBOL_MATRICES[1][..4],
            [1 << 31, 3 << 30, 5 << 29, 15 << 28]
        );
        assert_eq!(SOBOL_MATRICES[3][..4], [1 << 31, 3 << 30, 1 << 29, 5 << 28]);
    }

    #[test]
    fn closed_forms_equal_the_matrices() {
        let mut x = 0x1234_5678u32;
        for i in (0..5000u32).chain([u32::MAX, 1 << 31, 0xffff_0000]) {
            x = crate::sampler::hash_u32(x ^ i);
            for index in [i, x] {
                for dim in 0..2 {
                    assert_eq!(
                        sobol_reversed(dim, index).reverse_bits(),
                        sobol(dim as usize, index),
                        "dimension {dim}, index {index:#x}"
                    );
                }
            }
        }
    }

    #[test]
    fn lens_index_maps_aligned_blocks_onto_aligned_blocks() {
        for (c, &column) in LENS_INDEX_COLUMNS.iter().enumerate() {
            assert_eq!(
                column >> c,
                1,
                "column {c} must have bit {c} as its highest"
            );
        }
        for k in [0u32, 1, 4, 8, 12, 16, 18] {
            for block in [0u32, 1, 5, 1000] {
                let mut images: Vec<u32> = (block << k..(block + 1) << k).map(lens_index).collect();
                images.sort_unstable();
                let first = images[0] & !((1u32 << k) - 1);
                let expected: Vec<u32> = (first..first + (1 << k)).collect();
                assert_eq!(images, expected, "block {block} of 2^{k}");
            }
        }
        // Linear: the image of a XOR is the XOR of the images.
        for (a, b) in [(3u32, 5u32), (0xdead_beef, 0x1234_5678), (u32::MAX, 1)] {
            assert_eq!(lens_index(a ^ b), lens_index(a) ^ lens_index(b));
        }
    }

    #[test]
    fn first_two_dimensions_are_a_0_2_sequence() {
        // Every aligned block of 2^k points: one point per elementary interval 2^-a x 2^-(k-a).
        for k in 0..=10u32 {
            for block in [0u32, 1, 7] {
                for a in 0..=k {
                    let mut seen = vec![false; 1 << k];
                    for i in block << k..(block + 1) << k {
                        let (x, y) = (sobol(0, i), sobol(1, i));
                        let cell = if k == 0 {
                            0
                        } else {
                            ((x as u64 >> (32 - a)) << (k - a)) | (y as u64 >> (32 - (k - a)))
                        };
                        assert!(!seen[cell as usize], "k {k} block {block} a {a}");
                        seen[cell as usize] = true;
                    }
                }
            }
        }
    }
}
