//! The GLSL mirror of the tone maps (shaders/include/tonemap.glsl, what the preview's resolve
//! pass shows) against lensray-core/src/film/tonemap.rs on the device, validation on
//! (tests/renderer.rs says how a machine without a device skips).
//!
//! Not bit for bit: GLSL's log2 and pow are the driver's (Vulkan allows them a few ulp, and
//! may fuse a matrix product's multiplies and adds), so each channel is held to TOLERANCE, 1/40
//! of an 8-bit step, and its sRGB byte to one step (a value on a rounding edge). Measured
//! (largest difference, 470 colours): llvmpipe neutral 1.2e-7, agx 1.9e-5; NVIDIA H200 neutral
//! 1.2e-7, agx 2.4e-5.

mod support;

use glam::Vec3;
use lensray_core::film::colour::linear_to_srgb;
use lensray_core::film::tonemap::{agx, pbr_neutral};
use lensray_vulkan::probe_tonemaps;

use support::*;

const TOLERANCE: f32 = 1e-4;

/// Greys over 20 stops (a sixth of a stop apart), colours of every hue and saturation at
/// several brightnesses, the PBR Neutral toe's edge (0.08) and its compression's start, zero,
/// and negative and huge values.
fn colours() -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    for i in 0..=120 {
        out.push([2f32.powf(i as f32 / 6.0 - 12.0); 3]);
    }
    for h in 0..12 {
        let hue = h as f32 / 12.0 * std::f32::consts::TAU;
        for saturation in [0.0, 0.3, 0.7, 1.0] {
            for brightness in [0.05, 0.18, 0.5, 1.0, 3.0, 20.0, 300.0] {
                let c = [0.0, 2.094, 4.189].map(|phase: f32| {
                    let s = 0.5 + 0.5 * (hue + phase).cos();
                    brightness * (1.0 - saturation + saturation * s)
                });
                out.push(c);
            }
        }
    }
    let below = |x: f32| f32::from_bits(x.to_bits() - 1);
    for edge in [0.08f32, 0.8, 0.76] {
        out.extend([[below(edge), 0.5, 0.9], [edge, 0.5, 0.9], [0.9, edge, 1.2]]);
    }
    out.extend([
        [0.0; 3],
        [-1.0, 0.5, 2.0],
        [1e6, 1e5, 1e4],
        [1e-12, 0.0, 1e-20],
    ]);
    out
}

fn byte(c: f32) -> i32 {
    (linear_to_srgb(c).clamp(0.0, 1.0) * 255.0 + 0.5) as i32
}

#[test]
fn tonemap_mirror_matches_rust() {
    let Some((gpu, log)) = renderer("tonemap_mirror_matches_rust") else {
        return;
    };
    let colours = colours();
    let results = probe_tonemaps(&gpu, &colours).expect("tonemap probe");
    assert_eq!(results.len(), colours.len());
    let mut differences = Vec::new();
    let mut worst = [0f32; 2];
    for (c, got) in colours.iter().zip(&results) {
        let input = Vec3::from_array(*c);
        for (k, (name, rust)) in [("pbr_neutral", pbr_neutral(input)), ("agx", agx(input))]
            .into_iter()
            .enumerate()
        {
            let gpu_value = Vec3::from_array(got[k]);
            let error = (gpu_value - rust).abs().max_element();
            worst[k] = worst[k].max(error);
            let bytes_differ = (0..3).any(|i| (byte(gpu_value[i]) - byte(rust[i])).abs() > 1);
            if error.is_nan() || error > TOLERANCE || bytes_differ {
                differences.push(format!(
                    "{name}({c:?}): GPU {gpu_value:?}, Rust {rust:?} (error {error:e})"
                ));
            }
        }
    }
    println!(
        "tonemap mirror on {}: {} colours, largest differences: neutral {:e}, agx {:e}",
        gpu.device_name(),
        colours.len(),
        worst[0],
        worst[1]
    );
    assert!(
        differences.is_empty(),
        "{} of {} differ:\n{}",
        differences.len(),
        2 * colours.len(),
        differences[..differences.len().min(20)].join("\n")
    );
    finish(gpu, log);
}
