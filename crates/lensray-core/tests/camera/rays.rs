//! 3. Pinhole rays agree with the projection matrices; 4. image orientation.

use glam::{Vec2, Vec3};
use lensray_core::camera::{CameraParams, LensParams, ProjectionParams, Ray};

use crate::common::*;
use crate::round_trip::unproject;
use lensray_core::sampler::CameraSample;

/// Pixels to visit: every pixel of small images, a stride (plus the last row and column) of
/// larger ones.
fn pixels(width: u32, height: u32) -> Vec<(u32, u32)> {
    let stride = |n: u32| (n / 24).max(1);
    let mut rows: Vec<u32> = (0..height).step_by(stride(height) as usize).collect();
    let mut cols: Vec<u32> = (0..width).step_by(stride(width) as usize).collect();
    rows.push(height - 1);
    cols.push(width - 1);
    rows.dedup();
    cols.dedup();
    rows.iter()
        .flat_map(|&i| cols.iter().map(move |&j| (i, j)))
        .collect()
}

/// The pinhole ray through the centre of pixel (row i, column j) passes through every world
/// point that the projection chain maps to raster (j + 0.5, i + 0.5), at any depth.
#[test]
fn pinhole_ray_through_pixel_centre_hits_unprojected_points() {
    let mut rng = Rng::new(20);
    for setup in setups() {
        let setup = setup.with_lens(LensParams::Pinhole);
        let cam = setup.camera();
        let r = setup.reference();
        let name = setup.name;
        for (i, j) in pixels(cam.width, cam.height) {
            let centre = Vec2::new(j as f32 + 0.5, i as f32 + 0.5);
            // Aperture 0: the lens sample must not matter.
            let ray = cam.first_order_ray(CameraSample::new(centre, rng.vec2()));
            let other = cam.first_order_ray(CameraSample::new(centre, rng.vec2()));
            assert_eq!(ray, other, "{name}: pinhole ray depends on the lens sample");
            // The camera-space pinhole ray, moved to world space by hand.
            let camera_ray = cam.pinhole_ray(centre);
            let by_hand = Ray {
                origin: cam.world_from_camera.transform_point3(camera_ray.origin),
                direction: cam
                    .world_from_camera
                    .transform_vector3(camera_ray.direction),
            };
            assert_close(
                &format!("{name}: |direction| of ray through {centre:?}"),
                ray.direction.length() as f64,
                1.0,
                1e-6,
            );

            for depth in [0.0, 0.25, 0.5, 0.9, 1.0] {
                let p = unproject(&cam, centre.extend(depth));
                let pd = p.as_dvec3();
                // Self-check: the chain really maps p to the pixel centre.
                let back = cam.project(p);
                // Unprojected then projected: two passes of f32 rounding.
                let px_tol = 2.0 * r.raster_tolerance(pd).0;
                let off = (back.truncate() - centre).abs().max_element() as f64;
                assert!(
                    off <= px_tol,
                    "{name}: unprojected point {p:?} projects to {back:?}, not {centre:?} \
                     ({off:.3e} px off, tolerance {px_tol:.3e})"
                );
                let scale = (pd - r.eye).length();
                for (which, ray) in [("first_order_ray", &ray), ("pinhole_ray", &by_hand)] {
                    let (dist, t) = ray_distance(ray, pd);
                    assert!(
                        dist <= 1e-5 * scale,
                        "{name}: {which} through pixel centre {centre:?} misses the point \
                         {p:?} (depth {depth}) by {dist:.3e} = {:.3e} relative to its distance \
                         {scale} from the eye (tolerance 1e-5)\nray {ray:?}",
                        dist / scale
                    );
                    assert!(
                        t >= -1e-5 * scale,
                        "{name}: {which}: point {p:?} at depth {depth} lies behind the ray \
                         origin (t = {t})"
                    );
                }
            }
        }
    }
}

/// Perspective rays start at the eye; orthographic rays start on the near plane and run along
/// the view axis; both start where the projection puts depth 0 (orthographic) or at the centre
/// of projection (perspective).
#[test]
fn pinhole_ray_origin_and_direction_follow_the_model() {
    let mut rng = Rng::new(21);
    for setup in setups() {
        let setup = setup.with_lens(LensParams::Pinhole);
        let cam = setup.camera();
        let r = setup.reference();
        let name = setup.name;
        for _ in 0..200 {
            let film = Vec2::new(
                rng.range(0.0, r.width) as f32,
                rng.range(0.0, r.height) as f32,
            );
            let ray = cam.first_order_ray(CameraSample::new(film, Vec2::splat(0.5)));
            let o = ray.origin.as_dvec3();
            let d = ray.direction.as_dvec3();
            if setup.is_orthographic() {
                assert_close(
                    &format!("{name}: orthographic ray origin's view depth (near plane)"),
                    r.camera_coords(o).z,
                    r.near,
                    2e-6 * (o - r.eye).length(),
                );
                assert_vec_close(
                    &format!("{name}: orthographic ray direction (forward)"),
                    d,
                    r.forward,
                    1e-6,
                );
                let start = unproject(&cam, film.extend(0.0)).as_dvec3();
                assert_vec_close(
                    &format!("{name}: orthographic ray through {film:?} starts at depth 0"),
                    o,
                    start,
                    4e-6 * (start - r.eye).length().max(1.0),
                );
            } else {
                assert_vec_close(
                    &format!("{name}: perspective ray origin (eye)"),
                    o,
                    r.eye,
                    1e-6 * r.eye.length().max(1.0),
                );
                // Direction against the f64 reference: normalize(x_s, y_s, 1) in camera space.
                let expected = (r.world_from_camera_coords(r.pinhole_point_camera(
                    film.x as f64,
                    film.y as f64,
                    1.0,
                )) - r.eye)
                    .normalize();
                assert_vec_close(
                    &format!("{name}: perspective ray direction through {film:?}"),
                    d,
                    expected,
                    2e-6,
                );
            }
        }
    }
}

/// A camera neither axis-aligned nor level: eye, target and up all oblique.
fn oblique(projection: ProjectionParams) -> CameraParams {
    CameraParams {
        eye: Vec3::new(2.0, 1.5, -3.0),
        target: Vec3::new(-1.0, 0.2, 4.0),
        up: Vec3::new(0.1, 1.0, 0.2),
        projection,
        lens: LensParams::Pinhole,
        near: 0.1,
        far: 100.0,
        width: 200,
        height: 100,
        movements: lensray_core::camera::Movements::NONE,
    }
}

/// Points to the right of the camera (along cross(forward, up)) land in the right half of the
/// image; points above (along the user's up) in the top rows; and rays through the left/top of
/// the image point left/up. Also the plain case a human can picture: looking down -z with +y up,
/// +x is on the right.
#[test]
fn image_orientation() {
    let perspective = ProjectionParams::Perspective { vfov_degrees: 50.0 };
    let orthographic = ProjectionParams::Orthographic { height: 3.0 };
    let level = |projection| CameraParams {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        ..oblique(projection)
    };
    let cases = [
        ("oblique perspective", oblique(perspective)),
        ("oblique orthographic", oblique(orthographic)),
        ("level perspective looking down -z", level(perspective)),
        ("level orthographic looking down -z", level(orthographic)),
    ];
    for (name, params) in cases {
        let cam = params.build().unwrap();
        let (w, h) = (params.width as f32, params.height as f32);
        let eye = params.eye;
        let forward = (params.target - params.eye).normalize();
        // Independent of the code's frame: right from the stated formula, up as the user gave it.
        let right = forward.cross(params.up).normalize();
        let up = params.up.normalize();
        if name.starts_with("level") {
            assert!(
                (right - Vec3::X).length() < 1e-6,
                "{name}: right is {right:?}, expected +x"
            );
        }
        let centre = eye + 5.0 * forward;
        let on_axis = cam.project(centre);
        assert!(
            (on_axis.x - w / 2.0).abs() < 1e-3 && (on_axis.y - h / 2.0).abs() < 1e-3,
            "{name}: the view axis projects to {on_axis:?}, not the image centre ({}, {})",
            w / 2.0,
            h / 2.0
        );
        let to_right = cam.project(centre + 0.5 * right);
        assert!(
            to_right.x > w / 2.0 + 1.0 && (to_right.y - h / 2.0).abs() < 1e-2,
            "{name}: a point to the right projects to {to_right:?}: expected column > {} on row {}",
            w / 2.0,
            h / 2.0
        );
        let to_left = cam.project(centre - 0.5 * right);
        assert!(
            to_left.x < w / 2.0 - 1.0,
            "{name}: a point to the left projects to {to_left:?}: expected column < {}",
            w / 2.0
        );
        let above = cam.project(centre + 0.5 * up);
        assert!(
            above.y < h / 2.0 - 1.0,
            "{name}: a point above projects to {above:?}: expected row < {} (row 0 is the top)",
            h / 2.0
        );
        let below = cam.project(centre - 0.5 * up);
        assert!(
            below.y > h / 2.0 + 1.0,
            "{name}: a point below projects to {below:?}: expected row > {}",
            h / 2.0
        );
        // Rays through the top-left and bottom-right pixels.
        let top_left =
            cam.first_order_ray(CameraSample::new(Vec2::new(0.5, 0.5), Vec2::splat(0.5)));
        let bottom_right = cam.first_order_ray(CameraSample::new(
            Vec2::new(w - 0.5, h - 0.5),
            Vec2::splat(0.5),
        ));
        // Orthographic rays are parallel: compare origins; perspective: directions.
        let (tl, br) = if cam.is_orthographic() {
            (top_left.origin - eye, bottom_right.origin - eye)
        } else {
            (top_left.direction, bottom_right.direction)
        };
        assert!(
            tl.dot(right) < 0.0 && tl.dot(up) > 0.0,
            "{name}: top-left pixel's ray {top_left:?} should go left (got {}) and up (got {})",
            tl.dot(right),
            tl.dot(up)
        );
        assert!(
            br.dot(right) > 0.0 && br.dot(up) < 0.0,
            "{name}: bottom-right pixel's ray {bottom_right:?} should go right (got {}) and down \
             (got {})",
            br.dot(right),
            br.dot(up)
        );
        // The frame is orthonormal with the code's true_up having a positive component on up.
        let frame = cam.frame;
        assert!(
            (frame.right - right).length() < 1e-6
                && frame.true_up.dot(up) > 0.0
                && (frame.forward - forward).length() < 1e-6,
            "{name}: frame {frame:?} disagrees with right {right:?}, up {up:?}, forward {forward:?}"
        );
    }
}
