//! Shadow rays: a square occluder between a wall and a point light casts the analytic shadow.
//!
//! The camera looks along -z at a wall z = WALL; a square occluder [-H, H]^2 at z = OCC sits
//! between the wall and a point light up and to the right, so the shadow falls down and to the
//! left of where the occluder itself is seen. Wall: red emission plus a grey diffuse term;
//! occluder: black (an emissive occluder would light the wall). Each of the three cases has
//! its own value.

use std::path::PathBuf;

use glam::Vec3;
use lensray_core::camera::LensParams;
use lensray_core::film::colour::linear_to_srgb;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::scene::{Light, Scene};
use lensray_core::settings::{Shading, Shot};

use crate::{camera, material, quad, settings};

/// The wall's plane, world z.
const WALL: f32 = -4.0;
/// The occluder's plane, world z.
const OCC: f32 = -2.5;
/// Half the occluder's side.
const H: f32 = 0.2;
/// The point light, up and to the right of the occluder.
const LIGHT: Vec3 = Vec3::new(0.8, 0.3, -1.0);
/// The wall's emission: all a shadowed wall pixel shows.
const WALL_EMISSION: Vec3 = Vec3::new(0.05, 0.0, 0.0);
/// What an occluder pixel shows: it neither emits nor reflects.
const OCCLUDER_EMISSION: Vec3 = Vec3::ZERO;

/// Writes an image as an sRGB PNG under target/test-output (for a failing test to show).
fn write_png(image: &Image, name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/test-output");
    std::fs::create_dir_all(&dir).expect("create target/test-output");
    let path = dir.join(name);
    let encode = |v: f32| (linear_to_srgb(v).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    let mut buf = image::RgbImage::new(image.width, image.height);
    for (i, p) in image.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        buf.put_pixel(x, y, image::Rgb([encode(p.x), encode(p.y), encode(p.z)]));
    }
    buf.save(&path).expect("write PNG");
    path
}

/// What a pixel of the shadow scene shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Seen {
    Occluder,
    LitWall,
    ShadowedWall,
    /// Anything else (only ever a rendered value).
    Other,
}

/// The wall and the occluder, lit, through a pinhole camera of `width` x `height` pixels.
fn render_shadow_scene(width: u32, height: u32) -> Image {
    let scene = Scene {
        meshes: vec![
            quad(-50.0, 50.0, -50.0, 50.0, WALL, 0),
            quad(-H, H, -H, H, OCC, 1),
        ],
        materials: vec![
            material("wall", Vec3::splat(0.8), WALL_EMISSION),
            material("occluder", Vec3::ZERO, OCCLUDER_EMISSION),
        ],
        lights: vec![Light::point(LIGHT, Vec3::splat(10.0))],
        ..Default::default()
    };
    let s = settings(Shading::Lit, 1);
    let shot = Shot {
        camera: camera(width, height, LensParams::Pinhole),
        render: s,
    };
    let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    image
}

/// The analytic class of the ray through a raster point, written out independently of the
/// camera module: vfov 40 degrees, square pixels, row 0 at the top, camera +x = world +x.
fn analytic_seen(width: u32, height: u32, col: u32, row: u32) -> Seen {
    let half_height = (20.0f32).to_radians().tan();
    let pixel_size = 2.0 * half_height / height as f32;
    let inside = |p: Vec3| p.x.abs() < H && p.y.abs() < H;
    let dir = Vec3::new(
        (col as f32 + 0.5 - width as f32 / 2.0) * pixel_size,
        (height as f32 / 2.0 - row as f32 - 0.5) * pixel_size,
        -1.0,
    );
    if inside(dir * (OCC / dir.z)) {
        return Seen::Occluder;
    }
    let p = dir * (WALL / dir.z);
    // The segment from the wall point to the light crosses the occluder's plane here.
    let q = p + (LIGHT - p) * ((OCC - WALL) / (LIGHT.z - WALL));
    if inside(q) {
        Seen::ShadowedWall
    } else {
        Seen::LitWall
    }
}

/// The class the render shows at a pixel, told apart by the values each case has.
fn rendered_seen(image: &Image, col: u32, row: u32) -> Seen {
    let c = image.get(col, row);
    if c == OCCLUDER_EMISSION {
        Seen::Occluder
    } else if c == WALL_EMISSION {
        Seen::ShadowedWall
    } else if c.x > WALL_EMISSION.x && c.y > 0.0 && c.z > 0.0 {
        Seen::LitWall
    } else {
        Seen::Other
    }
}

/// The pixels where the rendered class differs from the analytic one, and how many were
/// checked. Film samples are jittered inside the pixel: only pixels whose 3x3 neighbourhood is
/// all of one class are sure to be that class (every boundary here is an axis-aligned line).
fn class_mismatches(
    width: u32,
    height: u32,
    analytic: &dyn Fn(u32, u32) -> Seen,
    rendered: &dyn Fn(u32, u32) -> Seen,
) -> (Vec<String>, usize) {
    let mut mismatches = Vec::new();
    let mut checked = 0;
    for row in 1..height - 1 {
        for col in 1..width - 1 {
            let class = analytic(col, row);
            let uniform =
                (row - 1..=row + 1).all(|r| (col - 1..=col + 1).all(|c| analytic(c, r) == class));
            if uniform {
                checked += 1;
                let got = rendered(col, row);
                if got != class {
                    mismatches.push(format!("({col},{row}): expected {class:?}, got {got:?}"));
                }
            }
        }
    }
    (mismatches, checked)
}

/// The bounding box (min col, min row, max col, max row) of the pixels `class_of` calls a
/// shadowed wall.
fn shadow_box(width: u32, height: u32, class_of: &dyn Fn(u32, u32) -> Seen) -> [u32; 4] {
    let mut b = [u32::MAX, u32::MAX, 0, 0];
    for row in 0..height {
        for col in 0..width {
            if class_of(col, row) == Seen::ShadowedWall {
                b = [b[0].min(col), b[1].min(row), b[2].max(col), b[3].max(row)];
            }
        }
    }
    b
}

#[test]
fn shadow_ray_blocks_the_light() {
    let (width, height) = (128u32, 96u32);
    let image = render_shadow_scene(width, height);
    let analytic = |col: u32, row: u32| analytic_seen(width, height, col, row);
    let rendered = |col: u32, row: u32| rendered_seen(&image, col, row);

    let (mismatches, checked) = class_mismatches(width, height, &analytic, &rendered);
    let expected_box = shadow_box(width, height, &analytic);
    let rendered_box = shadow_box(width, height, &rendered);
    let box_differs = expected_box
        .iter()
        .zip(&rendered_box)
        .any(|(a, b)| a.abs_diff(*b) > 1);
    let shadowed = (0..height)
        .flat_map(|r| (0..width).map(move |c| (c, r)))
        .filter(|&(c, r)| analytic(c, r) == Seen::ShadowedWall)
        .count();
    if !mismatches.is_empty() || box_differs {
        let png = write_png(&image, "shadow.png");
        panic!(
            "{} of {checked} pixels differ from the analytic shadow: {}\n\
             shadow box (min col, min row, max col, max row): analytic {expected_box:?}, \
             rendered {rendered_box:?}; image: {}",
            mismatches.len(),
            mismatches.join(", "),
            png.display()
        );
    }
    // Test set-up: a shadow of many pixels, displaced from the occluder, with plenty checked.
    assert!(
        shadowed > 100,
        "only {shadowed} pixels in the analytic shadow"
    );
    assert!(
        checked > (width * height / 2) as usize,
        "only {checked} pixels checked"
    );
}
