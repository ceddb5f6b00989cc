//! The GLSL mirror of the spectral weighting (shaders/include/spectral.glsl) against
//! lensray-core/src/film/spectral.rs on the device, bit for bit, validation on (tests/renderer.rs
//! says how a machine without a device skips).

mod support;

use lensray_core::film::spectral::{
    rgb_weights, sample_wavelength, wavelength_interval, WAVELENGTH_MAX_NM, WAVELENGTH_MIN_NM,
};
use lensray_core::interface::SPECTRAL_CDF;
use lensray_vulkan::probe_spectral;

use support::*;

/// Sample values and wavelengths where rounding is likeliest to differ: a stratified grid, each
/// entry of the cumulative table and the float below it, the ends; each wavelength node, the
/// floats on either side of it, a fine sweep and values outside the range.
fn queries() -> Vec<[f32; 2]> {
    let below = |x: f32| f32::from_bits(x.to_bits() - 1);
    let above = |x: f32| f32::from_bits(x.to_bits() + 1);
    let mut us: Vec<f32> = (0..4096).map(|i| (i as f32 + 0.5) / 4096.0).collect();
    for &c in &SPECTRAL_CDF[1..SPECTRAL_CDF.len() - 1] {
        us.extend([below(c), c, above(c)]);
    }
    us.extend([0.0, f32::MIN_POSITIVE, below(1.0)]);
    let mut lambdas: Vec<f32> = Vec::new();
    for i in 0..=80 {
        let node = WAVELENGTH_MIN_NM + 5.0 * i as f32;
        lambdas.extend([below(node), node, above(node)]);
    }
    lambdas.extend([0.0, 379.0, 781.0, 1e4, -5.0]);
    let span = WAVELENGTH_MAX_NM - WAVELENGTH_MIN_NM;
    while lambdas.len() < us.len() {
        let i = lambdas.len() as f32;
        lambdas.push(WAVELENGTH_MIN_NM + (i * 0.618_034 * span) % span);
    }
    us.iter()
        .zip(lambdas.iter().cycle())
        .map(|(&u, &l)| [u, l])
        .collect()
}

fn bits(m: [f32; 9]) -> [u32; 9] {
    m.map(f32::to_bits)
}

#[test]
fn spectral_mirror_matches_rust_bit_for_bit() {
    let Some((gpu, log)) = renderer("spectral_mirror_matches_rust_bit_for_bit") else {
        return;
    };
    let queries = queries();
    let results = probe_spectral(&gpu, &queries).expect("spectral probe");
    assert_eq!(results.len(), queries.len());
    let mut differences = Vec::new();
    for (&[u, lambda], got) in queries.iter().zip(&results) {
        let wavelength = sample_wavelength(u);
        let interval = wavelength_interval(u);
        let sampled = rgb_weights(wavelength).to_cols_array();
        let given = rgb_weights(lambda).to_cols_array();
        if got.wavelength.to_bits() != wavelength.to_bits() || got.interval != interval {
            differences.push(format!(
                "u = {u:?}: GPU {} nm (interval {}), Rust {wavelength} nm (interval {interval})",
                got.wavelength, got.interval
            ));
        }
        if bits(got.sampled_weights) != bits(sampled) {
            differences.push(format!(
                "W({wavelength:?} nm): GPU {:?}, Rust {sampled:?}",
                got.sampled_weights
            ));
        }
        if bits(got.given_weights) != bits(given) {
            differences.push(format!(
                "W({lambda:?} nm): GPU {:?}, Rust {given:?}",
                got.given_weights
            ));
        }
    }
    println!(
        "spectral mirror on {}: {} queries, {} differences",
        gpu.device_name(),
        queries.len(),
        differences.len()
    );
    assert!(
        differences.is_empty(),
        "{} of {} queries differ:\n{}",
        differences.len(),
        queries.len(),
        differences[..differences.len().min(20)].join("\n")
    );
    finish(gpu, log);
}
