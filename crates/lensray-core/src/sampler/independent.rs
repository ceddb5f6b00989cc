//! The independent sampler: every dimension of every sample is its own hash (white noise, error
//! falling as N^-1/2). Kept for comparisons; bit-identical to lensray's original sampler.

use super::hash::{hash_u32, unit_float};
use super::{pixel_key, DIM_FILM_X, DIM_FILM_Y, DIM_LENS_X, DIM_LENS_Y};

/// The key of one (seed, pixel, sample) triple; dimensions are drawn from it with `sample_1d`.
#[inline]
pub fn sample_key(seed: u32, pixel_index: u32, sample_index: u32) -> u32 {
    hash_u32(pixel_key(seed, pixel_index) ^ sample_index)
}

/// Dimension `dim` of the sample with key `key`, uniform in [0, 1).
#[inline]
pub fn sample_1d(key: u32, dim: u32) -> f32 {
    unit_float(hash_u32(key ^ dim.wrapping_mul(0x9e37_79b9)))
}

/// Film offset (x, y) and lens position (x, y) of sample `sample_index` of the pixel whose
/// [`pixel_key`] is `key`: the camera's four dimensions, each uniform in [0, 1).
#[inline]
pub fn independent_sample(key: u32, sample_index: u32) -> [f32; 4] {
    let sample = hash_u32(key ^ sample_index);
    [
        sample_1d(sample, DIM_FILM_X),
        sample_1d(sample, DIM_FILM_Y),
        sample_1d(sample, DIM_LENS_X),
        sample_1d(sample, DIM_LENS_Y),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_uniform() {
        // Mean and variance of 64k draws against 1/2 and 1/12 (4 standard errors).
        let n = 65_536u32;
        let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
        for i in 0..n {
            let u = sample_1d(sample_key(7, i, 3), DIM_LENS_X) as f64;
            sum += u;
            sum_sq += u * u;
        }
        let mean = sum / n as f64;
        let var = sum_sq / n as f64 - mean * mean;
        let se = (1.0f64 / 12.0 / n as f64).sqrt();
        assert!((mean - 0.5).abs() < 4.0 * se, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 0.002, "variance {var}");
    }

    #[test]
    fn camera_dimensions_are_the_keyed_hashes() {
        // The original definition: sample_1d(sample_key(seed, pixel, s), dim) for dims 0..4.
        for s in 0..100 {
            let key = pixel_key(5, 1234);
            let dims = independent_sample(key, s);
            for (dim, &u) in dims.iter().enumerate() {
                assert_eq!(u, sample_1d(sample_key(5, 1234, s), dim as u32));
            }
        }
    }
}
