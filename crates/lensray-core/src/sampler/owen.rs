//! Hash-based Owen scrambling (B. Burley 2020, "Practical Hash-based Owen Scrambling", after
//! Laine and Karras 2011) with N. Vegdahl's improved Laine-Karras hash (2021, "Building a Better
//! LK Hash", as in pbrt-v4's `FastOwenScrambler`).
//!
//! Owen scrambling flips each binary digit of a point in [0, 1) by a random function of the
//! digits above it. With the digits stored reversed (bit 0 = the most significant digit) that
//! is a bijection in which bit k depends only on bits below k, which is what additions,
//! multiplications and `x ^= x * even` do: one hash scrambles all 32 digits at once.

/// A random bijection of u32 in which bit k of the result is bit k of `x` flipped by a function
/// of `seed` and the bits of `x` below k.
#[inline]
pub fn laine_karras_permutation(mut x: u32, seed: u32) -> u32 {
    x ^= x.wrapping_mul(0x3d20_adea);
    x = x.wrapping_add(seed);
    x = x.wrapping_mul((seed >> 16) | 1);
    x ^= x.wrapping_mul(0x0552_6c56);
    x ^= x.wrapping_mul(0x53a2_2864);
    x
}

/// The Owen-scrambled value, as 32 binary digits in the normal order, of the value whose digits
/// are given reversed (bit 0 the most significant): Sobol' points come out that way.
#[inline]
pub fn owen_scramble_reversed(reversed: u32, seed: u32) -> u32 {
    laine_karras_permutation(reversed, seed).reverse_bits()
}

/// Burley's shuffle: the index Owen-scrambled as if it were a value. The index's high bits are
/// permuted as a whole and its low bits by a function of the high ones, so every aligned block
/// of 2^k indices maps onto an aligned block of 2^k indices: a shuffled sequence keeps the
/// stratification of its power-of-two prefixes, in a random order independent of other seeds.
#[inline]
pub fn shuffle_index(index: u32, seed: u32) -> u32 {
    laine_karras_permutation(index.reverse_bits(), seed).reverse_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_is_nested() {
        // Bit k of the result depends only on bits 0..=k of the input: changing bits above k
        // leaves bits 0..=k alone, for any seed.
        let mut state = 1u32;
        for _ in 0..2000 {
            state = crate::sampler::hash_u32(state.wrapping_add(0x9e37_79b9));
            let (x, seed) = (state, crate::sampler::hash_u32(state));
            let k = state % 31;
            let low = (2u32 << k) - 1;
            let changed = x ^ (!low & crate::sampler::hash_u32(x ^ 77));
            assert_eq!(
                laine_karras_permutation(x, seed) & low,
                laine_karras_permutation(changed, seed) & low,
                "x {x:#x} seed {seed:#x} k {k}"
            );
        }
    }

    #[test]
    fn shuffle_maps_aligned_blocks_onto_aligned_blocks() {
        for seed in [0u32, 1, 0xdead_beef, 0x1234_5678] {
            for k in [0u32, 1, 3, 6] {
                for block in [0u32, 1, 5, 1000] {
                    let size = 1u32 << k;
                    let mut images: Vec<u32> = (block * size..(block + 1) * size)
                        .map(|i| shuffle_index(i, seed))
                        .collect();
                    let target = images[0] >> k;
                    assert!(
                        images.iter().all(|&j| j >> k == target),
                        "seed {seed:#x}: block {block} of {size} is split: {images:?}"
                    );
                    images.sort_unstable();
                    images.dedup();
                    assert_eq!(images.len() as u32, size, "not a permutation");
                }
            }
        }
    }

    #[test]
    fn permutation_is_a_bijection_on_low_bits() {
        // Nested and bijective: on the 2^12 values of the low 12 bits it permutes.
        for seed in [3u32, 0xffff_ffff, 0x8000_0000] {
            let mut seen = vec![false; 1 << 12];
            for x in 0..1u32 << 12 {
                seen[(laine_karras_permutation(x, seed) & 0xfff) as usize] = true;
            }
            assert!(seen.iter().all(|&s| s), "seed {seed:#x}");
        }
    }
}
