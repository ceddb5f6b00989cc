//! Integer hashing and the bits-to-float conversion shared by every sampler kind.

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

/// The 24 high bits as a float in [0, 1): exact on every IEEE device, and truncating, so the
/// leading bits (the strata of a low-discrepancy point) survive the conversion unchanged.
#[inline]
pub fn unit_float(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
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
        assert_eq!(unit_float(0x8000_0000), 0.5);
    }
}
