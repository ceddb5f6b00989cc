//! The deterministic sampler shared by every path: counter-based, so any sample of any pixel can
//! be computed on its own, in any order, on any thread or GPU invocation. `shaders/sampler.glsl`
//! mirrors it function by function with 32-bit integer arithmetic only, so the GPU reproduces the
//! CPU's random numbers bit for bit.

use glam::{UVec2, Vec2};

/// Sample dimensions used by the camera. Later consumers take dimensions from `FIRST_FREE` on.
pub const DIM_FILM_X: u32 = 0;
pub const DIM_FILM_Y: u32 = 1;
pub const DIM_LENS_X: u32 = 2;
pub const DIM_LENS_Y: u32 = 3;
pub const DIM_FIRST_FREE: u32 = 4;

/// An integer hash with good avalanche ("lowbias32", C. Wellons' hash-prospector).
#[inline]
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The key of one (seed, pixel, sample) triple; dimensions are drawn from it with `sample_1d`.
#[inline]
pub fn sample_key(seed: u32, pixel_index: u32, sample_index: u32) -> u32 {
    hash_u32(hash_u32(hash_u32(seed) ^ pixel_index) ^ sample_index)
}

/// The 24 high bits of the hash as a float in [0, 1): exact on every IEEE device.
#[inline]
pub fn unit_float(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Dimension `dim` of the sample with key `key`, uniform in [0, 1).
#[inline]
pub fn sample_1d(key: u32, dim: u32) -> f32 {
    unit_float(hash_u32(key ^ dim.wrapping_mul(0x9e37_79b9)))
}

/// What the camera needs of one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// Raster position (column + u, row + v): uniform over the pixel (box filter).
    pub film: Vec2,
    /// Uniform in [0, 1)^2, mapped to the aperture disk by the lens.
    pub lens: Vec2,
}

/// Sample `sample_index` of pixel (column, row) of an image `width` pixels wide.
#[inline]
pub fn camera_sample(seed: u32, pixel: UVec2, width: u32, sample_index: u32) -> CameraSample {
    let key = sample_key(seed, pixel.y * width + pixel.x, sample_index);
    CameraSample {
        film: Vec2::new(
            pixel.x as f32 + sample_1d(key, DIM_FILM_X),
            pixel.y as f32 + sample_1d(key, DIM_FILM_Y),
        ),
        lens: Vec2::new(sample_1d(key, DIM_LENS_X), sample_1d(key, DIM_LENS_Y)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_matches_known_values() {
        // Fixed points of the spec: the GLSL mirror is tested against the same numbers on the GPU.
        // Values computed independently (Python, arbitrary-precision integers masked to 32 bits).
        assert_eq!(hash_u32(0), 0);
        assert_eq!(hash_u32(1), 0x6889_90c0);
        assert_eq!(hash_u32(12345), 0x912e_fcf7);
        assert_eq!(hash_u32(0xdead_beef), 0xe628_c683);
    }

    #[test]
    fn unit_float_range() {
        assert_eq!(unit_float(0), 0.0);
        assert!(unit_float(u32::MAX) < 1.0);
    }

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
    fn film_sample_stays_in_its_pixel() {
        for s in 0..256 {
            let c = camera_sample(1, UVec2::new(5, 9), 16, s);
            assert!(c.film.x >= 5.0 && c.film.x < 6.0 && c.film.y >= 9.0 && c.film.y < 10.0);
        }
    }
}
