//! The default sampler: Owen-scrambled Sobol' points whose film and lens pairs are each a
//! (0, 2)-sequence and which are also stratified jointly in 4-D. The film pair is the first two
//! Sobol' dimensions at the sample index; the lens pair is the same two dimensions at
//! [`lens_index`] of it, a fixed linear permutation of every aligned block of indices chosen for
//! the joint stratification (film x against lens x, and so on; see `quality.rs`). Each of the
//! four dimensions is Owen-scrambled per pixel (Burley 2020), so pixels are independent and every
//! 2^k samples of a pixel are stratified in film and in lens alike. docs/sampler.md has the
//! measurements that chose this over padded, randomly shuffled pairs and over Joe and Kuo's 4-D
//! Sobol' points.
//!
//! Later dimensions (the environment, the wavelength and the BRDF pairs of a path's vertices,
//! `vertex_dimensions`) come in pairs padded the usual way: the same (0, 2)
//! pair at a per-pixel randomly shuffled index, independent of the camera's.

use super::hash::{hash_u32, unit_float};
use super::owen::{owen_scramble_reversed, shuffle_index};
use super::sobol::{lens_index, sobol_reversed};
use super::{DIM_FILM_X, DIM_FILM_Y, DIM_LENS_X, DIM_LENS_Y};

/// The Owen-scrambling seed of dimension `dim` of the pixel with key `pixel_key`.
#[inline]
pub fn scramble_seed(pixel_key: u32, dim: u32) -> u32 {
    hash_u32(pixel_key ^ dim.wrapping_mul(0x9e37_79b9))
}

/// The seed of the sample-order shuffle of 2-D pair `pair` (dimensions 2 pair, 2 pair + 1),
/// for the pairs after the camera's.
#[inline]
pub fn shuffle_seed(pixel_key: u32, pair: u32) -> u32 {
    hash_u32(scramble_seed(pixel_key, 2 * pair))
}

/// Dimension `dim` of sample `sample_index` of the pixel with key `pixel_key`, in [0, 1), on
/// its own.
#[inline]
pub fn sobol_1d(pixel_key: u32, sample_index: u32, dim: u32) -> f32 {
    let pair = dim / 2;
    let index = match pair {
        0 => sample_index,
        1 => lens_index(sample_index),
        _ => shuffle_index(sample_index, shuffle_seed(pixel_key, pair)),
    };
    unit_float(owen_scramble_reversed(
        sobol_reversed(dim % 2, index),
        scramble_seed(pixel_key, dim),
    ))
}

/// The scrambling seeds of the camera's four dimensions in one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SobolPixel {
    pub film_x: u32,
    pub film_y: u32,
    pub lens_x: u32,
    pub lens_y: u32,
}

#[inline]
pub fn sobol_pixel(pixel_key: u32) -> SobolPixel {
    SobolPixel {
        film_x: scramble_seed(pixel_key, DIM_FILM_X),
        film_y: scramble_seed(pixel_key, DIM_FILM_Y),
        lens_x: scramble_seed(pixel_key, DIM_LENS_X),
        lens_y: scramble_seed(pixel_key, DIM_LENS_Y),
    }
}

/// Film offset (x, y) and lens position (x, y) of sample `sample_index`: `sobol_1d` of the
/// camera's four dimensions.
#[inline]
pub fn sobol_sample(pixel: &SobolPixel, sample_index: u32) -> [f32; 4] {
    let lens = lens_index(sample_index);
    [
        unit_float(owen_scramble_reversed(
            sobol_reversed(0, sample_index),
            pixel.film_x,
        )),
        unit_float(owen_scramble_reversed(
            sobol_reversed(1, sample_index),
            pixel.film_y,
        )),
        unit_float(owen_scramble_reversed(
            sobol_reversed(0, lens),
            pixel.lens_x,
        )),
        unit_float(owen_scramble_reversed(
            sobol_reversed(1, lens),
            pixel.lens_y,
        )),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::pixel_key;

    #[test]
    fn camera_dimensions_equal_the_dimensions_on_their_own() {
        for (seed, pixel_index) in [(0u32, 0u32), (7, 12345), (0xffff_ffff, 999)] {
            let key = pixel_key(seed, pixel_index);
            let pixel = sobol_pixel(key);
            for s in (0..300).chain([1 << 20, u32::MAX]) {
                let dims = sobol_sample(&pixel, s);
                for (dim, &u) in dims.iter().enumerate() {
                    assert_eq!(u.to_bits(), sobol_1d(key, s, dim as u32).to_bits());
                }
            }
        }
    }

    /// The cell of (x, y) in the grid of 2^a x 2^(k - a) elementary intervals.
    fn cell(x: f32, y: f32, k: u32, a: u32) -> usize {
        let column = (x * (1u32 << a) as f32) as usize;
        let row = (y * (1u32 << (k - a)) as f32) as usize;
        (column << (k - a)) | row
    }

    /// For 2^k samples of one pixel from `first` (a multiple of 2^k), dimensions `dims`: the
    /// first grid of 2^a x 2^(k-a) intervals that lacks a point, with the number of empty ones.
    fn unstratified(key: u32, first: u32, k: u32, dims: [u32; 2]) -> Option<(u32, usize)> {
        let points: Vec<[f32; 2]> = (first..first + (1 << k))
            .map(|s| dims.map(|d| sobol_1d(key, s, d)))
            .collect();
        (0..=k).find_map(|a| {
            let mut seen = vec![false; 1 << k];
            for p in &points {
                seen[cell(p[0], p[1], k, a)] = true;
            }
            let empty = seen.iter().filter(|&&s| !s).count();
            (empty > 0).then_some((a, empty))
        })
    }

    #[test]
    fn every_pair_is_stratified_in_every_power_of_two_block() {
        // Film, lens, and a later (padded) pair.
        for (seed, pixel_index) in [(0u32, 0u32), (1, 5), (42, 640 * 479 + 639), (9, 77)] {
            let key = pixel_key(seed, pixel_index);
            for k in 0..=10 {
                for block in [0u32, 1, 3] {
                    for (name, dims) in [("film", [0, 1]), ("lens", [2, 3]), ("pair 2", [4, 5])] {
                        if let Some((a, empty)) = unstratified(key, block << k, k, dims) {
                            panic!(
                                "seed {seed} pixel {pixel_index}: {name} samples {}..{} leave \
                                 {empty} of the {} intervals of 2^-{a} x 2^-{} empty",
                                block << k,
                                (block + 1) << k,
                                1 << k,
                                k - a
                            );
                        }
                    }
                }
            }
        }
    }
}
