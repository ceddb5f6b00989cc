//! The app's GPU test helpers: the shared GPU test support of lensray-vulkan's tests (one
//! copy, included below: the renderer or a recorded skip, validation checks, test scenes and
//! cameras, image comparison), and the helpers that open the app's render paths on it.
#![allow(
    dead_code,
    reason = "each test binary includes this module and uses part of it"
)]

// lensray-vulkan's own test support: one copy, which its tests use as `mod support;`.
#[path = "../../../lensray-vulkan/tests/support/mod.rs"]
mod support;

pub use support::*;

use glam::Vec3;
use lensray::paths::{self, DeviceChoice, OpenedPath, PathChoice, PathKind, PathOptions};
use lensray_core::camera::{CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::scene::Scene;
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{GpuError, GpuOptions};

/// `choice` opened on the test scene for `shot` as `render --path` opens it (validation on for
/// GPU paths); `None` (skip recorded) where the machine cannot run it and skipping is allowed.
pub fn open_path(test: &str, choice: PathChoice, shot: &Shot) -> Option<OpenedPath> {
    open_path_with(test, choice, &test_scene(), shot)
}

/// [`open_path`] on `scene`.
pub fn open_path_with(
    test: &str,
    choice: PathChoice,
    scene: &Scene,
    shot: &Shot,
) -> Option<OpenedPath> {
    let options = PathOptions {
        path: choice,
        device: DeviceChoice::Auto,
        gpu: GpuOptions {
            validate: choice != PathChoice::Only(PathKind::Cpu),
            ..GpuOptions::default()
        },
    };
    match paths::open(&options, scene, shot) {
        Ok(opened) => Some(opened),
        Err(e) => match e.downcast_ref::<GpuError>() {
            Some(gpu) if may_skip(gpu) => {
                record_skip(test, &format!("{e:#}"));
                None
            }
            _ => panic!("{test}: --path {choice}: {e:#}"),
        },
    }
}

/// The traced path (`rayquery` or `software`) the Vulkan device traces with by default (ray
/// queries where it has them): what the hybrid and raster paths are compared with. `None`
/// (skip recorded) where the machine may skip GPU tests; any other failure fails the test.
pub fn traced_path(test: &str) -> Option<PathKind> {
    default_traversal(test).map(PathKind::of_traversal)
}

/// `choice`'s render of `shot` of the test scene (see `open_path`), closed with the validation
/// check.
pub fn render_path(test: &str, choice: PathChoice, shot: &Shot) -> Option<Image> {
    let OpenedPath { mut path, .. } = open_path(test, choice, shot)?;
    let image = path.render(shot, &mut |_, _| {}).expect("render");
    path.close().expect("close: validation messages or leaks");
    Some(image)
}

/// `choice`'s render of `shot` of `scene`, closed with the validation checks; `None` where GPU
/// tests may be skipped.
pub fn render_scene(test: &str, choice: PathChoice, scene: &Scene, shot: &Shot) -> Option<Image> {
    let OpenedPath { mut path, .. } = open_path_with(test, choice, scene, shot)?;
    let image = path.render(shot, &mut |_, _| {}).expect("render");
    path.close().expect("close: validation messages or leaks");
    Some(image)
}

/// Renders each of `shots` (named) of `scene` on the CPU and on every GPU path (`rayquery`,
/// `rtpipeline`, `software`, and `raster` with the shared samples it draws), and panics, with
/// the images written under the shot's name, unless each agrees with the CPU within 1/255 on
/// 99.9 % of pixels with a mean difference under 1e-3. Each GPU path is opened once for all
/// the shots, as a sequence's frames are: opening one (its device and pipelines) costs more
/// than these small renders.
pub fn assert_gpu_paths_match_cpu(test: &str, scene: &Scene, shots: &[(String, Shot)]) {
    assert!(!shots.is_empty(), "{test}: no shot to compare");
    let cpu = PathChoice::Only(PathKind::Cpu);
    let mut references = Vec::new();
    for (name, shot) in shots {
        let shared = Shot {
            render: RenderSettings {
                shared_samples: true,
                ..shot.render
            },
            ..shot.clone()
        };
        let (Some(image), Some(shared_image)) = (
            render_scene(test, cpu, scene, shot),
            render_scene(test, cpu, scene, &shared),
        ) else {
            return;
        };
        write_png(&image, &format!("{name}-cpu.png"));
        references.push(Reference {
            shot: shot.clone(),
            image,
            shared,
            shared_image,
        });
    }
    for kind in [
        PathKind::RayQuery,
        PathKind::RtPipeline,
        PathKind::Software,
        PathKind::Raster,
    ] {
        let of = |r: &Reference| match kind {
            PathKind::Raster => (r.shared.clone(), r.shared_image.clone()),
            _ => (r.shot.clone(), r.image.clone()),
        };
        let first = of(&references[0]).0;
        let Some(OpenedPath { mut path, .. }) = open_path_with(test, kind.into(), scene, &first)
        else {
            return;
        };
        for ((name, _), r) in shots.iter().zip(&references) {
            let (shot, reference) = of(r);
            let image = path.render(&shot, &mut |_, _| {}).expect("render");
            let diff = compare(&image, &reference, 1.0 / 255.0);
            println!("{name} {kind}: {diff:?}");
            if diff.within < 0.999 || diff.mean_abs >= 1e-3 {
                let files = write_comparison(&image, &reference, &format!("{name}-{kind}-vs-cpu"));
                panic!("{name} {kind}: differs from the CPU: {diff:?}; wrote {files}");
            }
        }
        path.close().expect("close: validation messages or leaks");
    }
}

/// A shot's CPU reference, and its shared-sample one (the raster path's).
struct Reference {
    shot: Shot,
    image: Image,
    shared: Shot,
    shared_image: Image,
}

/// An unlit shot of `spp` samples a pixel, `width` x `height`, through an orthographic pinhole
/// two units tall at (0, 0, `z`) looking at the origin, +y up: the test quads of the z = 0
/// plane seen square on from their front (z > 0) or their back.
pub fn orthographic_along_z(z: f32, width: u32, height: u32, spp: u32) -> Shot {
    let camera = CameraParams {
        eye: Vec3::new(0.0, 0.0, z),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: ProjectionParams::Orthographic { height: 2.0 },
        lens: LensParams::Pinhole,
        near: 0.1,
        far: 10.0,
        width,
        height,
        movements: Movements::NONE,
    }
    .build()
    .expect("valid camera");
    Shot {
        camera,
        render: settings(Shading::Unlit, spp),
    }
}
