//! Each motion against numbers worked out by hand. The scene is the cube [-1, 1]^3 (radius
//! sqrt 3); the usual camera looks from (0, 0, 5) at the origin with a 40 degree field of view
//! on a 200 x 100 image. Here: pinning, reset, the image size and the readout; the motions,
//! the thin lens's controls and real lenses in the submodules.

use glam::DVec3;

use super::*;
use crate::preview::test_scene::unit_cube;
use lensray_core::camera::Camera;
use lensray_core::settings::{CameraSettings, ImageSettings};

mod lens_controls;
mod navigation;
mod real_lens;

const EPS: f64 = 1e-9;

fn base_settings() -> Settings {
    Settings {
        camera: CameraSettings {
            eye: Some([0.0, 0.0, 5.0]),
            target: Some([0.0, 0.0, 0.0]),
            vfov_degrees: Some(40.0),
            aperture_radius: Some(0.1),
            focus_distance: Some(5.0),
            ..CameraSettings::default()
        },
        image: ImageSettings {
            width: Some(200),
            height: Some(100),
            ..ImageSettings::default()
        },
        ..Settings::default()
    }
}

fn physical_settings() -> Settings {
    let mut s = base_settings();
    s.camera.aperture_radius = None;
    s.camera.focal_length_mm = Some(50.0);
    s.camera.f_number = Some(2.8);
    s
}

fn rig_for(settings: Settings) -> CameraRig {
    CameraRig::new(settings, &unit_cube()).expect("test camera resolves")
}

fn eye(rig: &CameraRig) -> DVec3 {
    DVec3::from_array(rig.settings().camera.eye.unwrap())
}

fn target(rig: &CameraRig) -> DVec3 {
    DVec3::from_array(rig.settings().camera.target.unwrap())
}

fn camera(rig: &CameraRig) -> Camera {
    rig.shot(&unit_cube()).expect("rig resolves").camera
}

fn assert_close(actual: f64, expected: f64, tolerance: f64) {
    assert!(
        (actual - expected).abs() <= tolerance,
        "{actual} != {expected} (tolerance {tolerance})"
    );
}

fn assert_vec_close(actual: DVec3, expected: DVec3, tolerance: f64) {
    assert!(
        actual.abs_diff_eq(expected, tolerance),
        "{actual} != {expected} (tolerance {tolerance})"
    );
}

fn assert_cameras_close(a: &Camera, b: &Camera, tolerance: f32) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    assert!(a
        .camera_from_world
        .abs_diff_eq(b.camera_from_world, tolerance));
    assert!(a
        .screen_from_camera
        .abs_diff_eq(b.screen_from_camera, tolerance));
    assert!(a
        .clip_from_world()
        .abs_diff_eq(b.clip_from_world(), tolerance));
    assert!(
        (a.lens.first_order().aperture_radius - b.lens.first_order().aperture_radius).abs()
            <= tolerance
    );
    assert!(
        (a.lens.first_order().focus_distance - b.lens.first_order().focus_distance).abs()
            <= tolerance
    );
    assert_eq!(a.is_orthographic(), b.is_orthographic());
}

#[test]
fn pinning_keeps_the_resolved_camera_exactly() {
    let scene = unit_cube();
    let mut ortho = base_settings();
    ortho.camera.projection = Some(ProjectionKind::Orthographic);
    for settings in [
        Settings::default(),
        base_settings(),
        physical_settings(),
        ortho,
    ] {
        let expected = shot(&settings, &scene).unwrap();
        let rig = CameraRig::new(settings.clone(), &scene).unwrap();
        let pinned = rig.shot(&scene).unwrap();
        let mut expected_camera = expected.camera;
        if settings.camera.aperture_radius.is_none() && settings.camera.focal_length_mm.is_none() {
            // A pinhole gets a focus distance for the focus controls: the target's distance.
            // Its aperture is 0, so the image is the same.
            assert!(pinned.camera.lens.is_pinhole());
            let eye = expected_camera.frame.eye;
            expected_camera.lens.first_order_mut().focus_distance = eye.length();
        }
        assert_eq!(pinned.camera, expected_camera, "{settings:?}");
        assert_eq!(pinned.render, expected.render, "{settings:?}");
        let c = &rig.settings().camera;
        assert!(c.eye.is_some() && c.target.is_some() && c.up.is_some());
        assert!(c.projection.is_some() && c.focus_distance.is_some());
        // Near and far are derived for each new eye unless the user gave them.
        assert_eq!((c.near, c.far), (None, None));
    }
}

#[test]
fn pinning_the_default_camera_gives_explicit_values() {
    // `settings::shot`'s automatic framing: 1.05 r / sin(20 degrees) from the centre, r = sqrt 3,
    // 35 degrees around from +z toward +x and 25 degrees up.
    let rig = rig_for(Settings::default());
    let distance = 1.05 * 3f64.sqrt() / 20f64.to_radians().sin();
    let (around, up) = (35f64.to_radians(), 25f64.to_radians());
    let direction = DVec3::new(around.sin() * up.cos(), up.sin(), around.cos() * up.cos());
    assert_vec_close(eye(&rig), direction * distance, 1e-5);
    assert_eq!(target(&rig), DVec3::ZERO);
    let c = &rig.settings().camera;
    assert_eq!(c.up, Some([0.0, 1.0, 0.0]));
    assert_eq!(c.vfov_degrees, Some(40.0));
    assert_eq!(c.aperture_radius, Some(0.0), "a pinhole");
    assert_close(c.focus_distance.unwrap(), distance, 1e-5);
    assert_eq!(rig.settings().image.width, Some(640));
    assert_eq!(rig.settings().image.height, Some(480));
    assert_close(rig.scene_radius(), 3f64.sqrt(), 1e-6);
}

#[test]
fn reset_restores_the_start_camera_at_the_window_size() {
    let mut rig = rig_for(base_settings());
    let start = camera(&rig);
    rig.orbit(40.0, 20.0);
    rig.pan(3.0, 4.0);
    rig.dolly(2.0);
    rig.step_aperture(2);
    rig.toggle_projection();
    rig.set_image_size(300, 150);
    rig.reset();
    let after = camera(&rig);
    assert_eq!((after.width, after.height), (300, 150));
    rig.set_image_size(200, 100);
    assert_eq!(camera(&rig), start);
}

#[test]
fn image_size_follows_the_window() {
    let mut rig = rig_for(base_settings());
    rig.set_image_size(0, 0);
    let c = camera(&rig);
    assert_eq!((c.width, c.height), (1, 1));
    rig.set_image_size(1280, 720);
    let c = camera(&rig);
    assert_eq!((c.width, c.height), (1280, 720));
    // Pan scale follows the new height: 5 * 2 tan(20 degrees) / 720 per pixel.
    rig.pan(0.0, 72.0);
    assert_close(eye(&rig).y, 0.5 * 2.0 * 20f64.to_radians().tan(), EPS);
}

#[test]
fn readout_shows_the_lens_panel_values() {
    let r = rig_for(base_settings()).readout();
    assert_eq!(
        r,
        LensReadout {
            projection: ProjectionKind::Perspective,
            focal_length_mm: None,
            f_number: None,
            sensor_height_mm: None,
            aperture_radius: 0.1,
            focus_distance: 5.0,
            vfov_degrees: Some(40.0),
            ortho_height: None,
            target_distance: 5.0,
            real: None,
        }
    );
}

#[test]
fn near_and_far_given_by_the_user_are_kept() {
    let mut settings = base_settings();
    settings.camera.near = Some(0.5);
    settings.camera.far = Some(50.0);
    let mut rig = rig_for(settings);
    rig.orbit(10.0, 10.0);
    rig.dolly(1.0);
    let c = camera(&rig);
    assert_eq!((c.near, c.far), (0.5, 50.0));
}
