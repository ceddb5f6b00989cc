//! Aperture shapes as a camera shows them, on the CPU reference: a small
//! out-of-focus point images as the aperture scaled by its circle of confusion, turned by 180
//! degrees in front of the focal plane; roundness 1 is the round aperture exactly.

use glam::{Vec2, Vec3};
use lensray_core::camera::aperture::ApertureImage;
use lensray_core::camera::{ApertureShape, Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::{Material, Scene};
use lensray_core::settings::{RenderSettings, Shading, Shot};

const SIZE: u32 = 96;
const FOCUS: f32 = 5.0;

/// Camera at the origin looking along world -z: camera +x is world +x, camera +y world +y.
fn camera(aperture_radius: f32, shape: ApertureShape) -> Camera {
    CameraParams {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 40.0 },
        lens: LensParams::ThinLens {
            aperture_radius: f64::from(aperture_radius),
            focus_distance: f64::from(FOCUS),
        },
        near: 0.01,
        far: 100.0,
        width: SIZE,
        height: SIZE,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera")
    .with_aperture(shape.build().expect("valid aperture"))
    .expect("a thin lens takes any aperture")
}

fn settings(spp: u32) -> RenderSettings {
    RenderSettings {
        spp,
        seed: 3,
        sampler: SamplerKind::default(),
        shading: Shading::Unlit,
        background: Vec3::ZERO,
        environment: Vec3::ZERO,
        shared_samples: false,
        noise_threshold: None,
        environment_seen: false,
        bounces: 1,
    }
}

/// A small white sphere on the view axis at depth `z`.
fn point_scene(z: f32, radius: f32) -> Scene {
    Scene {
        meshes: vec![lensray_core::scene::generate::uv_sphere(
            "point",
            Vec3::new(0.0, 0.0, -z),
            radius,
            24,
            12,
            0,
        )],
        materials: vec![Material {
            name: "white".into(),
            diffuse: Vec3::ONE,
            emission: Vec3::ZERO,
            ..Default::default()
        }],
        ..Default::default()
    }
}

/// Whether the unit-shape point `q` (aspect applied) lies in `camera`'s aperture.
fn in_shape(camera: &Camera, q: Vec2) -> bool {
    let aperture = &camera.lens.first_order().aperture;
    let q = Vec2::new(q.x, q.y / aperture.shape.aspect);
    if let Some(image) = aperture.image() {
        // Turned back into the image's square.
        let c = aperture.turn();
        let p = Vec2::new(c.x * q.x + c.y * q.y, -c.y * q.x + c.x * q.y);
        if p.x.abs() > 1.0 || p.y.abs() > 1.0 {
            return false;
        }
        let (column, row) = image.cell_of(p);
        return image.transmission()[(row * image.columns() + column) as usize] > 0.0;
    }
    let fan = aperture.fan();
    if fan.is_empty() {
        return q.length() <= 1.0;
    }
    (0..fan.len()).all(|i| (fan[(i + 1) % fan.len()] - fan[i]).perp_dot(q - fan[i]) >= 0.0)
}

/// The share of the image's light that falls inside the analytic footprint of a point on the
/// axis at depth `z`: the film point at screen position s sees the point through lens point
/// L = (s - p / z) / (1 / F - 1 / z) (p = 0 here), so the footprint is the aperture scaled by
/// A (1 / F - 1 / z): upright beyond the focal plane, turned in front of it. `turned` tests the
/// other orientation instead.
fn share_inside(image: &Image, camera: &Camera, z: f32, turned: bool) -> f64 {
    let scale = 1.0 / FOCUS - 1.0 / z;
    let (mut inside, mut total) = (0.0f64, 0.0f64);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let value = f64::from(image.pixels[(y * SIZE + x) as usize].x);
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let screen = camera
                .screen_from_raster
                .transform_point3(centre.extend(0.0));
            let mut lens =
                Vec2::new(screen.x, screen.y) / (scale * camera.lens.first_order().aperture_radius);
            if turned {
                lens = -lens;
            }
            total += value;
            if in_shape(camera, lens) {
                inside += value;
            }
        }
    }
    inside / total.max(1e-30)
}

/// A pentagon (vertex up) and a curved, squeezed heptagon, behind and in front of the focal
/// plane: at least 95 % of the light falls inside the aperture's analytic footprint in the
/// stated orientation. For the pentagon, clearly less falls inside the other orientation (a
/// pentagon and its half turn share 81 % of their area; a curved heptagon and its half turn
/// are too alike to tell apart).
#[test]
fn an_out_of_focus_point_images_as_the_aperture_turned_in_front_of_the_focus() {
    let pentagon = ApertureShape {
        blades: Some(5),
        rotation_degrees: 90.0,
        ..ApertureShape::ROUND
    };
    let heptagon = ApertureShape {
        blades: Some(7),
        rotation_degrees: 10.0,
        roundness: 0.5,
        aspect: 1.5,
        ..ApertureShape::ROUND
    };
    // (shape, depth, point radius): the circle of confusion is ~30 px wide in each case, the
    // point's own image under 2 px.
    let cases = [
        (pentagon.clone(), 10.0, 0.05),
        (pentagon.clone(), 2.5, 0.02),
        (heptagon.clone(), 10.0, 0.05),
        (heptagon, 2.5, 0.02),
    ];
    for (shape, z, radius) in cases {
        let tells_turns = shape == pentagon;
        let pixels_per_unit = SIZE as f32 / (2.0 * 20f32.to_radians().tan());
        let reach = shape.aspect.max(1.0);
        let aperture_radius = 30.0 / ((1.0 / FOCUS - 1.0 / z).abs() * pixels_per_unit * reach);
        let shot = Shot {
            camera: camera(aperture_radius, shape.clone()),
            render: settings(1024),
        };
        let renderer = Renderer::new(&point_scene(z, radius));
        let (image, _) = renderer.render(&shot, &mut |_, _| {});
        let upright = share_inside(&image, &shot.camera, z, false);
        let turned = share_inside(&image, &shot.camera, z, true);
        println!("{shape:?} at z = {z}: {upright:.3} inside, {turned:.3} inside when turned");
        assert!(
            upright >= 0.95 && (!tells_turns || turned <= upright - 0.05),
            "{shape:?} at z = {z}: {upright:.3} of the light inside the footprint, {turned:.3} \
             inside the footprint turned by 180 degrees"
        );
    }
}

/// Roundness 1 is the round aperture, whatever the blades and rotation: the same image.
#[test]
fn roundness_one_renders_the_round_aperture() {
    let scene = point_scene(10.0, 0.3);
    let renderer = Renderer::new(&scene);
    let round = Shot {
        camera: camera(1.0, ApertureShape::ROUND),
        render: settings(16),
    };
    let curved = Shot {
        camera: camera(
            1.0,
            ApertureShape {
                blades: Some(6),
                rotation_degrees: 25.0,
                roundness: 1.0,
                ..ApertureShape::ROUND
            },
        ),
        render: settings(16),
    };
    let (a, _) = renderer.render(&round, &mut |_, _| {});
    let (b, _) = renderer.render(&curved, &mut |_, _| {});
    assert!(a.pixels.iter().any(|p| p.x > 0.0));
    assert_eq!(a, b, "roundness 1 must render the round aperture");
}

/// The letter F as a 5 x 7 mask (top row first): neither a half turn nor a mirror maps it
/// onto itself.
fn letter_f() -> ApertureShape {
    const ROWS: [&str; 7] = [
        "#####", "#....", "#....", "####.", "#....", "#....", "#....",
    ];
    let values: Vec<f32> = ROWS
        .iter()
        .flat_map(|row| row.chars().map(|c| if c == '#' { 1.0 } else { 0.0 }))
        .collect();
    ApertureShape {
        rotation_degrees: 10.0,
        image: Some(std::sync::Arc::new(
            ApertureImage::new(5, 7, &values).expect("an aperture image"),
        )),
        ..ApertureShape::ROUND
    }
}

/// An aperture image: an out-of-focus point images as the mask (the letter F, turned by 10
/// degrees), upright beyond the focal plane and turned by 180 degrees in front of it. The
/// mask's cells are 6 px at this blur, so the point's own 2 px image spills over their edges
/// more than over a polygon's: at least 85 % falls inside, and at most half as much inside the
/// other orientation.
#[test]
fn an_out_of_focus_point_images_as_the_aperture_image() {
    let shape = letter_f();
    for (z, radius) in [(10.0f32, 0.05f32), (2.5, 0.02)] {
        let pixels_per_unit = SIZE as f32 / (2.0 * 20f32.to_radians().tan());
        // The image's square is 2 aperture radii wide: 42 px here.
        let aperture_radius = 21.0 / ((1.0 / FOCUS - 1.0 / z).abs() * pixels_per_unit);
        let shot = Shot {
            camera: camera(aperture_radius, shape.clone()),
            render: settings(1024),
        };
        let renderer = Renderer::new(&point_scene(z, radius));
        let (image, _) = renderer.render(&shot, &mut |_, _| {});
        let upright = share_inside(&image, &shot.camera, z, false);
        let turned = share_inside(&image, &shot.camera, z, true);
        println!("letter F at z = {z}: {upright:.3} inside, {turned:.3} inside when turned");
        assert!(
            upright >= 0.85 && turned <= 0.5 * upright,
            "letter F at z = {z}: {upright:.3} of the light inside the footprint, {turned:.3} \
             inside the footprint turned by 180 degrees"
        );
    }
}
