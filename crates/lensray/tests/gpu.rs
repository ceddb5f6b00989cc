//! The Vulkan renderer on whatever ray-query device is present (lavapipe on CI), validation on:
//! every test ends by checking that the validation layer reported nothing, also after the
//! renderer (device, instance) was destroyed.
//!
//! Without a ray-query device (or the validation layer) these tests fail, unless
//! LENSRAY_SKIP_GPU_TESTS=1; then they are skipped, and scripts/test.sh reports how many.

mod gpu_support;

use glam::{UVec2, Vec2, Vec3};
use gpu_support::*;
use lensray_core::camera::{ApertureShape, Camera, LensParams};
use lensray_core::film::Image;
use lensray_core::interface::{VIEW_ALBEDO, VIEW_COC, VIEW_DEPTH, VIEW_NORMAL};
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::sampler::owen::{owen_scramble_reversed, shuffle_index};
use lensray_core::sampler::sobol::{lens_index, sobol_reversed};
use lensray_core::sampler::{
    camera_sample, hash_u32, sample_1d, sample_dimension, sample_key, SamplerKind,
};
use lensray_core::settings::Shading;
use lensray_vulkan::{focus_distance_at, GpuError, GpuOptions, GpuRenderer, ProbeQuery};

#[test]
fn bogus_device_index_is_a_clear_error() {
    let err = GpuRenderer::new(&GpuOptions {
        validate: true,
        device_index: Some(99),
        ..Default::default()
    })
    .err()
    .expect("device 99 must not exist");
    let text = err.to_string();
    if may_skip(&err) {
        record_skip("bogus_device_index_is_a_clear_error", &text);
        return;
    }
    assert!(
        matches!(err, GpuError::DeviceIndex { index: 99, .. }),
        "unexpected error: {text}"
    );
    assert!(
        text.contains("99") && text.contains("device"),
        "unclear: {text}"
    );
}

/// Every field of every struct shared with the shaders (src/interface) is read by GLSL where
/// Rust wrote it: std140 ones through a uniform block, std430 ones through a storage buffer,
/// the marked one through push constants too; no struct of the interface's list is left out.
#[test]
fn shader_layouts_match_rust() {
    use lensray_core::interface::glsl::{ProbeBlock, LAYOUT_PROBE_COPIES};
    use lensray_core::interface::shared_structs;

    let Some((mut gpu, log)) = renderer("shader_layouts_match_rust") else {
        return;
    };
    let report = gpu.probe_layouts().expect("layout probe");
    let structs = shared_structs();
    // Each struct of the list, in order, in its layout's block, then the pushed one.
    let probed: Vec<(&str, ProbeBlock, usize)> = report
        .blocks
        .iter()
        .map(|b| (b.rust, b.block, b.copies))
        .collect();
    let mut expected: Vec<(&str, ProbeBlock, usize)> = structs
        .iter()
        .map(|s| (s.rust, ProbeBlock::of(s.layout), LAYOUT_PROBE_COPIES))
        .collect();
    expected.extend(
        structs
            .iter()
            .filter(|s| s.probe_push)
            .map(|s| (s.rust, ProbeBlock::PushConstant, 1)),
    );
    assert_eq!(probed, expected, "the probe must read every shared struct");
    assert!(
        expected.iter().any(|e| e.1 == ProbeBlock::PushConstant),
        "a struct must be read through push constants"
    );
    let scalars: usize = structs
        .iter()
        .map(|s| s.scalars.len() * (LAYOUT_PROBE_COPIES + usize::from(s.probe_push)))
        .sum();
    assert_eq!(report.scalars_checked, scalars);
    println!(
        "layout probe: {} structs, {} blocks, {} scalars",
        structs.len(),
        report.blocks.len(),
        report.scalars_checked
    );
    assert!(
        report.mismatches.is_empty(),
        "{} of {} scalars are read elsewhere than Rust wrote them:\n{}",
        report.mismatches.len(),
        report.scalars_checked,
        report.mismatches.join("\n")
    );
    finish(gpu, log);
}

/// Even with LENSRAY_SKIP_GPU_TESTS=1, only a machine that cannot run GPU tests skips them: a
/// failing pipeline, a Vulkan error or bad input fails the test.
#[test]
fn only_a_missing_device_or_layer_may_skip() {
    let no_device = GpuError::NoRayQueryDevice("none".into());
    let no_layer = GpuError::MissingLayer("VK_LAYER_KHRONOS_validation".into());
    for e in [&no_device, &no_layer, &GpuError::NoDriver] {
        assert!(may_skip_when(true, e), "{e}");
        assert!(!may_skip_when(false, e), "{e}");
    }
    let real_failures = [
        GpuError::Vulkan {
            call: "vkCreateComputePipelines",
            result: ash::vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
        },
        GpuError::Invalid("bad input".into()),
        GpuError::NoScene,
        GpuError::Validation {
            count: 1,
            first: "leak".into(),
        },
    ];
    for e in &real_failures {
        assert!(!may_skip_when(true, e), "{e} must fail, not skip");
    }
}

/// `close` destroys every object and fails on the validation layer's leak report, which only
/// comes while the device is destroyed.
#[test]
fn close_fails_on_a_leaked_object() {
    let Some((gpu, log)) = renderer("close_fails_on_a_leaked_object") else {
        return;
    };
    gpu.leak_an_object_for_tests().expect("create a sampler");
    assert_no_validation_messages(&log, "before the device is destroyed");
    let err = gpu.close().expect_err("a leaked sampler must fail close()");
    let text = err.to_string();
    assert!(
        matches!(err, GpuError::Validation { .. }) && text.contains("VkSampler"),
        "unexpected error: {text}"
    );
    assert!(log.instance_destroyed());
}

#[test]
fn render_before_load_scene_is_an_error() {
    let Some((mut gpu, log)) = renderer("render_before_load_scene_is_an_error") else {
        return;
    };
    let cam = camera(false, LensParams::Pinhole, 16, 12);
    let err = gpu
        .render(&cam, &settings(Shading::Unlit, 1), &mut |_, _| {})
        .expect_err("no scene loaded");
    assert!(matches!(err, GpuError::NoScene), "{err}");
    finish(gpu, log);
}

#[test]
fn sampler_and_camera_mirrors_match_rust() {
    let Some((mut gpu, log)) = renderer("sampler_and_camera_mirrors_match_rust") else {
        return;
    };
    let shape = |blades, rotation_degrees, roundness, aspect| {
        ApertureShape {
            blades,
            rotation_degrees,
            roundness,
            aspect,
            image: None,
        }
        .build()
        .expect("a valid aperture")
    };
    let image = odd_aperture_image().build().expect("a valid aperture");
    let perspective = camera(
        false,
        LensParams::ThinLens {
            aperture_radius: 0.2,
            focus_distance: 4.0,
        },
        97,
        61,
    );
    let orthographic = camera(
        true,
        LensParams::ThinLens {
            aperture_radius: 0.1,
            focus_distance: 3.0,
        },
        97,
        61,
    );
    // Round, then every kind of shaped aperture (straight blades, odd and even; curved;
    // squeezed), on both projections.
    let cams = [
        perspective.clone(),
        orthographic.clone(),
        perspective
            .clone()
            .with_aperture(shape(Some(6), 15.0, 0.0, 1.0))
            .expect("a thin lens takes any aperture"),
        perspective
            .clone()
            .with_aperture(shape(Some(5), -30.0, 0.4, 1.5))
            .expect("a thin lens takes any aperture"),
        perspective
            .clone()
            .with_aperture(shape(None, 0.0, 0.0, 2.0))
            .expect("a thin lens takes any aperture"),
        orthographic
            .clone()
            .with_aperture(shape(Some(9), 0.0, 0.7, 0.5))
            .expect("a thin lens takes any aperture"),
        perspective
            .with_aperture(image.clone())
            .expect("a thin lens takes any aperture"),
        orthographic
            .with_aperture(image)
            .expect("a thin lens takes any aperture"),
    ];
    let kinds = [SamplerKind::Sobol, SamplerKind::Independent];
    for cam in &cams {
        let queries: Vec<ProbeQuery> = (0..4096u32)
            .map(|i| ProbeQuery {
                seed: hash_u32(i / 64),
                pixel_x: i % cam.width,
                pixel_y: (i / 7) % cam.height,
                width: cam.width,
                // Small indices and large ones (the shuffled lens index uses all 32 bits).
                sample_index: if i % 5 == 0 { hash_u32(i) } else { i % 33 },
                dim: i % 6,
                hash_input: i.wrapping_mul(0x9e37_79b9) ^ (i << 7),
                sampler_kind: kinds[(i / 2) as usize % 2].id(),
            })
            .collect();
        let results = gpu.probe_mirrors(cam, &queries).expect("probe");
        let mut worst_ray = 0.0f32;
        for (q, r) in queries.iter().zip(&results) {
            assert_eq!(r.hash, hash_u32(q.hash_input), "hash_u32({})", q.hash_input);
            let pixel_index = q.pixel_y * q.width + q.pixel_x;
            let key = sample_key(q.seed, pixel_index, q.sample_index);
            assert_eq!(r.key, key, "sample_key for {q:?}");
            assert_eq!(
                r.sample_bits,
                sample_1d(key, q.dim).to_bits(),
                "sample_1d for {q:?}"
            );
            let (x, seed) = (q.hash_input, q.seed);
            assert_eq!(
                [r.lens, r.scrambled, r.shuffled, r.sobol],
                [
                    lens_index(x),
                    owen_scramble_reversed(x, seed),
                    shuffle_index(x, seed),
                    sobol_reversed(q.dim % 2, x),
                ],
                "lens index, Owen scrambling and Sobol' points of {x:#x} with seed {seed:#x}"
            );
            let kind = kinds[q.sampler_kind as usize];
            assert_eq!(kind.id(), q.sampler_kind);
            assert_eq!(
                r.dimension_bits,
                sample_dimension(kind, q.seed, pixel_index, q.sample_index, q.dim).to_bits(),
                "sample_dimension for {q:?}"
            );
            let cs = camera_sample(
                kind,
                q.seed,
                UVec2::new(q.pixel_x, q.pixel_y),
                q.width,
                q.sample_index,
            );
            let gpu_cs = r.camera_sample;
            assert_eq!(
                [cs.film.x, cs.film.y, cs.lens.x, cs.lens.y].map(f32::to_bits),
                gpu_cs.map(f32::to_bits),
                "camera_sample for {q:?}"
            );
            // Lens points of a bladed aperture or an image: additions, multiplications,
            // divisions and table searches on both sides (`precise` in GLSL), bit for bit. The
            // disk's sine and cosine are the GPU's own, within a few units in the last place.
            let lens = cam.lens.lens_point(cs.lens);
            let gpu_lens = Vec2::new(r.lens_point[0], r.lens_point[1]);
            let disk = cam.lens.aperture.fan().is_empty() && cam.lens.aperture.image().is_none();
            if disk {
                let err = (gpu_lens - lens).length() / cam.lens.reach();
                assert!(err < 1e-6, "lens_point {lens} vs {gpu_lens} for {q:?}");
            } else {
                assert_eq!(
                    lens.to_array().map(f32::to_bits),
                    gpu_lens.to_array().map(f32::to_bits),
                    "lens_point of {:?} for {q:?}",
                    cam.lens.aperture.shape
                );
            }
            // Rays: same formulas, but GPU transcendentals and fused operations may differ in
            // the last bits.
            let ray = cam.generate_ray(cs.film, cs.lens);
            let o = Vec3::new(r.origin[0], r.origin[1], r.origin[2]);
            let d = Vec3::new(r.direction[0], r.direction[1], r.direction[2]);
            let err = (o - ray.origin).length() / (1.0 + ray.origin.length())
                + (d - ray.direction).length();
            worst_ray = worst_ray.max(err);
            // A thin lens: the ray through the lens is that ray, weight 1 (tests/gpu_lens.rs
            // checks real lenses).
            assert_eq!(
                r.through_lens_origin,
                [r.origin[0], r.origin[1], r.origin[2], 1.0],
                "generate_ray_through_lens for {q:?}"
            );
            assert_eq!(r.through_lens_direction, r.direction);
        }
        assert!(worst_ray < 1e-5, "generate_ray differs by {worst_ray}");
    }
    finish(gpu, log);
}

/// Mesh index of each flattened triangle.
fn triangle_meshes(scene: &lensray_core::scene::Scene) -> Vec<usize> {
    scene
        .meshes
        .iter()
        .enumerate()
        .flat_map(|(m, mesh)| std::iter::repeat_n(m, mesh.triangles.len()))
        .collect()
}

/// Pixels whose 8 neighbours all show the same thing (`id`) as the pixel.
fn interior(width: u32, height: u32, id: &[i64]) -> Vec<bool> {
    let (w, h) = (width as i64, height as i64);
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx < 0
                        || ny < 0
                        || nx >= w
                        || ny >= h
                        || id[(ny * w + nx) as usize] == id[i as usize]
                })
            })
        })
        .collect()
}

fn raster_depth_matches_rays(orthographic: bool) {
    let name = if orthographic {
        "raster_view_depth_matches_rays_orthographic"
    } else {
        "raster_view_depth_matches_rays_perspective"
    };
    let Some((mut gpu, log)) = renderer(name) else {
        return;
    };
    let scene = test_scene();
    gpu.load_scene(&scene).expect("load scene");
    let cam = camera(orthographic, LensParams::Pinhole, 160, 120);
    let g = gpu.render_gbuffer(&cam, BACKGROUND).expect("G-buffer");
    let cpu = CpuRenderer::new(&scene);
    let meshes = triangle_meshes(&scene);

    let n = (cam.width * cam.height) as usize;
    let mut ids = vec![-1i64; n];
    let mut depth = vec![0.0f32; n];
    for y in 0..cam.height {
        for x in 0..cam.width {
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let ray = cam.generate_ray(centre, Vec2::splat(0.5));
            if let Some(hit) = cpu.intersect(&ray) {
                let i = g.index(x, y);
                ids[i] = meshes[hit.triangle as usize] as i64;
                depth[i] = cam.view_depth(ray.at(hit.t));
            }
        }
    }
    let keep = interior(cam.width, cam.height, &ids);
    let (mut checked, mut good, mut coverage_mismatch) = (0usize, 0usize, 0usize);
    let mut worst = Vec::new();
    for i in 0..n {
        if !keep[i] {
            continue;
        }
        if g.coverage[i] != (ids[i] >= 0) {
            coverage_mismatch += 1;
            continue;
        }
        if ids[i] < 0 {
            assert_eq!(g.view_depth[i], 0.0, "uncovered pixel {i} has a depth");
            continue;
        }
        checked += 1;
        let rel = (g.view_depth[i] - depth[i]).abs() / depth[i];
        if rel <= 1e-3 {
            good += 1;
        } else if worst.len() < 10 {
            worst.push((i, g.view_depth[i], depth[i]));
        }
    }
    assert!(checked > n / 3, "only {checked} covered interior pixels");
    let fraction = good as f64 / checked as f64;
    println!("{name}: {good}/{checked} within 1e-3, coverage mismatches {coverage_mismatch}");
    assert!(
        fraction >= 0.995 && coverage_mismatch * 200 <= checked,
        "{name}: {good}/{checked} covered pixels within 1e-3 ({coverage_mismatch} coverage \
         mismatches); first misses (pixel, raster, ray): {worst:?}"
    );
    finish(gpu, log);
}

#[test]
fn raster_view_depth_matches_rays_perspective() {
    raster_depth_matches_rays(false);
}

#[test]
fn raster_view_depth_matches_rays_orthographic() {
    raster_depth_matches_rays(true);
}

#[test]
fn pinhole_compute_equals_gbuffer_albedo() {
    let Some((mut gpu, log)) = renderer("pinhole_compute_equals_gbuffer_albedo") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    for orthographic in [false, true] {
        let cam = camera(orthographic, LensParams::Pinhole, 128, 96);
        let g = gpu.render_gbuffer(&cam, BACKGROUND).expect("G-buffer");
        let image = gpu
            .render(&cam, &settings(Shading::Unlit, 4), &mut |_, _| {})
            .expect("render");
        let ids: Vec<i64> = g
            .albedo
            .iter()
            .map(|a| {
                let q = (*a * 1000.0).round();
                (q.x as i64) << 40 | (q.y as i64) << 20 | q.z as i64
            })
            .collect();
        let keep = interior(cam.width, cam.height, &ids);
        let checked = keep.iter().filter(|&&k| k).count();
        let equal = (0..g.albedo.len())
            .filter(|&i| keep[i] && (image.pixels[i] - g.albedo[i]).abs().max_element() <= 1e-6)
            .count();
        let fraction = equal as f64 / checked as f64;
        if fraction < 0.995 {
            let albedo = Image {
                width: cam.width,
                height: cam.height,
                pixels: g.albedo.clone(),
            };
            let files = write_comparison(&image, &albedo, &format!("pinhole-ortho{orthographic}"));
            panic!("pinhole (ortho {orthographic}): {equal}/{checked} interior pixels equal the albedo; wrote {files}");
        }
    }
    finish(gpu, log);
}

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
    let cam: Camera = camera(orthographic, lens.clone(), 96, 72);
    let s = settings(shading, 8);
    let mut last = (0, 0);
    let image = gpu
        .render(&cam, &s, &mut |done, total| last = (done, total))
        .expect("GPU render");
    assert_eq!(last.0, last.1, "progress must end at the total");
    let (reference, _) = CpuRenderer::new(&scene).render(&cam, &s, &mut |_, _| {});
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
    let cam = camera(
        false,
        LensParams::ThinLens {
            aperture_radius: 0.1,
            focus_distance: 4.0,
        },
        64,
        48,
    );
    let s = settings(Shading::Lit, 6);
    let whole = gpu.render(&cam, &s, &mut |_, _| {}).expect("render");
    // Bands of rows and one sample at a time: 64 * 48 * 6 / 1000 -> dozens of dispatches,
    // and sums held for 20 rows at a time (3 bands, the last one shorter). They are recorded
    // 8 to a submission and nothing waits between them: one wait, at the end.
    gpu.set_samples_per_dispatch(1000);
    gpu.set_max_band_pixels(64 * 20);
    let mut calls = Vec::new();
    let (before, dispatches_before) = (gpu.counters(), gpu.timings().dispatches);
    let split = gpu
        .render(&cam, &s, &mut |done, total| calls.push((done, total)))
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
        64 * 48 * 16 + 16 + 16 * dispatches,
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
    let Some(traversal) = traced_path(test).and_then(|p| p.traversal()) else {
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
    let cam = camera(false, lens, 32, 24);
    gpu.render(&cam, &settings(Shading::Lit, 2), &mut |_, _| {})
        .expect("lit render");
    assert_eq!(gpu.counters().pipelines, 1, "{traversal}: a traced render");
    gpu.render(&cam, &settings(Shading::Depth, 1), &mut |_, _| {})
        .expect("depth AOV");
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
    let cam = camera(false, lens, 32, 24);
    let s = settings(Shading::Unlit, 16);
    assert_eq!(s.sampler, SamplerKind::Sobol);
    let whole = gpu.render(&cam, &s, &mut |_, _| {}).expect("render");
    gpu.set_samples_per_dispatch(32 * 24 * 8);
    let dispatches_before = gpu.timings().dispatches;
    let halves = gpu.render(&cam, &s, &mut |_, _| {}).expect("render");
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

#[test]
fn aovs_come_from_the_gbuffer() {
    let Some((mut gpu, log)) = renderer("aovs_come_from_the_gbuffer") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let cam = camera(false, LensParams::Pinhole, 80, 60);
    let g = gpu.render_gbuffer(&cam, BACKGROUND).expect("G-buffer");
    let depth = gpu
        .render(&cam, &settings(Shading::Depth, 1), &mut |_, _| {})
        .expect("depth");
    let normal = gpu
        .render(&cam, &settings(Shading::Normal, 1), &mut |_, _| {})
        .expect("normal");
    let albedo = gpu
        .render(&cam, &settings(Shading::Albedo, 1), &mut |_, _| {})
        .expect("albedo");
    for i in 0..g.coverage.len() {
        assert_eq!(depth.pixels[i], Vec3::splat(g.view_depth[i]));
        assert_eq!(normal.pixels[i], g.normal[i]);
        assert_eq!(albedo.pixels[i], g.albedo[i]);
        if g.coverage[i] {
            assert!((g.normal[i].length() - 1.0).abs() < 1e-4);
            assert!(g.view_depth[i] > cam.near);
        } else {
            assert_eq!(g.albedo[i], BACKGROUND);
            assert_eq!(g.view_depth[i], 0.0);
        }
    }
    // Autofocus on the centre pixel: the sphere/box region is covered.
    let (cx, cy) = (cam.width / 2, cam.height / 2);
    let f = focus_distance_at(&g, cx, cy).expect("centre covered");
    assert_eq!(f, g.view_depth[g.index(cx, cy)]);
    assert_eq!(focus_distance_at(&g, cam.width, 0), None);
    finish(gpu, log);
}

/// The CPU reference's AOVs are defined as the G-buffer's (aperture-centre ray at each pixel
/// centre), so the two devices agree on them away from silhouettes, with depth of field on.
#[test]
fn gpu_aovs_match_cpu_aovs() {
    let Some((mut gpu, log)) = renderer("gpu_aovs_match_cpu_aovs") else {
        return;
    };
    let scene = test_scene();
    gpu.load_scene(&scene).expect("load scene");
    let cpu = lensray_core::reference::Renderer::new(&scene);
    let lens = LensParams::ThinLens {
        aperture_radius: 0.2,
        focus_distance: 4.0,
    };
    for orthographic in [false, true] {
        let cam = camera(orthographic, lens.clone(), 80, 60);
        for shading in [Shading::Depth, Shading::Normal, Shading::Albedo] {
            let s = settings(shading, 4);
            let g = gpu.render(&cam, &s, &mut |_, _| {}).expect("GPU AOV");
            let (c, _) = cpu.render(&cam, &s, &mut |_, _| {});
            // Depth to 1e-4 of the far distance; colours and normals absolutely.
            let tolerance = if shading == Shading::Depth {
                1e-4 * cam.far
            } else {
                1e-3
            };
            let diff = compare(&g, &c, tolerance);
            let name = format!(
                "aov_{shading:?}_{}",
                if orthographic { "ortho" } else { "persp" }
            );
            assert!(
                diff.within >= 0.995,
                "{name}: {:.4} of pixels within {tolerance} (max {}), {}",
                diff.within,
                diff.max_abs,
                write_comparison(&g, &c, &name)
            );
        }
    }
    finish(gpu, log);
}

/// The preview draws its non-final views with the view pass, straight into the window image,
/// and the final view's frames with the G-buffer and the resolve: both routes must show the
/// same bytes, background included.
#[test]
fn preview_views_by_both_routes_are_equal() {
    let Some((mut gpu, log)) = renderer("preview_views_by_both_routes_are_equal") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let lens = LensParams::ThinLens {
        aperture_radius: 0.1,
        focus_distance: 5.0,
    };
    for orthographic in [false, true] {
        let cam = camera(orthographic, lens.clone(), 96, 64);
        for view in [VIEW_ALBEDO, VIEW_NORMAL, VIEW_DEPTH, VIEW_COC] {
            let routes = gpu
                .probe_view_routes(&cam, BACKGROUND, view)
                .expect("both routes");
            let differ: Vec<i32> = routes
                .resolved
                .iter()
                .zip(&routes.drawn)
                .map(|(a, b)| {
                    (0..4)
                        .map(|c| (a[c] as i32 - b[c] as i32).abs())
                        .max()
                        .unwrap()
                })
                .filter(|&d| d > 0)
                .collect();
            if !differ.is_empty() {
                let name = format!("view{view}-ortho{orthographic}");
                for (pixels, route) in [(&routes.resolved, "resolved"), (&routes.drawn, "drawn")] {
                    let bytes = pixels.iter().flatten().copied().collect();
                    image::RgbaImage::from_raw(cam.width, cam.height, bytes)
                        .expect("4 bytes per pixel")
                        .save(output_dir().join(format!("{name}-{route}.png")))
                        .expect("write PNG");
                }
                panic!(
                    "view {view} (ortho {orthographic}): {} of {} pixels differ between the \
                     resolve and the view pass, by up to {}/255; wrote {name}-*.png under {}",
                    differ.len(),
                    routes.drawn.len(),
                    differ.iter().max().unwrap(),
                    output_dir().display()
                );
            }
        }
    }
    finish(gpu, log);
}

#[test]
fn empty_scene_shows_the_background() {
    let Some((mut gpu, log)) = renderer("empty_scene_shows_the_background") else {
        return;
    };
    let mut scene = test_scene();
    scene.meshes.clear();
    gpu.load_scene(&scene).expect("load an empty scene");
    let cam = camera(false, LensParams::Pinhole, 32, 24);
    let image = gpu
        .render(&cam, &settings(Shading::Lit, 2), &mut |_, _| {})
        .expect("render");
    assert!(image.pixels.iter().all(|&p| p == BACKGROUND));
    let g = gpu.render_gbuffer(&cam, BACKGROUND).expect("G-buffer");
    assert!(g.coverage.iter().all(|&c| !c));
    // A second scene replaces the first.
    gpu.load_scene(&test_scene()).expect("reload");
    let g = gpu.render_gbuffer(&cam, BACKGROUND).expect("G-buffer");
    assert!(g.coverage.iter().any(|&c| c));
    finish(gpu, log);
}

#[test]
fn invalid_scenes_are_rejected() {
    let Some((mut gpu, log)) = renderer("invalid_scenes_are_rejected") else {
        return;
    };
    let mut scene = test_scene();
    scene.meshes[1].material_ids[0] = 42;
    let err = gpu.load_scene(&scene).expect_err("material out of range");
    assert!(err.to_string().contains("material 42"), "{err}");
    let mut scene = test_scene();
    scene.meshes[0].triangles[0][2] = 1000;
    let err = gpu.load_scene(&scene).expect_err("index out of range");
    assert!(err.to_string().contains("out of range"), "{err}");
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
    for (name, desc) in scenes {
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
                },
                render: RenderStyle {
                    shading: Some(shading),
                    background: None,
                },
                ..Default::default()
            };
            let resolved = lensray_core::settings::shot(
                &desc.settings.clone().overridden_by(&over),
                &desc.scene,
            )
            .expect("resolve settings");
            let image = gpu
                .render(&resolved.camera, &resolved.render, &mut |_, _| {})
                .expect("GPU render");
            let (reference, _) = cpu.render(&resolved.camera, &resolved.render, &mut |_, _| {});
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

#[test]
fn list_devices_reports_a_ray_query_device() {
    let devices = match lensray_vulkan::list_devices() {
        Ok(d) => d,
        Err(e) if may_skip(&e) => {
            record_skip("list_devices_reports_a_ray_query_device", &e.to_string());
            return;
        }
        Err(e) => panic!("list_devices: {e}"),
    };
    let usable: Vec<_> = devices.iter().filter(|d| d.ray_query).collect();
    if usable.is_empty() && std::env::var("LENSRAY_SKIP_GPU_TESTS").as_deref() == Ok("1") {
        record_skip(
            "list_devices_reports_a_ray_query_device",
            "no Vulkan device with ray queries",
        );
        return;
    }
    assert!(!usable.is_empty(), "no ray-query device in {devices:#?}");
    for d in &devices {
        assert_eq!(d.ray_query, d.missing.is_empty(), "{d:?}");
        assert!(d.max_image_dimension_2d >= 4096 && d.max_storage_buffer_range > 0);
    }
    let text = lensray::cli::info::format_devices(&devices);
    assert!(
        text.contains(&usable[0].name)
            && text.contains("ray queries        yes")
            && text.contains("paths              rayquery, software, hybrid, raster, cpu"),
        "{text}"
    );
    // The renderer picks a usable device, and names it.
    let Some((gpu, log)) = renderer("list_devices_reports_a_ray_query_device") else {
        return;
    };
    assert!(usable.iter().any(|d| d.name == gpu.device_name()));
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
    let cam = camera(
        false,
        LensParams::ThinLens {
            aperture_radius: 0.1,
            focus_distance: 5.0,
        },
        37,
        23,
    );
    let s = settings(Shading::Unlit, 3);
    for traversal in gpu.traversals() {
        gpu.set_traversal(traversal).expect("traversal");
        let before = gpu.timings();
        gpu.render(&cam, &s, &mut |_, _| {}).expect("render");
        let after = gpu.timings();
        let rays = (after.rays_traced + after.first_dispatch_rays)
            - (before.rays_traced + before.first_dispatch_rays);
        assert_eq!(rays, 37 * 23 * 3, "{traversal}");
    }
    finish(gpu, log);
}
