//! 2. Unproject / project round trips through the camera's own inverse chain.

use glam::{DVec3, Mat4, Vec3};
use lensray_core::camera::Camera;

use crate::common::*;

/// raster -> world through the inverse chain: world_from_camera * camera_from_screen *
/// screen_from_raster, with the homogeneous divide.
pub fn unproject(cam: &Camera, raster: Vec3) -> Vec3 {
    let world_from_raster: Mat4 =
        cam.world_from_camera * cam.camera_from_screen * cam.screen_from_raster;
    transform_h(&world_from_raster, raster).0
}

/// Relative f32 error of camera depth z recovered from depth d: dz/dd * ulp(d) / z
/// (perspective: z (f - n) / (f n) per unit of depth; orthographic: (f - n) / z). This is the
/// conditioning of the depth encoding itself, not slack.
fn depth_conditioning(r: &RefCam, z: f64) -> f64 {
    let (n, f) = (r.near, r.far);
    let dz_dd_over_z = if r.orthographic {
        (f - n) / z
    } else {
        z * (f - n) / (f * n)
    };
    dz_dd_over_z * f32::EPSILON as f64
}

#[test]
fn raster_to_world_to_raster() {
    let mut rng = Rng::new(10);
    for setup in setups() {
        let cam = setup.camera();
        let r = setup.reference();
        let name = setup.name;
        for i in 0..2000 {
            let depth = match i % 50 {
                0 => 0.0,
                1 => 1.0,
                _ => rng.f64(),
            };
            let raster =
                DVec3::new(rng.range(0.0, r.width), rng.range(0.0, r.height), depth).as_vec3();
            let rd = raster.as_dvec3();
            let world = unproject(&cam, raster);

            // The unprojected point against the f64 reference unprojection.
            let expected_world = r.unproject(rd);
            let z = r.z_from_depth(rd.z);
            let dist = (expected_world - r.eye).length();
            let tol = dist * (4e-6 + 4.0 * depth_conditioning(&r, z)) + 4e-6 * r.eye.length();
            assert_vec_close(
                &format!("{name}: unproject raster {raster:?} (camera depth {z})"),
                world.as_dvec3(),
                expected_world,
                tol,
            );

            // And back.
            // Two passes through the f32 chain (unproject, then project): twice the rounding.
            let (px_tol, depth_tol) = r.raster_tolerance(expected_world);
            let (px_tol, depth_tol) = (2.0 * px_tol, 2.0 * depth_tol);
            let back = cam.project(world).as_dvec3();
            let label = format!("{name}: project(unproject({raster:?})) = {back:?}");
            assert_close(&format!("{label}: column"), back.x, rd.x, px_tol);
            assert_close(&format!("{label}: row"), back.y, rd.y, px_tol);
            assert_close(&format!("{label}: depth"), back.z, rd.z, depth_tol);
        }
    }
}

#[test]
fn world_to_raster_to_world() {
    let mut rng = Rng::new(11);
    for setup in setups() {
        let cam = setup.camera();
        let r = setup.reference();
        let name = setup.name;
        for _ in 0..2000 {
            let p = r.random_point(&mut rng, 1.0).as_vec3();
            let pd = p.as_dvec3();
            let raster = cam.project(p);
            let back = unproject(&cam, raster).as_dvec3();
            let z = r.camera_coords(pd).z;
            let dist = (pd - r.eye).length();
            let tol = dist * (4e-6 + 4.0 * depth_conditioning(&r, z)) + 4e-6 * r.eye.length();
            assert_vec_close(
                &format!("{name}: unproject(project({p:?})) via raster {raster:?}"),
                back,
                pd,
                tol,
            );
        }
    }
}
