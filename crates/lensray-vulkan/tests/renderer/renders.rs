//! Traced renders: the GPU against the CPU reference, dispatches split in samples and rows,
//! the pipelines a render makes, and the rays it counts.

use glam::Vec3;
use lensray_core::camera::LensParams;
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::sampler::SamplerKind;
use lensray_core::settings::{Shading, Shot};
use lensray_vulkan::GpuOptions;

use crate::support::*;

fn gpu_matches_cpu(orthographic: bool, shading: Shading) {
    let name = format!(
        "gpu-vs-cpu-{}-{:?}",
        if orthographic { "ortho" } else { "persp" },
        shading
    )
    .to_lowercase();
    let Some((mut gpu, log)) = renderer(&name) else {
        return;
    };
    let scene = test_scene();
    gpu.load_scene(&scene).expect("load scene");
    // Visible depth of field: focused on the sphere, aperture large enough to blur the rest.
    let lens = LensParams::ThinLens {
        aperture_radius: if orthographic { 0.08 } else { 0.12 },
        focus_distance: 5.0,
    };
    let shot = Shot {
        camera: camera(orthographic, lens.clone(), 96, 72),
        render: settings(shading, 8),
    };
    let mut last = (0, 0);
    let image = gpu
        .render(&shot, &mut |done, total| last = (done, total))
        .expect("GPU render");
    assert_eq!(last.0, last.1, "progress must end at the total");
    let (reference, _) = CpuRenderer::new(&scene).render(&shot, &mut |_, _| {});
    let diff = compare(&image, &reference, 1.0 / 255.0);
    println!("{name}: {diff:?}");
    if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
        let files = write_comparison(&image, &reference, &name);
        panic!("{name}: GPU and CPU differ: {diff:?}; wrote {files}");
    }
    finish(gpu, log);
}

#[test]
fn gpu_matches_cpu_perspective_unlit() {
    gpu_matches_cpu(false, Shading::Unlit);
}

#[test]
fn gpu_matches_cpu_perspective_lit() {
    gpu_matches_cpu(false, Shading::Lit);
}

#[test]
fn gpu_matches_cpu_orthographic_unlit() {
    gpu_matches_cpu(true, Shading::Unlit);
}

#[test]
fn gpu_matches_cpu_orthographic_lit() {
    gpu_matches_cpu(true, Shading::Lit);
}

#[test]
fn split_dispatches_accumulate_identically() {
    let Some((mut gpu, log)) = renderer("split_dispatches_accumulate_identically") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let shot = Shot {
        camera: camera(
            false,
            LensParams::ThinLens {
                aperture_radius: 0.1,
                focus_distance: 4.0,
            },
            64,
            48,
        ),
        render: settings(Shading::Lit, 6),
    };
    let whole = gpu.render(&shot, &mut |_, _| {}).expect("render");
    // Bands of rows and one sample at a time: 64 * 48 * 6 / 1000 -> dozens of dispatches,
    // and sums held for 20 rows at a time (3 bands, the last one shorter). They are recorded
    // 8 to a submission and nothing waits between them: one wait, at the end.
    gpu.set_samples_per_dispatch(1000);
    gpu.set_max_band_pixels(64 * 20);
    let mut calls = Vec::new();
    let (before, dispatches_before) = (gpu.counters(), gpu.timings().dispatches);
    let split = gpu
        .render(&shot, &mut |done, total| calls.push((done, total)))
        .expect("render");
    let counted = gpu.counters().since(&before);
    let dispatches = gpu.timings().dispatches - dispatches_before;
    assert!(
        dispatches > 20,
        "expected many dispatches, got {dispatches}"
    );
    assert_eq!(counted.submits, dispatches.div_ceil(8), "{counted:?}");
    assert_eq!(counted.cpu_waits, 1, "{counted:?}");
    // The image's sums, the ray counter and two timestamps per dispatch.
    assert_eq!(
        counted.readback_bytes,
        64 * 48 * 16 + 24 + 16 * dispatches,
        "{counted:?}"
    );
    assert!(calls.windows(2).all(|w| w[0].0 <= w[1].0));
    assert_eq!(calls.last().copied(), Some((64 * 48 * 6, 64 * 48 * 6)));
    assert_eq!(
        whole, split,
        "the split must add the same samples in the same order"
    );
    let t = gpu.timings();
    assert!(t.rays_traced > 0 && t.dispatches > 20, "{t:?}");
    // Compacted BLASes exist and are no larger than the builds.
    assert!(
        t.blas_compacted_bytes > 0 && t.blas_compacted_bytes <= t.blas_bytes,
        "{t:?}"
    );
    println!("timings: {t:?}");
    finish(gpu, log);
}

/// A device opened for one traversal compiles only what a render asks for: a traced render
/// makes its trace pipeline and nothing else (no raster G-buffer); the G-buffer's pipeline
/// comes with the first AOV or focus query, once.
#[test]
fn a_traced_render_makes_only_its_trace_pipeline() {
    let test = "a_traced_render_makes_only_its_trace_pipeline";
    let Some(traversal) = default_traversal(test) else {
        return;
    };
    let options = GpuOptions {
        traversal: Some(traversal),
        ..GpuOptions::default()
    };
    let Some((mut gpu, log)) = renderer_with(test, &options) else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let lens = LensParams::ThinLens {
        aperture_radius: 0.1,
        focus_distance: 4.0,
    };
    let lit = Shot {
        camera: camera(false, lens, 32, 24),
        render: settings(Shading::Lit, 2),
    };
    gpu.render(&lit, &mut |_, _| {}).expect("lit render");
    assert_eq!(gpu.counters().pipelines, 1, "{traversal}: a traced render");
    let depth = Shot {
        camera: lit.camera,
        render: settings(Shading::Depth, 1),
    };
    gpu.render(&depth, &mut |_, _| {}).expect("depth AOV");
    let cam = depth.camera;
    gpu.render_gbuffer(&cam, Vec3::ZERO).expect("G-buffer");
    assert_eq!(
        gpu.counters().pipelines,
        2,
        "{traversal}: and the G-buffer, once"
    );
    finish(gpu, log);
}

/// Progressive rendering: samples 0..8 then 8..16, accumulated by two dispatches, give exactly
/// the image of one dispatch of 0..16 with the default (Sobol') sampler.
#[test]
fn sample_ranges_add_up_to_the_whole() {
    let Some((mut gpu, log)) = renderer("sample_ranges_add_up_to_the_whole") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let lens = LensParams::ThinLens {
        aperture_radius: 0.15,
        focus_distance: 4.5,
    };
    let shot = Shot {
        camera: camera(false, lens, 32, 24),
        render: settings(Shading::Unlit, 16),
    };
    assert_eq!(shot.render.sampler, SamplerKind::Sobol);
    let whole = gpu.render(&shot, &mut |_, _| {}).expect("render");
    gpu.set_samples_per_dispatch(32 * 24 * 8);
    let dispatches_before = gpu.timings().dispatches;
    let halves = gpu.render(&shot, &mut |_, _| {}).expect("render");
    assert_eq!(
        gpu.timings().dispatches - dispatches_before,
        2,
        "expected the samples 0..8 then 8..16"
    );
    if whole != halves {
        let files = write_comparison(&halves, &whole, "sample-ranges");
        panic!("samples 0..8 + 8..16 differ from 0..16; wrote {files}");
    }
    finish(gpu, log);
}

/// The project's own scenes (built-in default, Cornell box from assets/) as the CLI resolves
/// them, small: GPU against the CPU reference, lit and unlit.
#[test]
fn gpu_matches_cpu_on_project_scenes() {
    use lensray_core::settings::{ImageSettings, RenderStyle, Settings};
    let Some((mut gpu, log)) = renderer("gpu_matches_cpu_on_project_scenes") else {
        return;
    };
    let cornell =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/cornell/cornell.toml");
    let scenes = [
        ("default", lensray_core::scene::builtin::default_scene()),
        (
            "cornell",
            lensray_core::scene::file::load(&cornell).expect("load the Cornell box"),
        ),
    ];
    for (name, mut desc) in scenes {
        let settings = desc.settings.clone();
        lensray_core::settings::light_scene(&settings, &mut desc.scene).expect("its lights");
        gpu.load_scene(&desc.scene).expect("load scene");
        let cpu = CpuRenderer::new(&desc.scene);
        for shading in [Shading::Unlit, Shading::Lit] {
            let over = Settings {
                image: ImageSettings {
                    width: Some(96),
                    height: Some(72),
                    spp: Some(4),
                    seed: Some(3),
                    sampler: None,
                    fps: None,
                },
                render: RenderStyle {
                    shading: Some(shading),
                    background: None,
                    environment: None,
                    environment_rotation: None,
                    environment_intensity: None,
                    bounces: None,
                    noise_threshold: None,
                },
                ..Default::default()
            };
            let resolved = lensray_core::settings::shot(
                &desc.settings.clone().overridden_by(&over),
                &desc.scene,
            )
            .expect("resolve settings");
            let image = gpu.render(&resolved, &mut |_, _| {}).expect("GPU render");
            let (reference, _) = cpu.render(&resolved, &mut |_, _| {});
            let diff = compare(&image, &reference, 1.0 / 255.0);
            let label = format!("scene-{name}-{shading:?}").to_lowercase();
            println!("{label}: {diff:?}");
            if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
                let files = write_comparison(&image, &reference, &label);
                panic!("{label}: GPU and CPU differ: {diff:?}; wrote {files}");
            }
        }
    }
    finish(gpu, log);
}

/// Rays are counted per workgroup, then once into the global counter: unlit, every sample is
/// exactly one camera ray, so a render of an image whose size is no multiple of the 8x8
/// workgroups (idle invocations at the edges) counts width x height x spp, on each traversal.
#[test]
fn rays_are_counted_exactly_per_workgroup() {
    let test = "rays_are_counted_exactly_per_workgroup";
    let Some((mut gpu, log)) = renderer(test) else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let shot = Shot {
        camera: camera(
            false,
            LensParams::ThinLens {
                aperture_radius: 0.1,
                focus_distance: 5.0,
            },
            37,
            23,
        ),
        render: settings(Shading::Unlit, 3),
    };
    for traversal in gpu.traversals() {
        gpu.set_traversal(traversal).expect("traversal");
        let before = gpu.timings();
        gpu.render(&shot, &mut |_, _| {}).expect("render");
        let after = gpu.timings();
        let rays = (after.rays_traced + after.first_dispatch_rays)
            - (before.rays_traced + before.first_dispatch_rays);
        assert_eq!(rays, 37 * 23 * 3, "{traversal}");
    }
    finish(gpu, log);
}

/// The ray count is 64 bits wide (a 4K render at 256 spp passes 2^32 rays): started 256 below
/// 2^32, a render of 768 camera rays must carry into the high word and report them all.
#[test]
fn the_ray_count_carries_past_two_to_the_32() {
    let Some((mut gpu, log)) = renderer("the_ray_count_carries_past_two_to_the_32") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let shot = Shot {
        camera: camera(false, LensParams::Pinhole, 24, 16),
        render: settings(Shading::Unlit, 2),
    };
    for traversal in gpu.traversals() {
        gpu.set_traversal(traversal).expect("traversal");
        // The first call times the pipeline's first dispatch apart; the later ones compare.
        gpu.render(&shot, &mut |_, _| {}).expect("render");
        let rays = |gpu: &mut lensray_vulkan::GpuRenderer| {
            let before = gpu.timings().rays_traced;
            gpu.render(&shot, &mut |_, _| {}).expect("render");
            gpu.timings().rays_traced - before
        };
        gpu.set_ray_counter_start(0);
        let plain = rays(&mut gpu);
        gpu.set_ray_counter_start(u32::MAX - 255);
        let carried = rays(&mut gpu);
        gpu.set_ray_counter_start(0);
        assert_eq!(plain, 24 * 16 * 2, "{traversal:?}: camera rays of the shot");
        assert_eq!(
            carried, plain,
            "{traversal:?}: the count started at 2^32 - 256 lost the carry"
        );
    }
    finish(gpu, log);
}
