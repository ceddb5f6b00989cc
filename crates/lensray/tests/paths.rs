//! The render-path interface: every path continues a render exactly, agrees with the CPU
//! reference, answers focus queries alike, and the choice of a path (`--path`, `--device`)
//! refuses contradictions with one clear line.

mod gpu_support;

use gpu_support::{
    camera, compare, may_skip, open_path, record_skip, settings, test_scene, write_comparison,
};
use lensray::paths::PathKind;
use lensray::paths::{self, DeviceChoice, DeviceKind, OpenedPath, PathChoice, PathOptions};
use lensray_core::camera::LensParams;
use lensray_core::film::Accumulation;
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{GpuError, GpuOptions};

fn shot() -> Shot {
    let lens = LensParams::ThinLens {
        aperture_radius: 0.12,
        focus_distance: 5.0,
    };
    Shot {
        camera: camera(false, lens, 64, 48),
        render: settings(Shading::Lit, 8),
    }
}

/// Opens `path` on the shot (validation on for GPU paths); `None` after recording a skip where
/// the machine has no usable device and LENSRAY_SKIP_GPU_TESTS=1.
fn open(test: &str, path: PathChoice) -> Option<OpenedPath> {
    open_path(test, path, &shot())
}

/// The paths this machine runs: the CPU, and every GPU path. A GPU path that does not open
/// fails the test, unless the machine may skip GPU tests (`LENSRAY_SKIP_GPU_TESTS=1` and no
/// usable device), where the skip is recorded as in every GPU test.
fn available(test: &str) -> Vec<PathChoice> {
    let mut kinds = vec![PathChoice::Only(PathKind::Cpu)];
    for kind in PathKind::ALL.into_iter().filter(|k| k.is_gpu()) {
        if let Some(opened) = open(test, kind.into()) {
            opened.path.close().expect("close");
            kinds.push(kind.into());
        }
    }
    kinds
}

/// Samples 0..3 then 3..8 added to one accumulation give the sums of 0..8 in one call, bit for
/// bit, on every path. A GPU path keeps the sums on its device between the calls: it reads back
/// nothing larger than a few bytes of progress until asked, then the image's sums once.
#[test]
fn every_path_continues_a_render_exactly() {
    let test = "every_path_continues_a_render_exactly";
    for choice in available(test) {
        let Some(OpenedPath { mut path, .. }) = open(test, choice) else {
            continue;
        };
        let gpu = path.kind().is_gpu();
        let shot = shot();
        let cam = &shot.camera;
        let image_bytes = u64::from(cam.width * cam.height) * 16;
        let mut whole = Accumulation::new(cam.width, cam.height);
        path.add_samples(&shot, 0..8, &mut whole, &mut |_, _| {})
            .expect("0..8");
        let mut parts = Accumulation::new(cam.width, cam.height);
        let before = path.report();
        path.add_samples(&shot, 0..3, &mut parts, &mut |_, _| {})
            .expect("0..3");
        assert_eq!(parts.on_host(), !gpu, "{choice}: where the sums are");
        path.add_samples(&shot, 3..8, &mut parts, &mut |_, _| {})
            .expect("3..8");
        let added = path.report().since(&before);
        if gpu {
            assert!(
                parts.host().is_err(),
                "{choice}: the host's stale sums must not be readable"
            );
            assert!(
                added.readback_bytes <= 1024,
                "{choice}: two calls continuing a render read back {} bytes",
                added.readback_bytes
            );
        }
        // The sums of the last call were copied out at its end: no submission to read them.
        // Those of an earlier accumulation take one copy, one wait.
        for (accumulation, submits) in [(&mut parts, 0), (&mut whole, 1)] {
            let before_read = path.report();
            path.read_sums(accumulation).expect("read");
            let read = path.report().since(&before_read);
            if gpu {
                assert_eq!(
                    (read.readback_bytes, read.submits, read.cpu_waits),
                    (image_bytes, submits, submits),
                    "{choice}: reading the sums back is one read of the image's sums"
                );
            }
        }
        let (whole, parts) = (whole.host().expect("read"), parts.host().expect("read"));
        // The hybrid gives pixels with a small circle of confusion fewer samples.
        if choice != PathChoice::Only(PathKind::Hybrid) {
            assert_eq!(parts.samples(), 8, "{choice}");
        }
        let differing = whole
            .pixels
            .iter()
            .zip(&parts.pixels)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differing, 0,
            "{choice}: {differing} pixels of 0..3 + 3..8 differ from 0..8"
        );
        let rendered = path.render(&shot, &mut |_, _| {}).expect("render");
        assert_eq!(
            rendered,
            whole.image(),
            "{choice}: render() is add_samples(0..spp)"
        );
        let report = path.report();
        assert!(report.rays > 0 && report.trace_seconds > 0.0, "{report:?}");
        path.close().expect("close: validation messages or leaks");
    }
}

/// An accumulation continues on another path: from the CPU to a GPU path (the host's sums go
/// up once), and back once the GPU path has read them; a path given sums another device holds
/// refuses with one clear line. The continued sums are those of one path alone, bit for bit
/// where both trace the same estimator (the CPU and `rayquery`/`software` agree within float
/// rounding, so the check is the image's).
#[test]
fn an_accumulation_moves_between_paths() {
    let test = "an_accumulation_moves_between_paths";
    let shot = shot();
    let cam = &shot.camera;
    let Some(OpenedPath { path: mut cpu, .. }) = open(test, PathChoice::Only(PathKind::Cpu)) else {
        return;
    };
    let mut reference = Accumulation::new(cam.width, cam.height);
    cpu.add_samples(&shot, 0..8, &mut reference, &mut |_, _| {})
        .expect("cpu 0..8");
    let reference = reference.image().expect("on the host");
    for choice in available(test).into_iter().filter(|c| {
        matches!(
            c.only(),
            Some(PathKind::RayQuery | PathKind::RtPipeline | PathKind::Software)
        )
    }) {
        let Some(OpenedPath { mut path, .. }) = open(test, choice) else {
            continue;
        };
        let mut moving = Accumulation::new(cam.width, cam.height);
        cpu.add_samples(&shot, 0..3, &mut moving, &mut |_, _| {})
            .expect("cpu 0..3");
        path.add_samples(&shot, 3..5, &mut moving, &mut |_, _| {})
            .expect("gpu 3..5");
        let refused = cpu
            .add_samples(&shot, 5..8, &mut moving, &mut |_, _| {})
            .expect_err("the CPU cannot add to sums a GPU holds");
        let line = format!("{refused:#}");
        assert!(
            line.contains("read_sums") && !line.contains('\n'),
            "{choice}: {line}"
        );
        path.read_sums(&mut moving).expect("read");
        cpu.add_samples(&shot, 5..8, &mut moving, &mut |_, _| {})
            .expect("cpu 5..8");
        let image = moving.image().expect("on the host");
        let diff = compare(&image, &reference, 1.0 / 255.0);
        assert!(
            diff.within >= 0.995 && diff.mean_abs < 1e-3,
            "{choice}: CPU, GPU, CPU in turn differ from the CPU alone: {diff:?}"
        );
        path.close().expect("close: validation messages or leaks");
    }
}

/// With shaped apertures (a curved, squeezed pentagon; an image, a soap-bubble ring brighter
/// at its rim, squeezed) each traced GPU path and the raster path render the CPU reference's
/// image, as with the round one.
#[test]
fn gpu_paths_agree_with_the_cpu_on_a_shaped_aperture() {
    let test = "gpu_paths_agree_with_the_cpu_on_a_shaped_aperture";
    let Shot {
        camera: cam,
        render: s,
    } = shot();
    let pentagon = lensray_core::camera::ApertureShape {
        blades: Some(5),
        rotation_degrees: 15.0,
        roundness: 0.3,
        aspect: 1.4,
        image: None,
    };
    let side = 33u32;
    let ring: Vec<f32> = (0..side * side)
        .map(|i| {
            let (x, y) = (i % side, i / side);
            let r = ((x as f32 + 0.5) / side as f32 * 2.0 - 1.0)
                .hypot((y as f32 + 0.5) / side as f32 * 2.0 - 1.0);
            if r <= 1.0 {
                0.3 + 0.7 * r * r
            } else {
                0.0
            }
        })
        .collect();
    let bubble = lensray_core::camera::ApertureShape {
        aspect: 1.4,
        image: Some(std::sync::Arc::new(
            lensray_core::camera::aperture::ApertureImage::new(side, side, &ring)
                .expect("an aperture image"),
        )),
        ..lensray_core::camera::ApertureShape::ROUND
    };
    let Some(OpenedPath { path: mut cpu, .. }) = open(test, PathChoice::Only(PathKind::Cpu)) else {
        return;
    };
    let shared = RenderSettings {
        shared_samples: true,
        ..s
    };
    for (name, shape) in [("pentagon", pentagon), ("image", bubble)] {
        let cam = cam
            .clone()
            .with_aperture(shape.build().expect("valid aperture"))
            .expect("a thin lens takes any aperture");
        for choice in available(test).into_iter().filter(|c| {
            matches!(
                c.only(),
                Some(
                    PathKind::RayQuery
                        | PathKind::RtPipeline
                        | PathKind::Software
                        | PathKind::Raster
                )
            )
        }) {
            let Some(OpenedPath { mut path, .. }) = open(test, choice) else {
                continue;
            };
            let shot = Shot {
                camera: cam.clone(),
                render: if choice == PathChoice::Only(PathKind::Raster) {
                    shared
                } else {
                    s
                },
            };
            let reference = cpu.render(&shot, &mut |_, _| {}).expect("cpu");
            let image = path.render(&shot, &mut |_, _| {}).expect("render");
            let diff = compare(&image, &reference, 1.0 / 255.0);
            println!("{name}, {choice}: {diff:?}");
            if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
                let files = write_comparison(
                    &image,
                    &reference,
                    &format!("aperture-{name}-{choice}-vs-cpu"),
                );
                panic!("{name}, {choice}: differs from the CPU reference: {diff:?}; wrote {files}");
            }
            path.close().expect("close: validation messages or leaks");
        }
    }
}

/// Each GPU path renders the CPU reference's image (the statistics of lensray-vulkan's
/// tests/renderer/renders.rs), and finds the same focus depth at a pixel.
#[test]
fn gpu_paths_agree_with_the_cpu_reference() {
    let test = "gpu_paths_agree_with_the_cpu_reference";
    let shot = shot();
    let cam = &shot.camera;
    let Some(OpenedPath { path: mut cpu, .. }) = open(test, PathChoice::Only(PathKind::Cpu)) else {
        return;
    };
    let reference = cpu.render(&shot, &mut |_, _| {}).expect("cpu render");
    // The raster path's estimator: every pixel draws the same camera samples.
    let shared = Shot {
        camera: cam.clone(),
        render: RenderSettings {
            shared_samples: true,
            ..shot.render
        },
    };
    let shared_reference = cpu
        .render(&shared, &mut |_, _| {})
        .expect("cpu render, shared samples");
    let focus_pixels = [[32, 24], [10, 40], [60, 5]];
    let reference_depths: Vec<Option<f32>> = focus_pixels
        .iter()
        .map(|&p| cpu.focus_depth_at(cam, p).expect("cpu focus"))
        .collect();
    // The hybrid is another estimator: tests/hybrid.rs checks it converges to the same image.
    for choice in available(test).into_iter().filter(|c| {
        *c != PathChoice::Only(PathKind::Cpu) && *c != PathChoice::Only(PathKind::Hybrid)
    }) {
        let Some(OpenedPath { mut path, .. }) = open(test, choice) else {
            continue;
        };
        let image = path.render(&shot, &mut |_, _| {}).expect("render");
        let reference = if choice == PathChoice::Only(PathKind::Raster) {
            &shared_reference
        } else {
            &reference
        };
        let diff = compare(&image, reference, 1.0 / 255.0);
        println!("{choice}: {diff:?}");
        if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
            let files = write_comparison(&image, reference, &format!("path-{choice}-vs-cpu"));
            panic!("{choice}: differs from the CPU reference: {diff:?}; wrote {files}");
        }
        for (&pixel, expected) in focus_pixels.iter().zip(&reference_depths) {
            let depth = path.focus_depth_at(cam, pixel).expect("focus");
            match (depth, expected) {
                (Some(d), Some(e)) => assert!(
                    (d - e).abs() <= 1e-4 * e.abs(),
                    "{choice}: focus depth at {pixel:?} is {d}, the CPU's {e}"
                ),
                (d, e) => assert_eq!(d.is_some(), e.is_some(), "{choice} at {pixel:?}"),
            }
        }
        path.close().expect("close: validation messages or leaks");
    }
}

/// `auto` names its choice and its reason; a GPU path when a device is usable.
#[test]
fn auto_says_what_it_chose_and_why() {
    let test = "auto_says_what_it_chose_and_why";
    let Some(OpenedPath { path, why, .. }) = open(test, PathChoice::Auto) else {
        return;
    };
    println!("auto: {} on {} ({why})", path.kind(), path.device_name());
    assert!(why.starts_with("auto: "), "{why}");
    assert!(
        path.kind().is_gpu(),
        "a usable Vulkan device, yet {}",
        path.kind()
    );
    path.close().expect("close");
}

/// `auto` weighs every GPU path: the hybrid always (lit too), the raster path left out, with the
/// reason, where the shot's blur would show as ghost copies at its spp, and considered in a
/// nearly pinhole shot at many samples; whatever it picks renders.
#[test]
fn auto_considers_the_hybrid_and_raster_paths() {
    let test = "auto_considers_the_hybrid_and_raster_paths";
    let s = shot().render;
    let blurred = Shot {
        camera: camera(
            false,
            LensParams::ThinLens {
                aperture_radius: 0.5,
                focus_distance: 5.0,
            },
            64,
            48,
        ),
        render: s,
    };
    let Some(OpenedPath { path, why, .. }) = open_path(test, PathChoice::Auto, &blurred) else {
        return;
    };
    println!("blurred, {} spp: {} ({why})", s.spp, path.kind());
    let path_kind = path.kind();
    path.close().expect("close");
    assert!(
        why.contains("raster left out: circles of confusion up to"),
        "{why}"
    );
    // Lit too, the hybrid is timed against the traced path (its error at equal spp is theirs):
    // with the raster path left out those two are the candidates, so the summary names both,
    // the faster first, and the traced one is the traversal auto picked.
    let compared = why
        .strip_prefix("auto: ")
        .and_then(|rest| rest.split_once(" rendered a "))
        .and_then(|(best, rest)| Some((best, rest.split_once(" calibration ")?.1)))
        .and_then(|(best, rest)| Some((best, rest.split_once("x faster than ")?.1)))
        .map(|(best, rest)| (best, rest.split(';').next().unwrap_or(rest)));
    let Some((best, next)) = compared else {
        panic!("auto's reason does not say what it compared: {why}");
    };
    let traced = if best == "hybrid" { next } else { best };
    assert!(
        [best, next].contains(&"hybrid") && ["rayquery", "software"].contains(&traced),
        "auto compared {best} and {next}, not the hybrid and a traced path: {why}"
    );
    assert!(
        why.contains(&format!("traversal {traced} ("))
            || why.contains(&format!("traces with {traced} (")),
        "the traced candidate {traced} is not the traversal auto picked: {why}"
    );
    assert_eq!(path_kind.name(), best, "{why}");
    let sharp = camera(
        false,
        LensParams::ThinLens {
            aperture_radius: 0.001,
            focus_distance: 5.0,
        },
        64,
        48,
    );
    let many = Shot {
        camera: sharp,
        render: settings(Shading::Unlit, 64),
    };
    let Some(OpenedPath { mut path, why, .. }) = open_path(test, PathChoice::Auto, &many) else {
        return;
    };
    println!("nearly pinhole, 64 spp: {} ({why})", path.kind());
    assert!(!why.contains("left out"), "{why}");
    let small = Shot {
        camera: many.camera,
        render: RenderSettings {
            spp: 2,
            ..many.render
        },
    };
    let image = path.render(&small, &mut |_, _| {}).expect("render");
    assert_eq!(image.pixels.len(), 64 * 48);
    path.close().expect("close: validation messages or leaks");
}

/// Choices that contradict each other are one-line errors, before any device opens.
#[test]
fn contradictory_choices_are_errors() {
    let shot = shot();
    let scene = test_scene();
    let cases = [
        (
            PathChoice::Only(PathKind::RayQuery),
            DeviceChoice::Only(DeviceKind::Cpu),
            GpuOptions::default(),
            "--path rayquery runs on a Vulkan device: it cannot be used with --device cpu",
        ),
        (
            PathChoice::Only(PathKind::Cpu),
            DeviceChoice::Only(DeviceKind::Gpu),
            GpuOptions::default(),
            "--path cpu runs on the CPU: it cannot be used with --device gpu",
        ),
        (
            PathChoice::Only(PathKind::Cpu),
            DeviceChoice::Auto,
            GpuOptions {
                validate: true,
                ..GpuOptions::default()
            },
            "--validate checks the Vulkan renderer: it cannot be used with --path cpu",
        ),
    ];
    for (path, device, gpu, expected) in cases {
        let options = PathOptions { path, device, gpu };
        let error = match paths::open(&options, &scene, &shot) {
            Ok(_) => panic!("{options:?} must be refused"),
            Err(e) => format!("{e:#}"),
        };
        assert_eq!(error, expected);
    }
}

/// A device without ray queries (hidden here) runs the software traversal: `auto` takes it as
/// the only one (for itself, the hybrid and the raster path), and asking for `rayquery` is a
/// clear error.
#[test]
fn without_ray_queries_the_software_path_runs() {
    let test = "without_ray_queries_the_software_path_runs";
    let shot = shot();
    let hidden = |path| PathOptions {
        path,
        device: DeviceChoice::Only(DeviceKind::Gpu),
        gpu: GpuOptions {
            validate: true,
            hide_ray_query: true,
            ..GpuOptions::default()
        },
    };
    let OpenedPath { mut path, why, .. } =
        match paths::open(&hidden(PathChoice::Auto), &test_scene(), &shot) {
            Ok(opened) => opened,
            Err(e) => match e.downcast_ref::<GpuError>() {
                Some(gpu) if may_skip(gpu) => return record_skip(test, &format!("{e:#}")),
                _ => panic!("{test}: {e:#}"),
            },
        };
    assert_ne!(path.kind(), PathKind::RayQuery, "{why}");
    assert!(
        why.contains("software (the only path this device supports)"),
        "{why}"
    );
    let image = path.render(&shot, &mut |_, _| {}).expect("render");
    assert!(image.pixels.iter().any(|p| p.max_element() > 0.0));
    path.close().expect("close: validation messages or leaks");

    let error = match paths::open(
        &hidden(PathChoice::Only(PathKind::RayQuery)),
        &test_scene(),
        &shot,
    ) {
        Ok(_) => panic!("--path rayquery must fail without ray queries"),
        Err(e) => format!("{e:#}"),
    };
    assert!(
        error.starts_with("--path rayquery: ") && error.contains("VK_KHR_ray_query"),
        "{error}"
    );
}

/// What a GPU render asks of the host: a 640x480, 16-spp render reads back the
/// image's sums and at most 4 KiB more (ray counter, timestamps), waits once (the hybrid's
/// plan too goes unwaited), and records its dispatches several to a submission.
#[test]
fn gpu_renders_read_back_once_and_never_wait_between_dispatches() {
    let test = "gpu_renders_read_back_once_and_never_wait_between_dispatches";
    let lens = LensParams::ThinLens {
        aperture_radius: 0.05,
        focus_distance: 5.0,
    };
    let shot = Shot {
        camera: camera(false, lens, 640, 480),
        render: settings(Shading::Unlit, 16),
    };
    let image_bytes = 640 * 480 * 16;
    for kind in PathKind::ALL.into_iter().filter(|k| k.is_gpu()) {
        let Some(OpenedPath { mut path, .. }) = open_path(test, kind.into(), &shot) else {
            continue;
        };
        let before = path.report();
        path.render(&shot, &mut |_, _| {}).expect("render");
        let r = path.report().since(&before);
        path.close().expect("close: validation messages or leaks");
        println!(
            "{kind}: {} submits, {} waits, {} bytes read back",
            r.submits, r.cpu_waits, r.readback_bytes
        );
        let waits = 1;
        assert_eq!(r.cpu_waits, waits, "{kind}: {r:?}");
        assert!(
            r.readback_bytes >= image_bytes && r.readback_bytes <= image_bytes + 4096,
            "{kind}: {} bytes read back, the image is {image_bytes}",
            r.readback_bytes
        );
        // The raster path: 16 samples, 8 to a submission.
        let most = if kind == PathKind::Raster { 2 } else { 16 };
        assert!(r.submits >= 1 && r.submits < most + waits, "{kind}: {r:?}");
    }
}
