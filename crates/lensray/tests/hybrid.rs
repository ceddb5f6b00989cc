//! The hybrid path (docs/hybrid.md): it converges to the image of the paths that trace every
//! sample (no bias: image-mean error within noise, RMSE against a converged reference
//! comparable), and an in-focus shot takes the G-buffer shortcut for most pixels.

mod gpu_support;

use gpu_support::{
    camera, may_skip, moved_camera, record_skip, render_path as render, settings, test_scene,
    traced_path, MOVED,
};
use lensray::paths::RenderPath;
use lensray::paths::{GpuPath, PathChoice, PathKind};
use lensray_core::camera::{Camera, LensParams};
use lensray_core::film::compare::{mean_error, rmse};
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{device_plan, host_plan, read_plan, GpuOptions, GpuRenderer};

/// The hybrid path on a validated device with the test scene loaded.
fn hybrid(test: &str) -> Option<GpuPath> {
    let renderer = match GpuRenderer::new(&GpuOptions {
        validate: true,
        ..GpuOptions::default()
    }) {
        Ok(renderer) => renderer,
        Err(e) if may_skip(&e) => {
            record_skip(test, &e.to_string());
            return None;
        }
        Err(e) => panic!("{test}: {e}"),
    };
    let mut path = GpuPath::new(renderer, PathKind::Hybrid).expect("hybrid path");
    path.load_scene(&test_scene()).expect("load scene");
    Some(path)
}

fn blurred_shot(width: u32, height: u32) -> Camera {
    // Focused near the middle of the scene: sharp and blurred regions, foreground over sharp
    // background included.
    camera(
        false,
        LensParams::ThinLens {
            aperture_radius: 0.12,
            focus_distance: 5.0,
        },
        width,
        height,
    )
}

/// Hybrid and rayquery (software where the device has no ray queries) at equal spp against a
/// CPU reference of 16x the samples and another seed: the hybrid's image-mean error is within
/// noise (4 standard errors), and its RMSE is comparable to the full path's.
fn converges(test: &str, shading: Shading) {
    converges_with(test, shading, blurred_shot(96, 72));
}

/// [`converges`] with the camera `cam`.
fn converges_with(test: &str, shading: Shading, cam: Camera) {
    let shot = Shot {
        camera: cam,
        render: settings(shading, 64),
    };
    let reference_shot = Shot {
        camera: shot.camera.clone(),
        render: RenderSettings {
            spp: 1024,
            seed: shot.render.seed ^ 0x5bd1_e995,
            ..shot.render
        },
    };
    let Some(reference) = render(test, PathChoice::Only(PathKind::Cpu), &reference_shot) else {
        return;
    };
    let Some(mut path) = hybrid(test) else {
        return;
    };
    let image = path.render(&shot, &mut |_, _| {}).expect("hybrid render");
    let plan = read_plan(path.renderer(), &shot).expect("read the plan");
    let hybrid_rays = path.report().rays;
    Box::new(path)
        .close()
        .expect("close: validation messages or leaks");
    // The hybrid traced with the device's default traversal: the full render traces with it.
    let Some(traced) = traced_path(test) else {
        return;
    };
    let full_choice = PathChoice::Only(traced);
    let Some(full) = render(test, full_choice, &shot) else {
        return;
    };

    let (hybrid_mean, full_mean) = (
        mean_error(&image, &reference),
        mean_error(&full, &reference),
    );
    let (hybrid_rmse, full_rmse) = (rmse(&image, &reference), rmse(&full, &reference));
    println!(
        "{shading:?}: shortcut {:.1}% of pixels, {:.1}% of the samples expected traced, \
         {hybrid_rays} rays; mean error hybrid {hybrid_mean:?}, {full_choice} {full_mean:?}; \
         RMSE hybrid {hybrid_rmse:.3e}, {full_choice} {full_rmse:.3e}",
        100.0 * plan.shortcut_fraction(),
        100.0 * plan.expected_samples / plan.all_samples as f64,
    );
    assert!(
        plan.shortcut_pixels > 0 && plan.shortcut_fraction() < 1.0,
        "the shot must mix shortcut and traced pixels"
    );
    assert!(
        hybrid_mean.mean.abs() <= 4.0 * hybrid_mean.standard_error,
        "{shading:?}: the hybrid's image mean is off by {hybrid_mean:?}: biased"
    );
    assert!(
        full_mean.mean.abs() <= 4.0 * full_mean.standard_error,
        "{shading:?}: {full_choice}'s image mean is off by {full_mean:?}"
    );
    // Where it traces it traces the same samples; its shortcut pixels add almost nothing.
    assert!(
        hybrid_rmse <= 1.1 * full_rmse,
        "{shading:?}: hybrid RMSE {hybrid_rmse:.3e} against {full_choice}'s {full_rmse:.3e}"
    );
}

/// Shifted and tilted: the plan's circles of confusion come from the tilted plane of focus
/// (`CocLens`), so the window it traces holds every lens ray and the hybrid stays unbiased, at
/// the full path's RMSE.
#[test]
fn hybrid_converges_on_a_shifted_tilted_shot() {
    let lens = LensParams::ThinLens {
        aperture_radius: 0.12,
        focus_distance: 5.0,
    };
    converges_with(
        "hybrid_converges_on_a_shifted_tilted_shot",
        Shading::Unlit,
        moved_camera(false, lens, 96, 72, MOVED),
    );
}

/// A squeezed, bladed aperture (reaching 1.8x its radius vertically, which the plan's circle
/// of confusion uses): the hybrid still converges to the full image, at the full path's RMSE.
#[test]
fn hybrid_converges_with_a_squeezed_bladed_aperture() {
    let aperture = lensray_core::camera::ApertureShape {
        blades: Some(5),
        rotation_degrees: 90.0,
        roundness: 0.2,
        aspect: 1.8,
        image: None,
    }
    .build()
    .expect("valid aperture");
    converges_with(
        "hybrid_converges_with_a_squeezed_bladed_aperture",
        Shading::Unlit,
        blurred_shot(96, 72)
            .with_aperture(aperture)
            .expect("a thin lens takes any aperture"),
    );
}

#[test]
fn hybrid_converges_to_the_full_image_unlit() {
    converges("hybrid_converges_to_the_full_image_unlit", Shading::Unlit);
}

#[test]
fn hybrid_converges_to_the_full_image_lit() {
    converges("hybrid_converges_to_the_full_image_lit", Shading::Lit);
}

/// A pinhole shot is in focus everywhere: most pixels take the shortcut and the path traces a
/// small fraction of the rays of a full render, with an image close to the full one.
#[test]
fn an_in_focus_shot_takes_the_shortcut() {
    let test = "an_in_focus_shot_takes_the_shortcut";
    let shot = Shot {
        camera: camera(false, LensParams::Pinhole, 96, 72),
        render: settings(Shading::Unlit, 32),
    };
    let (cam, s) = (&shot.camera, &shot.render);
    let Some(mut path) = hybrid(test) else {
        return;
    };
    let image = path.render(&shot, &mut |_, _| {}).expect("render");
    let plan = read_plan(path.renderer(), &shot).expect("read the plan");
    let rays = path.report().rays;
    Box::new(path).close().expect("close");
    let all = u64::from(cam.width) * u64::from(cam.height) * u64::from(s.spp);
    println!(
        "shortcut {:.1}% of pixels; {rays} rays of {all} ({:.1}%)",
        100.0 * plan.shortcut_fraction(),
        100.0 * rays as f64 / all as f64
    );
    assert!(
        plan.shortcut_fraction() > 0.7,
        "{:.3}",
        plan.shortcut_fraction()
    );
    // The warm-up of `paths::open` is not here: every ray counted is this render's.
    assert!(rays * 4 < all, "{rays} rays of {all}");
    let Some(full) = render(test, PathChoice::Only(PathKind::Software), &shot) else {
        return;
    };
    let error = rmse(&image, &full);
    assert!(error < 0.05, "RMSE {error} against the full render");
}

/// The plan made on the device (shaders/passes/hybrid_plan.comp, what `render --path hybrid` and the
/// preview use) equals the host's reference `Plan::new` entry for entry, on the test scene:
/// blurred (foreground and background), pinhole and orthographic shots, unlit and lit, odd
/// sizes (partial tiles), and several sample counts.
#[test]
fn the_device_plan_equals_the_host_plan() {
    let test = "the_device_plan_equals_the_host_plan";
    let renderer = match GpuRenderer::new(&GpuOptions {
        validate: true,
        ..GpuOptions::default()
    }) {
        Ok(renderer) => renderer,
        Err(e) if may_skip(&e) => {
            record_skip(test, &e.to_string());
            return;
        }
        Err(e) => panic!("{test}: {e}"),
    };
    let mut renderer = renderer;
    renderer.load_scene(&test_scene()).expect("load scene");
    let thin = |aperture_radius, focus_distance| LensParams::ThinLens {
        aperture_radius,
        focus_distance,
    };
    let shots = [
        (camera(false, thin(0.12, 5.0), 96, 72), 64),
        (camera(false, thin(0.3, 3.0), 101, 67), 16),
        (camera(false, thin(0.02, 6.0), 80, 60), 7),
        (camera(false, LensParams::Pinhole, 96, 72), 32),
        (camera(true, thin(0.2, 5.5), 90, 70), 64),
        (moved_camera(false, thin(0.12, 5.0), 96, 72, MOVED), 64),
        (moved_camera(true, thin(0.2, 5.5), 90, 70, MOVED), 64),
    ];
    for (cam, spp) in &shots {
        for shading in [Shading::Unlit, Shading::Lit] {
            let shot = Shot {
                camera: cam.clone(),
                render: settings(shading, *spp),
            };
            let host = host_plan(&mut renderer, &shot).expect("host plan");
            let device = device_plan(&mut renderer, &shot).expect("device plan");
            let differing: Vec<usize> = (0..host.entries.len())
                .filter(|&i| host.entries[i] != device.entries[i])
                .collect();
            assert!(
                differing.is_empty(),
                "{}x{} {:?} {shading:?} {spp} spp: {} of {} entries differ, first at pixel {}: \
                 host {:?}, device {:?}",
                cam.width,
                cam.height,
                cam.lens,
                differing.len(),
                host.entries.len(),
                differing[0],
                host.entries[differing[0]],
                device.entries[differing[0]]
            );
            assert_eq!(host, device);
            assert!(host.shortcut_pixels > 0 || *spp == 16);
        }
    }
    renderer
        .close()
        .expect("close: validation messages or leaks");
}

/// Lit, the shortcut follows the shading: on the built-in default scene (curved spheres, shadows
/// over the floor, strong blur) the hybrid's error against a converged reference is that of a
/// path tracing every sample (measured 1.000x here). A plan blind to shadow boundaries, its
/// shortcut samples not reprojected onto the pre-pass's image, gives 1.33x here, 2.2x at
/// 640x480 (docs/hybrid.md).
#[test]
fn lit_shortcuts_follow_shadows_and_curvature() {
    use lensray_core::reference::Renderer as CpuRenderer;
    use lensray_core::settings::{ImageSettings, RenderStyle, Settings};
    let test = "lit_shortcuts_follow_shadows_and_curvature";
    let mut description = lensray_core::scene::builtin::default_scene();
    let settings = description.settings.clone();
    lensray_core::settings::light_scene(&settings, &mut description.scene).expect("its light");
    let over = Settings {
        image: ImageSettings {
            width: Some(256),
            height: Some(192),
            spp: Some(16),
            seed: Some(3),
            sampler: None,
            fps: None,
        },
        render: RenderStyle {
            shading: Some(Shading::Lit),
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
        &description.settings.clone().overridden_by(&over),
        &description.scene,
    )
    .expect("resolve settings");
    let open = || match GpuRenderer::new(&GpuOptions {
        validate: true,
        ..GpuOptions::default()
    }) {
        Ok(mut renderer) => {
            renderer.load_scene(&description.scene).expect("load scene");
            Some(renderer)
        }
        Err(e) if may_skip(&e) => {
            record_skip(test, &e.to_string());
            None
        }
        Err(e) => panic!("{test}: {e}"),
    };
    let Some(mut full_renderer) = open() else {
        return;
    };
    let full = full_renderer
        .render(&resolved, &mut |_, _| {})
        .expect("full render");
    full_renderer
        .close()
        .expect("close: validation messages or leaks");
    let Some(renderer) = open() else {
        return;
    };
    let mut path = GpuPath::new(renderer, PathKind::Hybrid).expect("hybrid path");
    let image = path
        .render(&resolved, &mut |_, _| {})
        .expect("hybrid render");
    let shortcut = read_plan(path.renderer(), &resolved)
        .expect("read the plan")
        .shortcut_fraction();
    Box::new(path)
        .close()
        .expect("close: validation messages or leaks");
    let reference_shot = Shot {
        camera: resolved.camera.clone(),
        render: RenderSettings {
            spp: 256,
            seed: 0x5bd1_e995,
            ..resolved.render
        },
    };
    let (reference, _) =
        CpuRenderer::new(&description.scene).render(&reference_shot, &mut |_, _| {});

    let (hybrid_rmse, full_rmse) = (rmse(&image, &reference), rmse(&full, &reference));
    let hybrid_mean = mean_error(&image, &reference);
    println!(
        "default scene, lit, 256x192, 16 spp: shortcut {:.1}% of pixels; RMSE hybrid \
         {hybrid_rmse:.3e}, full {full_rmse:.3e} ({:.3}x); mean error {hybrid_mean:?}",
        100.0 * shortcut,
        hybrid_rmse / full_rmse
    );
    assert!(shortcut > 0.2, "the shot must take the shortcut somewhere");
    assert!(
        hybrid_mean.mean.abs() <= 4.0 * hybrid_mean.standard_error,
        "the hybrid's image mean is off by {hybrid_mean:?}: biased"
    );
    assert!(
        hybrid_rmse <= 1.05 * full_rmse,
        "lit hybrid RMSE {hybrid_rmse:.3e} against {full_rmse:.3e} tracing every sample"
    );
}
