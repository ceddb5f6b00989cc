//! Orbit, pan, dolly and fly.

use glam::{DVec3, Vec2, Vec3};

use super::*;

#[test]
fn orbit_right_turns_the_eye_left_about_the_up_axis() {
    let mut rig = rig_for(base_settings());
    // 100 px at 0.3 degrees per pixel: 30 degrees, towards the camera's left (-x).
    rig.orbit(100.0, 0.0);
    assert_vec_close(eye(&rig), DVec3::new(-2.5, 0.0, 5.0 * 0.75f64.sqrt()), EPS);
    assert_eq!(target(&rig), DVec3::ZERO);
}

#[test]
fn orbit_down_raises_the_eye_keeping_the_distance() {
    let mut rig = rig_for(base_settings());
    rig.orbit(0.0, 100.0);
    assert_vec_close(eye(&rig), DVec3::new(0.0, 2.5, 5.0 * 0.75f64.sqrt()), EPS);
    rig.orbit(37.0, -55.0);
    assert_close((eye(&rig) - target(&rig)).length(), 5.0, EPS);
}

#[test]
fn orbit_stops_short_of_the_pole() {
    let mut rig = rig_for(base_settings());
    rig.orbit(0.0, 10_000.0);
    let e = eye(&rig);
    assert_close(e.y, 5.0 * 89f64.to_radians().sin(), EPS);
    assert_close(e.length(), 5.0, EPS);
    assert_eq!(rig.settings().camera.up, Some([0.0, 1.0, 0.0]));
    // Still a valid camera whose up points up in the image.
    assert!(camera(&rig).frame.true_up.y > 0.0);
    rig.orbit(0.0, -10_000.0);
    assert_close(eye(&rig).y, -5.0 * 89f64.to_radians().sin(), EPS);
}

#[test]
fn perspective_pan_keeps_the_target_under_the_cursor() {
    let mut rig = rig_for(base_settings());
    let before = camera(&rig);
    let old_target = Vec3::ZERO;
    assert!(before
        .project(old_target)
        .truncate()
        .abs_diff_eq(Vec2::new(100.0, 50.0), 1e-4));
    rig.pan(10.0, -4.0);
    // 5 * 2 tan(20 degrees) / 100 world units per pixel; the camera moves against the cursor.
    let s = 5.0 * 2.0 * 20f64.to_radians().tan() / 100.0;
    let shift = DVec3::new(-10.0 * s, -4.0 * s, 0.0);
    assert_vec_close(eye(&rig), DVec3::new(0.0, 0.0, 5.0) + shift, EPS);
    assert_vec_close(target(&rig), shift, EPS);
    let after = camera(&rig);
    assert_eq!(after.frame.forward, before.frame.forward, "view direction");
    let moved = after.project(old_target).truncate();
    assert!(moved.abs_diff_eq(Vec2::new(110.0, 46.0), 1e-3), "{moved}");
}

#[test]
fn orthographic_pan_moves_by_the_view_height_per_pixel() {
    let mut settings = base_settings();
    settings.camera.projection = Some(ProjectionKind::Orthographic);
    settings.camera.ortho_height = Some(4.0);
    let mut rig = rig_for(settings);
    rig.pan(-25.0, 0.0);
    // 4 / 100 per pixel: 25 px to the left moves the camera 1 to the right.
    assert_vec_close(eye(&rig), DVec3::new(1.0, 0.0, 5.0), EPS);
    assert_vec_close(target(&rig), DVec3::new(1.0, 0.0, 0.0), EPS);
    let moved = camera(&rig).project(Vec3::ZERO).truncate();
    assert!(moved.abs_diff_eq(Vec2::new(75.0, 50.0), 1e-3), "{moved}");
}

#[test]
fn dolly_scales_the_distance_by_0_9_per_step() {
    let mut rig = rig_for(base_settings());
    rig.dolly(2.0);
    assert_vec_close(eye(&rig), DVec3::new(0.0, 0.0, 4.05), EPS);
    rig.dolly(-1.0);
    assert_vec_close(eye(&rig), DVec3::new(0.0, 0.0, 4.5), EPS);
    rig.dolly(0.5);
    assert_close(eye(&rig).z, 4.5 * 0.9f64.sqrt(), EPS);
    // Never through the target.
    rig.dolly(10_000.0);
    assert!(eye(&rig).z > 0.0);
    assert_eq!(target(&rig), DVec3::ZERO);
    rig.shot(&unit_cube()).expect("still a camera");
}

#[test]
fn orthographic_dolly_scales_the_view_height() {
    let mut settings = base_settings();
    settings.camera.projection = Some(ProjectionKind::Orthographic);
    settings.camera.ortho_height = Some(4.0);
    let mut rig = rig_for(settings);
    rig.dolly(3.0);
    assert_close(
        rig.settings().camera.ortho_height.unwrap(),
        4.0 * 0.729,
        EPS,
    );
    assert_eq!(eye(&rig), DVec3::new(0.0, 0.0, 5.0));
}

#[test]
fn fly_moves_a_scene_radius_per_second_along_camera_axes() {
    let mut rig = rig_for(base_settings());
    let r = 3f64.sqrt();
    rig.fly(Vec3::Z, 0.5);
    assert_vec_close(eye(&rig), DVec3::new(0.0, 0.0, 5.0 - 0.5 * r), 1e-6);
    assert_vec_close(target(&rig), DVec3::new(0.0, 0.0, -0.5 * r), 1e-6);
    rig.fly(Vec3::new(1.0, 1.0, 0.0), 1.0);
    // Diagonals are normalised: r / sqrt 2 right (+x) and up (+y).
    let d = r / 2f64.sqrt();
    assert_vec_close(target(&rig), DVec3::new(d, d, -0.5 * r), 1e-6);
}
