//! Shared helpers of the GPU tests: opening the renderer (or skipping), validation checks,
//! small test scenes and cameras, image comparison with PNG output on failure.
//!
//! lensray-vulkan's tests use it as `mod support;`; the app's tests and benches include this
//! same file through theirs (crates/lensray/tests/gpu_support/mod.rs), which adds the helpers
//! that open the app's render paths.
#![allow(
    dead_code,
    reason = "each test binary includes this module and uses part of it"
)]

use std::path::PathBuf;

use glam::Vec3;
use lensray_core::camera::{Camera, CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::{Light, Material, Mesh, Scene};
use lensray_core::settings::{RenderSettings, Shading};
use lensray_vulkan::{GpuError, GpuOptions, GpuRenderer, Traversal, ValidationLog};

/// Opens the renderer with validation on. If that fails, the test fails, with one exception:
/// with `LENSRAY_SKIP_GPU_TESTS=1`, when the machine cannot run GPU tests at all (see
/// [`may_skip`]), the skip is recorded and this returns `None`.
pub fn renderer(test: &str) -> Option<(GpuRenderer, ValidationLog)> {
    renderer_with(test, &GpuOptions::default())
}

/// [`renderer`] with `options` (validation forced on).
pub fn renderer_with(test: &str, options: &GpuOptions) -> Option<(GpuRenderer, ValidationLog)> {
    match GpuRenderer::new(&GpuOptions {
        validate: true,
        ..*options
    }) {
        Ok(r) => {
            let log = r.validation_log();
            Some((r, log))
        }
        Err(e) if may_skip(&e) => {
            record_skip(test, &e.to_string());
            None
        }
        Err(e) => panic!(
            "{test}: cannot open a Vulkan device with ray queries and validation: {e}\n\
             (on a machine without one, LENSRAY_SKIP_GPU_TESTS=1 skips the GPU tests)"
        ),
    }
}

/// True when `LENSRAY_SKIP_GPU_TESTS=1` and `e` says the machine cannot run GPU tests at all:
/// no Vulkan loader or driver, no device with ray queries, or no validation layer. Any other
/// error (a pipeline bug, out of memory) fails the test whatever the variable says.
pub fn may_skip(e: &GpuError) -> bool {
    may_skip_when(
        std::env::var("LENSRAY_SKIP_GPU_TESTS").as_deref() == Ok("1"),
        e,
    )
}

/// [`may_skip`] with the variable's value given.
pub fn may_skip_when(skip_requested: bool, e: &GpuError) -> bool {
    skip_requested
        && matches!(
            e,
            GpuError::Loader(_)
                | GpuError::NoDriver
                | GpuError::NoRayQueryDevice(_)
                | GpuError::MissingLayer(_)
        )
}

/// A GPU command failed with `stderr`. With `LENSRAY_SKIP_GPU_TESTS=1` on a machine that cannot
/// run GPU tests (checked here by opening the device with validation, as the command does) the
/// skip is recorded; in every other case the test fails with the command's message.
pub fn skip_or_fail(test: &str, stderr: &str) {
    match GpuRenderer::new(&GpuOptions {
        validate: true,
        device_index: None,
        ..Default::default()
    }) {
        Err(e) if may_skip(&e) => record_skip(test, &e.to_string()),
        Err(e) => panic!("{test}: the GPU command failed: {stderr}(the device does not open: {e})"),
        Ok(_) => panic!("{test}: the GPU command failed although a device opens: {stderr}"),
    }
}

/// Records a skipped test: a line on stdout, and one in the file `LENSRAY_SKIP_LOG` names,
/// which scripts/test.sh counts and reports in its last lines.
pub fn record_skip(test: &str, reason: &str) {
    println!("SKIPPED {test}: {reason}");
    if let Ok(path) = std::env::var("LENSRAY_SKIP_LOG") {
        use std::io::Write;
        let line = format!("{test}\t{}\n", reason.replace(['\n', '\t'], " "));
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .and_then(|mut f| f.write_all(line.as_bytes()))
            .unwrap_or_else(|e| panic!("cannot record the skip in {path}: {e}"));
    }
}

/// The traversal the Vulkan device traces with by default (ray queries where it has them),
/// found by opening it and closing it with the validation check. `None` (skip recorded) where
/// the machine may skip GPU tests; any other failure fails the test.
pub fn default_traversal(test: &str) -> Option<Traversal> {
    let (renderer, _) = renderer(test)?;
    let traversal = renderer.traversal();
    renderer
        .close()
        .expect("close: validation messages or leaks");
    Some(traversal)
}

/// Fails on any validation warning or error recorded so far.
pub fn assert_no_validation_messages(log: &ValidationLog, when: &str) {
    let messages = log.messages();
    assert!(
        messages.is_empty(),
        "{} validation message(s) {when}:\n{}",
        messages.len(),
        messages.join("\n")
    );
}

/// Closes the renderer, which destroys every object and fails on any validation message, the
/// leak report at shutdown included; then checks the log once more.
pub fn finish(renderer: GpuRenderer, log: ValidationLog) {
    assert_no_validation_messages(&log, "while rendering");
    if let Err(e) = renderer.close() {
        panic!("closing the renderer: {e}");
    }
    assert!(
        log.instance_destroyed(),
        "the Vulkan instance outlived the renderer: some GPU object leaked"
    );
    assert_no_validation_messages(&log, "after the renderer was dropped");
}

pub fn material(name: &str, diffuse: Vec3, emission: Vec3) -> Material {
    Material {
        name: name.into(),
        diffuse,
        emission,
        ..Default::default()
    }
}

/// An axis-aligned box, 12 triangles, no vertex normals.
pub fn cuboid(min: Vec3, max: Vec3, material: u32) -> Mesh {
    let corners: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        })
        .collect();
    let faces = [
        [0, 2, 6, 4],
        [1, 5, 7, 3],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 6, 7, 5],
    ];
    let triangles: Vec<[u32; 3]> = faces
        .iter()
        .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
        .collect();
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "box".into(),
        positions: corners,
        normals: vec![],
        material_ids: vec![material; triangles.len()],
        triangles,
        ..Default::default()
    }
}

/// A horizontal quad at height y.
pub fn floor(half: f32, y: f32, material: u32) -> Mesh {
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "floor".into(),
        positions: vec![
            Vec3::new(-half, y, -half),
            Vec3::new(half, y, -half),
            Vec3::new(half, y, half),
            Vec3::new(-half, y, half),
        ],
        normals: vec![],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![material; 2],
        ..Default::default()
    }
}

/// A UV sphere with vertex normals (the scene generators' own).
pub fn sphere(center: Vec3, radius: f32, rings: u32, segments: u32, material: u32) -> Mesh {
    lensray_core::scene::generate::uv_sphere("sphere", center, radius, segments, rings, material)
}

/// A floor, a box, a sphere with vertex normals and a small emissive box: 4 meshes.
pub fn test_scene() -> Scene {
    Scene {
        meshes: vec![
            floor(4.0, 0.0, 0),
            cuboid(Vec3::new(-1.6, 0.0, -0.8), Vec3::new(-0.4, 1.2, 0.4), 1),
            sphere(Vec3::new(0.8, 0.7, 0.3), 0.7, 16, 24, 2),
            cuboid(Vec3::new(1.0, 0.0, -2.2), Vec3::new(1.6, 0.4, -1.6), 3),
        ],
        materials: vec![
            material("floor", Vec3::new(0.7, 0.7, 0.65), Vec3::ZERO),
            material("red", Vec3::new(0.8, 0.15, 0.1), Vec3::ZERO),
            material("blue", Vec3::new(0.1, 0.3, 0.85), Vec3::ZERO),
            material("lamp", Vec3::new(0.9, 0.8, 0.2), Vec3::new(0.5, 0.4, 0.1)),
        ],
        lights: vec![TEST_LIGHT],
        ..Default::default()
    }
}

/// The test scene's light.
pub const TEST_LIGHT: Light = Light::point(Vec3::new(2.0, 4.0, 3.0), Vec3::new(30.0, 28.0, 25.0));

pub const BACKGROUND: Vec3 = Vec3::new(0.05, 0.1, 0.2);

/// An aperture image of odd size (the table searches' steps do not divide it) with a
/// gradient, a hole and an empty row; turned and squeezed.
pub fn odd_aperture_image() -> lensray_core::camera::ApertureShape {
    let (columns, rows) = (37u32, 23u32);
    let values: Vec<f32> = (0..columns * rows)
        .map(|i| {
            let (x, y) = (i % columns, i / columns);
            if y == 3 || (10..14).contains(&x) && (8..12).contains(&y) {
                0.0
            } else {
                0.05 + (x * y) as f32 / (columns * rows) as f32
            }
        })
        .collect();
    lensray_core::camera::ApertureShape {
        rotation_degrees: 20.0,
        aspect: 1.3,
        image: Some(std::sync::Arc::new(
            lensray_core::camera::aperture::ApertureImage::new(columns, rows, &values)
                .expect("an aperture image"),
        )),
        ..lensray_core::camera::ApertureShape::ROUND
    }
}

pub fn camera(orthographic: bool, lens: LensParams, width: u32, height: u32) -> Camera {
    moved_camera(orthographic, lens, width, height, Movements::NONE)
}

/// The shift and tilt of the moved test shots: the window off the axis up and right, the
/// plane of focus turned 25 degrees toward the lower left (a thin lens in world units turns
/// the plane itself).
pub const MOVED: Movements = Movements {
    shift: [0.12, 0.08],
    tilt_degrees: 25.0,
    tilt_direction_degrees: 30.0,
};

/// [`camera`] with `movements`.
pub fn moved_camera(
    orthographic: bool,
    lens: LensParams,
    width: u32,
    height: u32,
    movements: Movements,
) -> Camera {
    CameraParams {
        eye: Vec3::new(2.5, 2.2, 4.5),
        target: Vec3::new(0.0, 0.5, 0.0),
        up: Vec3::Y,
        projection: if orthographic {
            ProjectionParams::Orthographic { height: 4.0 }
        } else {
            ProjectionParams::Perspective { vfov_degrees: 45.0 }
        },
        lens,
        near: 0.5,
        far: 50.0,
        width,
        height,
        movements,
    }
    .build()
    .expect("valid test camera")
}

pub fn settings(shading: Shading, spp: u32) -> RenderSettings {
    RenderSettings {
        spp,
        seed: 7,
        sampler: SamplerKind::default(),
        shading,
        background: BACKGROUND,
        environment: Vec3::ZERO,
        shared_samples: false,
        noise_threshold: None,
        environment_seen: false,
        bounces: 1,
    }
}

/// Statistics of |a - b| per channel.
#[derive(Debug)]
pub struct Diff {
    pub within: f64,
    pub mean_abs: f64,
    pub max_abs: f32,
}

pub fn compare(a: &Image, b: &Image, tolerance: f32) -> Diff {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let mut within = 0usize;
    let mut sum = 0.0f64;
    let mut max_abs = 0.0f32;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let d = (*p - *q).abs();
        if d.max_element() <= tolerance {
            within += 1;
        }
        sum += f64::from(d.x + d.y + d.z) / 3.0;
        max_abs = max_abs.max(d.max_element());
    }
    let n = a.pixels.len() as f64;
    Diff {
        within: within as f64 / n,
        mean_abs: sum / n,
        max_abs,
    }
}

/// target/test-output of the workspace: the crate that includes this file (lensray-vulkan or
/// the app) lies two folders below the workspace's root.
pub fn output_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/test-output");
    std::fs::create_dir_all(&dir).expect("create target/test-output");
    dir
}

/// Writes an image as an sRGB PNG under target/test-output.
pub fn write_png(image: &Image, name: &str) -> PathBuf {
    let path = output_dir().join(name);
    // The encoding lensray's own PNGs use (sRGB, 8 bits).
    let bytes = lensray_core::film::colour::to_display_bytes(image, Shading::Unlit);
    image::RgbImage::from_raw(image.width, image.height, bytes)
        .expect("3 bytes per pixel")
        .save(&path)
        .expect("write PNG");
    path
}

/// Writes both images and |a - b| (scaled x16) as PNGs; returns their paths for messages.
pub fn write_comparison(a: &Image, b: &Image, name: &str) -> String {
    let diff = Image {
        width: a.width,
        height: a.height,
        pixels: a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(p, q)| (*p - *q).abs() * 16.0)
            .collect(),
    };
    let paths = [
        write_png(a, &format!("{name}-gpu.png")),
        write_png(b, &format!("{name}-cpu.png")),
        write_png(&diff, &format!("{name}-diff.png")),
    ];
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
