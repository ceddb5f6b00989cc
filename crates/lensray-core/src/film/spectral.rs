//! One wavelength per camera sample, for lenses that disperse light, in a scene that stays RGB:
//! the radiance a ray brings back (linear sRGB) is weighted by a 3x3 matrix of the sample's
//! wavelength, so that the film still collects linear sRGB and the expected image through a lens
//! that does not disperse equals the RGB render exactly (a white surface stays white).
//! `shaders/include/spectral.glsl` mirrors this module function by function, bit for bit.
//!
//! # The definition
//!
//! - **Range and nodes.** 380 to 780 nm, a node every 5 nm (81 nodes, 80 intervals). The data
//!   come from colour-science 0.4.7 at the nodes: the CIE 1931 2 degree standard observer
//!   (x, y, z bar), CIE illuminant D65, and the three basis spectra of Mallett and Yuksel 2019,
//!   "Spectral Primary Decomposition for Rendering with sRGB Reflectance"
//!   (`colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019`: b_r, b_g, b_b, which sum to 1).
//! - **Upsampling.** A radiance (r, g, b) is the spectrum
//!   L(lambda) = D65(lambda) (r b_r + g b_g + b b_b)(lambda) / N, with N the integral of
//!   ybar D65 (10567.26781, the trapezoid over the nodes), so that white (1, 1, 1) has Y = 1.
//!   The decomposition is linear, and the basis' round trip is exact over the sRGB gamut.
//! - **The matrix.** At node i, T_i = M xyzbar(lambda_i) (D65(lambda_i) b(lambda_i))^T / N,
//!   M being linear sRGB from XYZ (D65 white; colour's sRGB `matrix_XYZ_to_RGB`, rows
//!   (3.2406, -1.5372, -0.4986), (-0.9689, 1.8758, 0.0415), (0.0557, -0.2040, 1.0570)). Between
//!   nodes T is linearly interpolated. Its integral R over the range (the trapezoid, exact for
//!   a piecewise-linear T) is about I: its entries differ from I's by at most 2.62e-4 (the
//!   generated table's header lists R). The table holds T' = R^-1 T, whose integral is I
//!   exactly in f64, and within 1e-6 as the f32 table it is rounded to.
//! - **Sampling density.** p(lambda) is constant over each interval; interval k has probability
//!   P_k = 0.99 m_k / sum(m) + 0.01 / 80, m_k the integral over it of the Frobenius norm of T'.
//!   The 1 % uniform share is the floor that leaves no interval at probability 0: each has at
//!   least 1.25e-4 (the least is 1.2571e-4, at the red end). The cumulative table CDF (f32,
//!   0 at the first node, 1 at the last) defines the probabilities the code uses,
//!   `P_k = CDF[k + 1] - CDF[k]`; the table stores 1 / P_k and 1 / p = 5 nm / P_k per interval,
//!   rounded to f32.
//! - **Inversion.** u in [0, 1) picks the interval k with `CDF[k] <= u < CDF[k + 1]` by a binary
//!   search of fixed length (7 steps) and `lambda = lambda_k + 5 nm (u - CDF[k]) / P_k` (the
//!   fraction clamped to [0, 1] against rounding). u is sample dimension
//!   [`DIM_WAVELENGTH`](crate::sampler::DIM_WAVELENGTH), the first of a pair of the sampler, so
//!   wavelengths are stratified like the camera's dimensions and their colour noise falls as
//!   fast.
//! - **The weight.** W(lambda) = T'(lambda) / p(lambda), a 3x3 matrix; the film gets
//!   W rgb_radiance (times the camera's weight). `E[W]` = the integral of T' = I (within 3e-8
//!   in f32). W jumps where p does, at the nodes, so a stratified estimate's error falls as
//!   1 / n there: the mean over u = (i + 0.5) / n is I within 2.0e-4 at n = 4096, 1.6e-5 at
//!   n = 65536. At a node the weight takes the interval its wavelength's position rounds into,
//!   which can differ from the one the search chose only within rounding of the node.
//!
//! The numbers are generated once by `scripts/spectral/tables.py` into lensray-interface's
//! `spectral_table.rs`, their one definition; its `constants.rs` includes that file and
//! names its tables as the shared constants `SPECTRAL_*`, which the GLSL header declares too.
//!
//! # Dispersion at little cost: the d line, checked
//!
//! One wavelength per sample makes each sample a saturated colour, and where a pixel's
//! samples see different radiance (a blurred edge, a texture, a shadow, the lens's own
//! vignetting) the colours no longer average to white: colour noise many times the luminance
//! noise. Yet a lens disperses little: at most wavelengths a ray sees what the d line's ray
//! sees. So every sample of a dispersive lens traces the d line, whose radiance L_d goes to
//! the film as it is (through the identity: no colour noise), and one sample in
//! `DISPERSION_CHECK_INVERSE` (k) also traces its wavelength lambda and adds
//! k W(lambda) (L_lambda - L_d), what its wavelength changes. Whether a sample checks (c = 1)
//! is [`checks_dispersion`] of dimension `DIM_DISPERSION_CHECK`, independent of lambda (the
//! pair's other dimension), so E(c k W (L_lambda - L_d)) = E(W L_lambda) - E(W) L_d =
//! E(W L_lambda) - L_d (E(W) = I) and the estimate L_d + c k W(lambda) (L_lambda - L_d) is
//! unbiased. The difference is 0 where the two rays see the same thing, so colour noise is
//! left only where dispersion shows: its fringes. A sample's two rays share every other
//! dimension, so their paths draw alike. The film's values are [`d_line_value`] and
//! [`checked_value`].
//!
//! # Arithmetic
//!
//! f32 only, written out so that GLSL with `precise` rounds every step the same way: only
//! `+`, `-`, `*` (correctly rounded in Vulkan, unlike `/`, hence the stored reciprocals),
//! comparisons, `min`/`clamp`, float-integer conversions of small exact values and a loop of
//! fixed length; no fused multiply-add, no libm.

use glam::{Mat3, Vec3};

use crate::interface::{
    DISPERSION_CHECK_INVERSE, SPECTRAL_CDF, SPECTRAL_INTERVALS, SPECTRAL_INV_DENSITY,
    SPECTRAL_INV_PROBABILITY, SPECTRAL_INV_STEP_NM, SPECTRAL_MAX_NM, SPECTRAL_MIN_NM,
    SPECTRAL_STEP_NM, SPECTRAL_WEIGHTS,
};

/// The shortest wavelength a sample takes, in nm.
pub const WAVELENGTH_MIN_NM: f32 = SPECTRAL_MIN_NM;
/// The longest wavelength a sample takes, in nm.
pub const WAVELENGTH_MAX_NM: f32 = SPECTRAL_MAX_NM;

/// The largest power of two below the number of intervals: the binary search's first step
/// (its steps 64, 32, ..., 1 reach any of the 80 intervals).
const SEARCH_FIRST_STEP: u32 = 64;
const _: () = assert!(SEARCH_FIRST_STEP < SPECTRAL_INTERVALS);
const _: () = assert!(2 * SEARCH_FIRST_STEP >= SPECTRAL_INTERVALS);

/// The interval k of the sampling density with `CDF[k] <= u < CDF[k + 1]` (0 for u < 0, the last
/// for u >= 1): a binary search of fixed length, the same loop on every invocation.
#[inline]
pub fn wavelength_interval(u: f32) -> u32 {
    let mut k = 0;
    let mut step = SEARCH_FIRST_STEP;
    while step > 0 {
        let next = k + step;
        if next < SPECTRAL_INTERVALS && SPECTRAL_CDF[next as usize] <= u {
            k = next;
        }
        step >>= 1;
    }
    k
}

/// The wavelength (nm) of sample value `u` in [0, 1): the inverse of the sampling density's
/// cumulative distribution, from [`WAVELENGTH_MIN_NM`] to [`WAVELENGTH_MAX_NM`].
#[inline]
pub fn sample_wavelength(u: f32) -> f32 {
    let k = wavelength_interval(u);
    let fraction = (u - SPECTRAL_CDF[k as usize]) * SPECTRAL_INV_PROBABILITY[k as usize];
    let fraction = fraction.clamp(0.0, 1.0);
    let node = k as f32 * SPECTRAL_STEP_NM + SPECTRAL_MIN_NM;
    node + SPECTRAL_STEP_NM * fraction
}

/// W(lambda) = T'(lambda) / p(lambda): the matrix that takes a ray's linear sRGB radiance to
/// what a sample of wavelength `lambda_nm` (drawn by [`sample_wavelength`]) adds to the film,
/// in linear sRGB. Its expectation over the samples is I. Wavelengths outside the range take
/// the value at its nearer end.
#[inline]
pub fn rgb_weights(lambda_nm: f32) -> Mat3 {
    let last = SPECTRAL_INTERVALS - 1;
    let x = (lambda_nm - SPECTRAL_MIN_NM) * SPECTRAL_INV_STEP_NM;
    let x = x.clamp(0.0, SPECTRAL_INTERVALS as f32);
    let k = (x as u32).min(last);
    // Exact: x and k are within 1 of each other and below 2^23.
    let t = x - k as f32;
    let s = 1.0 - t;
    let inv_density = SPECTRAL_INV_DENSITY[k as usize];
    let a = 9 * k as usize;
    let b = a + 9;
    let w: [f32; 9] = std::array::from_fn(|j| {
        (SPECTRAL_WEIGHTS[a + j] * s + SPECTRAL_WEIGHTS[b + j] * t) * inv_density
    });
    Mat3::from_cols_array(&w)
}

/// Whether a sample of a dispersive lens whose dimension `DIM_DISPERSION_CHECK` is `u` traces
/// its wavelength too: one in `DISPERSION_CHECK_INVERSE` (u k < 1, exact: k is a power of
/// two).
#[inline]
pub fn checks_dispersion(u: f32) -> bool {
    u * (DISPERSION_CHECK_INVERSE as f32) < 1.0
}

/// What a dispersive lens's sample adds to the film from its d line's radiance `l_d`: `l_d`,
/// less k W(lambda) `l_d` where the sample checks the d line at `checked` = lambda (nm).
#[inline]
pub fn d_line_value(checked: Option<f32>, l_d: Vec3) -> Vec3 {
    match checked {
        Some(lambda) => l_d - rgb_weights(lambda) * l_d * (DISPERSION_CHECK_INVERSE as f32),
        None => l_d,
    }
}

/// What a checking sample adds to the film from its radiance `l` at its wavelength
/// `lambda_nm`: k W(lambda) `l`.
#[inline]
pub fn checked_value(lambda_nm: f32, l: Vec3) -> Vec3 {
    rgb_weights(lambda_nm) * l * (DISPERSION_CHECK_INVERSE as f32)
}

const _: () = assert!(DISPERSION_CHECK_INVERSE.is_power_of_two());

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3, Vec3};

    use super::*;
    use crate::interface::SPECTRAL_NODES;

    /// The probability of interval k as the code sees it (exact in f64).
    fn probability(k: usize) -> f64 {
        f64::from(SPECTRAL_CDF[k + 1]) - f64::from(SPECTRAL_CDF[k])
    }

    fn node_matrix(i: usize) -> DMat3 {
        let m: [f64; 9] = std::array::from_fn(|j| f64::from(SPECTRAL_WEIGHTS[9 * i + j]));
        DMat3::from_cols_array(&m)
    }

    /// The mean of W over u = (i + 0.5) / n, in f64.
    fn mean_weight(n: u32) -> DMat3 {
        let mut sum = DMat3::ZERO;
        for i in 0..n {
            let u = (i as f32 + 0.5) / n as f32;
            sum += rgb_weights(sample_wavelength(u)).as_dmat3();
        }
        sum * (1.0 / f64::from(n))
    }

    fn max_deviation(a: DMat3, b: DMat3) -> f64 {
        (a - b)
            .to_cols_array()
            .iter()
            .fold(0.0, |m, v| f64::max(m, v.abs()))
    }

    #[test]
    fn the_tables_integrate_to_the_identity() {
        let nodes = SPECTRAL_NODES as usize;
        let mut integral = DMat3::ZERO;
        for i in 0..nodes {
            let width = if i == 0 || i == nodes - 1 { 2.5 } else { 5.0 };
            integral += node_matrix(i) * width;
        }
        let deviation = max_deviation(integral, DMat3::IDENTITY);
        println!("trapezoid of T' (f32 table) = {integral:?}, max |. - I| = {deviation:.3e}");
        assert!(deviation < 1e-6, "the integral of T' is {integral:?}");
        assert_eq!(SPECTRAL_CDF[0], 0.0);
        assert_eq!(SPECTRAL_CDF[nodes - 1], 1.0);
        for k in 0..nodes - 1 {
            let p = probability(k);
            assert!(p >= 1.25e-4, "interval {k} has probability {p}");
            let inv = f64::from(SPECTRAL_INV_PROBABILITY[k]);
            let inv_density = f64::from(SPECTRAL_INV_DENSITY[k]);
            assert!(
                (inv * p - 1.0).abs() < 1e-6,
                "interval {k}: 1/P = {inv}, P = {p}"
            );
            assert!((inv_density * p / 5.0 - 1.0).abs() < 1e-6, "interval {k}");
        }
    }

    /// The exact expectation of W under the sampling: W is linear in u over each interval, so
    /// its mean there is its value at the interval's middle u.
    fn expected_weight() -> DMat3 {
        let mut sum = DMat3::ZERO;
        for k in 0..SPECTRAL_INTERVALS as usize {
            let middle = 0.5 * (SPECTRAL_CDF[k] + SPECTRAL_CDF[k + 1]);
            sum += rgb_weights(sample_wavelength(middle)).as_dmat3() * probability(k);
        }
        sum
    }

    #[test]
    fn the_expected_weight_is_the_identity() {
        let exact = expected_weight();
        let deviation = max_deviation(exact, DMat3::IDENTITY);
        println!("E[W] = {exact:?}, max |. - I| = {deviation:.3e}");
        assert!(deviation < 1e-6, "E[W] = {exact:?}");
        // Stratified u = (i + 0.5) / n: W jumps where p does, at the interval ends, and each
        // jump inside a stratum costs up to (the jump) / n, so the error falls as 1 / n:
        // 2.0e-4 at n = 4096, 1.6e-5 at n = 65536.
        for (n, tolerance) in [(4096, 5e-4), (65536, 5e-5)] {
            let mean = mean_weight(n);
            let deviation = max_deviation(mean, DMat3::IDENTITY);
            println!("mean W over {n} stratified u: max |. - I| = {deviation:.3e}");
            assert!(deviation < tolerance, "n = {n}: mean W = {mean:?}");
        }
    }

    #[test]
    fn white_stays_white_and_each_primary_round_trips() {
        let colours = [
            Vec3::ONE,
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            Vec3::new(0.2, 0.5, 0.9),
        ];
        for colour in colours {
            let exact = expected_weight() * colour.as_dvec3();
            let n = 4096;
            let mut sum = DVec3::ZERO;
            for i in 0..n {
                let u = (i as f32 + 0.5) / n as f32;
                sum += (rgb_weights(sample_wavelength(u)) * colour).as_dvec3();
            }
            let stratified = sum / f64::from(n);
            let error = (exact - colour.as_dvec3()).abs().max_element();
            let stratified_error = (stratified - colour.as_dvec3()).abs().max_element();
            println!(
                "{colour:?} -> {exact:?} (error {error:.3e}); over {n} stratified u {stratified:?} \
                 (error {stratified_error:.3e})"
            );
            assert!(error < 1e-6, "{colour:?} comes back as {exact:?}");
            assert!(
                stratified_error < 5e-4,
                "{colour:?}: {stratified:?} over {n} u"
            );
        }
    }

    #[test]
    fn sample_wavelength_is_monotone_and_in_range() {
        let below = |x: f32| f32::from_bits(x.to_bits() - 1);
        let mut us: Vec<f32> = (0..1 << 18).map(|i| i as f32 / (1 << 18) as f32).collect();
        for &c in &SPECTRAL_CDF[1..SPECTRAL_NODES as usize - 1] {
            us.extend([below(c), c]);
        }
        us.push(below(1.0));
        us.sort_by(f32::total_cmp);
        assert_eq!(sample_wavelength(0.0), WAVELENGTH_MIN_NM);
        let mut previous = WAVELENGTH_MIN_NM;
        for &u in &us {
            let lambda = sample_wavelength(u);
            assert!(
                (WAVELENGTH_MIN_NM..=WAVELENGTH_MAX_NM).contains(&lambda),
                "u = {u:?} gives {lambda} nm"
            );
            assert!(
                lambda >= previous,
                "u = {u:?} gives {lambda} nm < {previous} nm"
            );
            previous = lambda;
        }
        // The last interval's probability is about 1.26e-4: the largest u below 1 falls
        // 2^-24 / 1.26e-4 of the interval, 2.4e-3 nm, short of its end.
        let last = sample_wavelength(below(1.0));
        println!("u = 1 - 2^-24 gives {last} nm");
        assert!(last > WAVELENGTH_MAX_NM - 5e-3, "{last}");
    }

    #[test]
    fn wavelengths_follow_the_density() {
        // Stratified u: 1 nm bins, each holding n P_k / 5 of the samples up to the one sample
        // at either end of the bin that rounding can move.
        let n: u32 = 1 << 20;
        let bins = (WAVELENGTH_MAX_NM - WAVELENGTH_MIN_NM) as usize;
        let mut counts = vec![0u32; bins];
        for i in 0..n {
            let lambda = sample_wavelength((i as f32 + 0.5) / n as f32);
            let bin = ((lambda - WAVELENGTH_MIN_NM) as usize).min(bins - 1);
            counts[bin] += 1;
        }
        let mut worst = (0.0f64, 0);
        for (bin, &count) in counts.iter().enumerate() {
            let expected = f64::from(n) * probability(bin / 5) / 5.0;
            let difference = (f64::from(count) - expected).abs();
            if difference > worst.0 {
                worst = (difference, bin);
            }
        }
        let (difference, bin) = worst;
        println!(
            "worst 1 nm bin: {} nm, {} samples, {difference:.2} from n p",
            bin + 380,
            counts[bin]
        );
        assert!(
            difference <= 3.0,
            "bin {} nm is off by {difference}",
            bin + 380
        );
    }

    #[test]
    fn weights_are_finite_across_the_range() {
        let mut lambdas: Vec<f32> = (0..=40_000)
            .map(|i| WAVELENGTH_MIN_NM + i as f32 * 0.01)
            .collect();
        for i in 0..SPECTRAL_NODES {
            let node = WAVELENGTH_MIN_NM + 5.0 * i as f32;
            let bits = node.to_bits();
            lambdas.extend([node, f32::from_bits(bits - 1), f32::from_bits(bits + 1)]);
        }
        let mut largest = 0.0f32;
        for lambda in lambdas {
            let w = rgb_weights(lambda);
            assert!(w.is_finite(), "W({lambda} nm) = {w:?}");
            largest = w
                .to_cols_array()
                .iter()
                .fold(largest, |m, v| m.max(v.abs()));
        }
        println!("largest |W| entry in the range: {largest}");
        // Continuous at the nodes (T' is; p jumps, so only per interval): at a node's two
        // sides the weight times the density is T' at the node.
        for i in 1..SPECTRAL_NODES - 1 {
            let node = WAVELENGTH_MIN_NM + 5.0 * i as f32;
            let at =
                rgb_weights(node).as_dmat3() * (1.0 / f64::from(SPECTRAL_INV_DENSITY[i as usize]));
            let deviation = max_deviation(at, node_matrix(i as usize));
            assert!(deviation < 1e-8, "node {node} nm: {at:?}");
        }
    }

    #[test]
    fn the_glsl_header_holds_the_same_tables() {
        let header = crate::interface::glsl_header();
        let line = header
            .lines()
            .find(|l| l.starts_with("const float SPECTRAL_WEIGHTS[729] = float[729]("))
            .expect("SPECTRAL_WEIGHTS in the header");
        let inner = &line[line.find("](").unwrap() + 2..line.rfind(");").unwrap()];
        let values: Vec<f32> = inner
            .split(", ")
            .map(|t| t.parse::<f64>().unwrap() as f32)
            .collect();
        assert_eq!(values.len(), 729);
        for (j, (v, w)) in values.iter().zip(SPECTRAL_WEIGHTS).enumerate() {
            assert_eq!(
                v.to_bits(),
                w.to_bits(),
                "entry {j}: GLSL reads {v:?}, Rust has {w:?}"
            );
        }
        assert!(header.contains("const float SPECTRAL_CDF[81] = float[81](0.0, "));
        assert!(header.contains("const uint DIM_WAVELENGTH = 6u;"));
    }
}
