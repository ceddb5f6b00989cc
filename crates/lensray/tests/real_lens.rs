//! Real lenses on the CPU reference renderer, against answers found without the
//! code under test: a thin singlet blurs as the thin lens does, every built-in lens images an
//! edge at its focus distance sharply, off-axis bokeh is cut to a cat-eye wide open (and
//! checked against rays traced forward from the emitter), the images' fall-off is the
//! irradiance integrated over the rear element's plane, dispersion puts colour where the
//! optics traced at each wavelength put it, and bad `--lens` options get one line.
//!
//! Camera set-up everywhere: the eye (the lens's entrance pupil) at the origin looking along
//! world -z, so camera +x is world +x and camera +y world +y; a view depth z is world -z.
//! Images are saved under target/test-output when a test fails.
//!
//! Run with `cargo test --test real_lens`.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use lensray_core::camera::RealLensParams;
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams, RealLens};
use lensray_core::film::colour::linear_to_srgb;
use lensray_core::film::Image;
use lensray_core::optics::{builtin, Prescription};
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::{Material, Mesh};
use lensray_core::settings::{RenderSettings, Shading};

// The edge fit that lensray-core's tests use too: one copy.
#[path = "../../lensray-core/tests/edge_fit/mod.rs"]
mod edge_fit;

#[path = "real_lens/bokeh.rs"]
mod bokeh;
#[path = "real_lens/colour.rs"]
mod colour;
#[path = "real_lens/edges.rs"]
mod edges;
#[path = "real_lens/fall_off.rs"]
mod fall_off;
#[path = "real_lens/options.rs"]
mod options;
#[path = "real_lens/spot.rs"]
mod spot;
#[path = "real_lens/tilt.rs"]
mod tilt;

/// An axis-aligned quad in the plane z = `z`, covering [x0, x1] x [y0, y1].
fn quad(x0: f32, x1: f32, y0: f32, y1: f32, z: f32, material: u32) -> Mesh {
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "quad".into(),
        positions: vec![
            Vec3::new(x0, y0, z),
            Vec3::new(x1, y0, z),
            Vec3::new(x1, y1, z),
            Vec3::new(x0, y1, z),
        ],
        normals: vec![],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![material; 2],
        ..Default::default()
    }
}

/// `Shading::Unlit` shows a material's diffuse colour: the quads below are emitters of it.
fn material(name: &str, diffuse: Vec3) -> Material {
    Material {
        name: name.into(),
        diffuse,
        emission: Vec3::ZERO,
        ..Default::default()
    }
}

fn camera(width: u32, height: u32, lens: LensParams) -> Camera {
    moved_camera(width, height, lens, lensray_core::camera::Movements::NONE)
}

/// [`camera`] with shift and tilt.
fn moved_camera(
    width: u32,
    height: u32,
    lens: LensParams,
    movements: lensray_core::camera::Movements,
) -> Camera {
    CameraParams {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        // A real or physical lens replaces it with its own field of view.
        projection: ProjectionParams::Perspective { vfov_degrees: 40.0 },
        lens,
        near: 0.001,
        far: 1000.0,
        width,
        height,
        movements,
    }
    .build()
    .expect("valid camera")
}

fn real(lens: &Arc<Prescription>, f_number: Option<f64>, focus: f64, sensor: f64) -> LensParams {
    LensParams::Real(RealLensParams {
        prescription: lens.clone(),
        f_number,
        focus_distance: focus,
        sensor_height_mm: sensor,
        // These tests check the geometry and radiometry at the d line; tests/real_lens/colour.rs
        // renders dispersion.
        dispersion: false,
        movements: lensray_core::camera::Movements::NONE,
    })
}

fn real_lens(camera: &Camera) -> &RealLens {
    camera.lens.real().expect("a real-lens camera")
}

fn builtin_lens(name: &str) -> Arc<Prescription> {
    Arc::new(builtin::lens(name).expect("a built-in lens"))
}

fn settings(spp: u32, seed: u32, background: Vec3) -> RenderSettings {
    RenderSettings {
        spp,
        seed,
        sampler: SamplerKind::Sobol,
        shading: Shading::Unlit,
        background,
        environment: Vec3::ZERO,
        shared_samples: false,
        noise_threshold: None,
        environment_seen: false,
        bounces: 1,
    }
}

/// Writes an image, scaled by `scale`, as an sRGB PNG under target/test-output.
fn write_png(image: &Image, name: &str, scale: f32) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/test-output");
    std::fs::create_dir_all(&dir).expect("create target/test-output");
    let path = dir.join(name);
    let encode = |v: f32| (linear_to_srgb(v * scale).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    let mut buf = image::RgbImage::new(image.width, image.height);
    for (i, p) in image.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        buf.put_pixel(x, y, image::Rgb([encode(p.x), encode(p.y), encode(p.z)]));
    }
    buf.save(&path).expect("write PNG");
    path
}

/// `x < bound`; false for NaN, so a check written `!below(..)` fails on NaN.
fn below(x: f64, bound: f64) -> bool {
    x < bound
}

/// `x > bound`; false for NaN.
fn above(x: f64, bound: f64) -> bool {
    x > bound
}
