//! Adaptive sampling on the device (`GpuRenderer::add_adaptive`, docs/adaptive.md), validation
//! on: the same rounds as the CPU reference (film/adaptive.rs decides both), so the same
//! sample counts and the same image wherever the two agree on which pixels go on; each pixel
//! holds, bit for bit, what a uniform render at its count holds; the same arguments give the
//! same image, however the calls are split into dispatches.

mod support;

use lensray_core::camera::LensParams;
use lensray_core::film::{Accumulation, Image, Sums};
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::settings::{Shading, Shot};
use lensray_vulkan::GpuRenderer;

use support::*;

/// Threshold and cap of the tests: rounds end at 32 (the minimum at 0.05), 48 and 64.
const THRESHOLD: f32 = 0.05;
const SPP: u32 = 64;

fn shot(shading: Shading, spp: u32, threshold: Option<f32>) -> Shot {
    let lens = LensParams::ThinLens {
        aperture_radius: 0.12,
        focus_distance: 5.0,
    };
    Shot {
        camera: camera(false, lens, 48, 36),
        render: lensray_core::settings::RenderSettings {
            noise_threshold: threshold,
            ..settings(shading, spp)
        },
    }
}

/// The device's sums of an adaptive render of `shot`.
fn gpu_adaptive(gpu: &mut GpuRenderer, shot: &Shot) -> Sums {
    let mut accumulation = Accumulation::new(shot.camera.width, shot.camera.height);
    let mut last = (0, 0);
    gpu.add_adaptive(shot, &mut accumulation, &mut |done, total| {
        last = (done, total)
    })
    .expect("GPU adaptive render");
    assert_eq!(
        last,
        (u64::from(SPP), u64::from(SPP)),
        "progress ends at spp"
    );
    accumulation.host().expect("read back").clone()
}

/// How many pixels' counts differ, and the counts each holds.
fn count_map(sums: &Sums) -> Vec<u32> {
    sums.pixels.iter().map(|p| p[3] as u32).collect()
}

fn gpu_adaptive_matches_cpu(shading: Shading) {
    let name = format!("gpu-adaptive-vs-cpu-{shading:?}").to_lowercase();
    let Some((mut gpu, log)) = renderer(&name) else {
        return;
    };
    let scene = test_scene();
    gpu.load_scene(&scene).expect("load scene");
    let shot = shot(shading, SPP, Some(THRESHOLD));
    let gpu_sums = gpu_adaptive(&mut gpu, &shot);
    let mut cpu_sums = Sums::new(shot.camera.width, shot.camera.height);
    let (_, report) =
        CpuRenderer::new(&scene).render_adaptive(&shot, THRESHOLD, &mut cpu_sums, &mut |_, _| {});
    let (gpu_counts, cpu_counts) = (count_map(&gpu_sums), count_map(&cpu_sums));
    let differing = gpu_counts
        .iter()
        .zip(&cpu_counts)
        .filter(|(a, b)| a != b)
        .count();
    let pixels = gpu_counts.len();
    let gpu_samples: u64 = gpu_counts.iter().map(|&n| u64::from(n)).sum();
    // The render must be adaptive for the comparison to mean anything: some pixels rest.
    assert!(
        gpu_samples < u64::from(SPP) * pixels as u64 && gpu_counts.contains(&SPP),
        "{name}: {gpu_samples} samples over {pixels} pixels"
    );
    // A pixel whose error lies within float noise of the threshold may go on on one device and
    // rest on the other (and its neighbours with it): at most 2% of the pixels.
    println!(
        "{name}: {differing} of {pixels} pixels differ in sample count; samples GPU {gpu_samples}, CPU {}",
        report.samples
    );
    assert!(
        differing * 50 <= pixels,
        "{name}: {differing} of {pixels} pixels differ in sample count"
    );
    // Where the counts agree, the usual GPU == CPU bounds (tests/renderer/renders.rs).
    let agreeing = |sums: &Sums| Image {
        pixels: sums
            .image()
            .pixels
            .iter()
            .zip(gpu_counts.iter().zip(&cpu_counts))
            .map(|(&v, (a, b))| if a == b { v } else { glam::Vec3::ZERO })
            .collect(),
        ..sums.image()
    };
    let diff = compare(&agreeing(&gpu_sums), &agreeing(&cpu_sums), 1.0 / 255.0);
    let whole = compare(&gpu_sums.image(), &cpu_sums.image(), 1.0 / 255.0);
    println!("{name}: where counts agree {diff:?}; whole image {whole:?}");
    if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
        let files = write_comparison(&gpu_sums.image(), &cpu_sums.image(), &name);
        panic!("{name}: GPU and CPU differ: {diff:?}; wrote {files}");
    }
    finish(gpu, log);
}

#[test]
fn gpu_adaptive_matches_cpu_unlit() {
    gpu_adaptive_matches_cpu(Shading::Unlit);
}

#[test]
fn gpu_adaptive_matches_cpu_lit() {
    gpu_adaptive_matches_cpu(Shading::Lit);
}

/// Each pixel that stopped at n samples holds what the uniform render at n spp holds there, bit
/// for bit: its samples are its indices 0..n, added in order. The same arguments give the same
/// sums again, with the calls split into one-sample dispatches over bands of rows too.
#[test]
fn gpu_adaptive_is_the_uniform_render_at_each_count_and_deterministic() {
    let name = "gpu_adaptive_is_the_uniform_render_at_each_count_and_deterministic";
    let Some((mut gpu, log)) = renderer(name) else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let adaptive_shot = shot(Shading::Lit, SPP, Some(THRESHOLD));
    let sums = gpu_adaptive(&mut gpu, &adaptive_shot);
    let counts = count_map(&sums);
    let mut checked = 0;
    for spp in [32, 48, 64] {
        let uniform = gpu
            .render(&shot(Shading::Lit, spp, None), &mut |_, _| {})
            .expect("uniform render");
        let image = sums.image();
        for (i, &n) in counts.iter().enumerate().filter(|(_, &n)| n == spp) {
            assert_eq!(
                image.pixels[i], uniform.pixels[i],
                "pixel {i} ({n} samples) differs from the uniform render at {spp} spp"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, counts.len(), "every count is a round's end");
    let again = gpu_adaptive(&mut gpu, &adaptive_shot);
    assert_eq!(sums, again, "the same arguments give the same sums");
    gpu.set_samples_per_dispatch(48 * 36);
    gpu.set_max_band_pixels(48 * 10);
    let split = gpu_adaptive(&mut gpu, &adaptive_shot);
    assert_eq!(sums, split, "split dispatches give the same sums");
    let image = gpu.render(&adaptive_shot, &mut |_, _| {}).expect("render");
    assert_eq!(image, sums.image(), "render samples adaptively too");
    finish(gpu, log);
}
