//! The device itself: opening it (or skipping), its errors, leaks caught on close, scenes it
//! accepts or refuses, and the devices it lists.

use lensray_core::camera::LensParams;
use lensray_core::settings::{Shading, Shot};
use lensray_vulkan::{GpuError, GpuOptions, GpuRenderer};

use crate::support::*;

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
    let shot = Shot {
        camera: camera(false, LensParams::Pinhole, 16, 12),
        render: settings(Shading::Unlit, 1),
    };
    let err = gpu
        .render(&shot, &mut |_, _| {})
        .expect_err("no scene loaded");
    assert!(matches!(err, GpuError::NoScene), "{err}");
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
    let shot = Shot {
        camera: camera(false, LensParams::Pinhole, 32, 24),
        render: settings(Shading::Lit, 2),
    };
    let cam = &shot.camera;
    let image = gpu.render(&shot, &mut |_, _| {}).expect("render");
    assert!(image.pixels.iter().all(|&p| p == BACKGROUND));
    let g = gpu.render_gbuffer(cam, BACKGROUND).expect("G-buffer");
    assert!(g.coverage.iter().all(|&c| !c));
    // A second scene replaces the first.
    gpu.load_scene(&test_scene()).expect("reload");
    let g = gpu.render_gbuffer(cam, BACKGROUND).expect("G-buffer");
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
    assert!(
        err.to_string().contains("indexes past 4 positions"),
        "{err}"
    );
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
    // The renderer picks a usable device, and names it.
    let Some((gpu, log)) = renderer("list_devices_reports_a_ray_query_device") else {
        return;
    };
    assert!(usable.iter().any(|d| d.name == gpu.device_name()));
    finish(gpu, log);
}
