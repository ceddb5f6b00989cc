//! Each motion against numbers worked out by hand. The scene is the cube [-1, 1]^3 (radius
//! sqrt 3); the usual camera looks from (0, 0, 5) at the origin with a 40 degree field of view
//! on a 200 x 100 image.

use glam::{DVec3, Vec2, Vec3};

use super::*;
use crate::preview::test_scene::unit_cube;
use lensray_core::camera::{Camera, Projection};
use lensray_core::optics::paraxial::FirstOrder;
use lensray_core::settings::{CameraSettings, ImageSettings};

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
    assert!((a.lens.aperture_radius - b.lens.aperture_radius).abs() <= tolerance);
    assert!((a.lens.focus_distance - b.lens.focus_distance).abs() <= tolerance);
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
            assert_eq!(pinned.camera.lens.aperture_radius, 0.0);
            let eye = expected_camera.frame.eye;
            expected_camera.lens.focus_distance = eye.length();
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
    // resolve's default eye: 1.1 r / sin(20 degrees) in front of the centre, r = sqrt 3.
    let rig = rig_for(Settings::default());
    let distance = 1.1 * 3f64.sqrt() / 20f64.to_radians().sin();
    assert_vec_close(eye(&rig), DVec3::new(0.0, 0.0, distance), 1e-5);
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

#[test]
fn focus_steps_are_eighths_of_a_doubling() {
    let mut rig = rig_for(base_settings());
    rig.set_focus_distance(3.0);
    assert_eq!(rig.readout().focus_distance, 3.0);
    rig.step_focus(8.0);
    assert_close(rig.readout().focus_distance, 6.0, EPS);
    rig.step_focus(-4.0);
    assert_close(rig.readout().focus_distance, 6.0 / 2f64.sqrt(), EPS);
    rig.step_focus(1.0);
    assert_close(
        rig.readout().focus_distance,
        6.0 / 2f64.sqrt() * 2f64.powf(0.125),
        EPS,
    );
    // A miss under the cursor leaves the focus alone.
    let before = rig.readout().focus_distance;
    for miss in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        rig.set_focus_distance(miss);
        assert_eq!(rig.readout().focus_distance, before);
    }
    let lens = camera(&rig).lens;
    assert_close(lens.focus_distance as f64, before, 1e-6);
}

#[test]
fn aperture_steps_in_world_units() {
    let mut settings = base_settings();
    settings.camera.aperture_radius = Some(0.0);
    let mut rig = rig_for(settings);
    let smallest = 0.002 * rig.scene_radius();
    assert_close(smallest, 0.002 * 3f64.sqrt(), 1e-9);
    rig.step_aperture(1);
    assert_close(rig.readout().aperture_radius, smallest, 1e-12);
    rig.step_aperture(3);
    assert_close(rig.readout().aperture_radius, 2.0 * smallest, 1e-12);
    rig.step_aperture(-3);
    assert_close(rig.readout().aperture_radius, smallest, 1e-12);
    rig.step_aperture(-1);
    assert_eq!(
        rig.readout().aperture_radius,
        0.0,
        "below the smallest: pinhole"
    );
    rig.step_aperture(-1);
    assert_eq!(rig.readout().aperture_radius, 0.0);
    // From 0, the first of two steps opens to the smallest radius, the second widens it.
    rig.step_aperture(2);
    assert_close(
        rig.readout().aperture_radius,
        smallest * 2f64.powf(1.0 / 3.0),
        1e-12,
    );
    // From a large radius: 0.1 * 2^(-1/3).
    let mut rig = rig_for(base_settings());
    rig.step_aperture(-1);
    assert_close(
        rig.readout().aperture_radius,
        0.1 / 2f64.powf(1.0 / 3.0),
        1e-12,
    );
    assert_close(camera(&rig).lens.aperture_radius as f64, 0.079370, 1e-6);
}

#[test]
fn f_number_steps_are_third_stops() {
    let mut rig = rig_for(physical_settings());
    rig.step_aperture(3);
    // One stop wider: N / sqrt 2.
    assert_close(rig.readout().f_number.unwrap(), 2.8 / 2f64.sqrt(), EPS);
    rig.step_aperture(-9);
    assert_close(rig.readout().f_number.unwrap(), 5.6, EPS);
    // Aperture radius f / 2N in metres.
    assert_close(rig.readout().aperture_radius, 0.05 / 11.2, EPS);
    assert_close(camera(&rig).lens.aperture_radius as f64, 0.05 / 11.2, 1e-7);
    rig.step_aperture(100);
    assert_eq!(rig.readout().f_number, Some(0.5));
    rig.step_aperture(-100);
    assert_eq!(rig.readout().f_number, Some(64.0));
}

#[test]
fn toggling_projection_twice_gives_back_the_camera() {
    for settings in [base_settings(), physical_settings()] {
        let mut rig = rig_for(settings);
        let before = camera(&rig);
        rig.toggle_projection();
        assert!(camera(&rig).is_orthographic());
        rig.toggle_projection();
        assert_cameras_close(&camera(&rig), &before, 1e-6);
    }
}

#[test]
fn orthographic_shows_what_perspective_showed_at_the_target() {
    let mut rig = rig_for(base_settings());
    rig.set_projection(ProjectionKind::Orthographic);
    let height = 2.0 * 20f64.to_radians().tan() * 5.0;
    assert_close(rig.readout().ortho_height.unwrap(), height, EPS);
    assert_eq!(rig.readout().vfov_degrees, None);
    match camera(&rig).projection {
        Projection::Orthographic { height: h } => assert_close(h as f64, height, 1e-6),
        other => panic!("{other:?}"),
    }
    // Zoomed out in orthographic, perspective comes back farther away with the same lens.
    rig.dolly(-1.0);
    rig.set_projection(ProjectionKind::Perspective);
    assert_vec_close(eye(&rig), DVec3::new(0.0, 0.0, 5.0 / 0.9), 1e-9);
    assert_eq!(rig.readout().vfov_degrees, Some(40.0));
    assert_eq!(rig.settings().camera.ortho_height, None);
}

#[test]
fn leaving_physical_units_keeps_the_framing() {
    let mut rig = rig_for(physical_settings());
    // 50 mm focused at 5 m: film at 1 / (1/50 - 1/5000) mm, field of view 2 atan(12 / s_i).
    let s_i: f64 = 1.0 / (1.0 / 50.0 - 1.0 / 5000.0);
    let vfov = (2.0 * (12.0 / s_i).atan()).to_degrees();
    assert_close(rig.readout().vfov_degrees.unwrap(), vfov, 1e-9);
    let before = camera(&rig);
    rig.set_aperture_radius(0.02);
    let after = camera(&rig);
    assert_eq!(rig.readout().focal_length_mm, None);
    assert_eq!(rig.readout().aperture_radius, 0.02);
    assert!(after
        .screen_from_camera
        .abs_diff_eq(before.screen_from_camera, 1e-6));
    assert!(after.screen_window.half_height - before.screen_window.half_height < 1e-6);
}

#[test]
fn focal_length_switches_to_physical_units_and_keeps_focus_beyond_it() {
    let mut rig = rig_for(base_settings());
    rig.set_f_number(4.0);
    assert_eq!(rig.readout().f_number, None, "world units have no f-number");
    rig.set_focus_distance(0.03);
    rig.set_focal_length_mm(85.0);
    let r = rig.readout();
    assert_eq!(r.focal_length_mm, Some(85.0));
    assert_eq!(r.f_number, Some(2.8));
    assert_eq!(r.sensor_height_mm, Some(24.0));
    assert_close(r.focus_distance, 0.085 * 1.001, EPS);
    rig.set_f_number(8.0);
    assert_eq!(rig.readout().f_number, Some(8.0));
    rig.set_f_number(100.0);
    assert_eq!(rig.readout().f_number, Some(64.0));
    rig.step_focus(-8.0);
    assert_close(rig.readout().focus_distance, 0.085 * 1.001, EPS);
    assert!(rig.shot(&unit_cube()).is_ok());
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

/// The usual camera with a real lens: double-gauss-50 (f/2.03 at its widest) wide open,
/// focused at the target.
fn real_settings() -> Settings {
    let mut s = base_settings();
    s.camera.aperture_radius = None;
    s.camera.lens.prescription = Some("double-gauss-50".into());
    s
}

fn double_gauss() -> FirstOrder {
    FirstOrder::of(&lensray_core::optics::builtin::lens("double-gauss-50").unwrap())
}

#[test]
fn a_real_lens_is_pinned_to_the_camera_render_resolves() {
    let scene = unit_cube();
    let settings = real_settings();
    let given = shot(&settings, &scene).unwrap().camera;
    let rig = CameraRig::new(settings.clone(), &scene).unwrap();
    let pinned = rig.shot(&scene).unwrap().camera;
    // The same camera, its f-number explicit (`RealLensParams` keeps what was asked).
    let mut explicit = settings;
    explicit.camera.f_number = Some(double_gauss().f_number);
    let expected = shot(&explicit, &scene).unwrap().camera;
    assert!(pinned == expected, "the pinned camera differs");
    let (a, b) = (pinned.real_lens.as_ref().unwrap(), given.real_lens.unwrap());
    assert_eq!((a.f_number, a.film_z()), (b.f_number, b.film_z()));
    assert!(a.pupil() == b.pupil());
    assert!(pinned.real_lens.is_some());
    let c = &rig.settings().camera;
    assert_eq!(c.lens.prescription.as_deref(), Some("double-gauss-50"));
    assert_eq!((c.aperture_radius, c.focal_length_mm), (None, None));
    // Wide open: the widest f-number, explicit.
    assert_eq!(c.f_number, Some(double_gauss().f_number));
    assert_eq!(
        rig.lens_choice(),
        LensChoice::Real("double-gauss-50".into())
    );
    let r = rig.readout();
    let real = r.real.expect("a real lens's readout");
    assert_eq!(real.f_number_range, (double_gauss().f_number, 22.0));
    assert_eq!(r.f_number, Some(double_gauss().f_number));
    // The first-order field of view is the traced one's within a few percent.
    let traced = pinned
        .real_lens
        .as_ref()
        .unwrap()
        .pinhole_vfov()
        .to_degrees();
    assert_close(r.vfov_degrees.unwrap(), traced, 0.02 * traced);
}

#[test]
fn a_real_lens_stops_down_from_its_widest_to_f_22() {
    let mut rig = rig_for(real_settings());
    let widest = double_gauss().f_number;
    rig.step_aperture(-3);
    assert_close(rig.readout().f_number.unwrap(), widest * 2f64.sqrt(), EPS);
    rig.step_aperture(-100);
    assert_eq!(rig.readout().f_number, Some(22.0));
    rig.step_aperture(100);
    assert_eq!(
        rig.readout().f_number,
        Some(widest),
        "never wider than the widest"
    );
    rig.set_f_number(1.4);
    assert_eq!(rig.readout().f_number, Some(widest));
    rig.set_f_number(45.0);
    assert_eq!(rig.readout().f_number, Some(22.0));
    rig.set_f_number(8.0);
    assert_eq!(rig.settings().camera.f_number, Some(8.0));
    let real = camera(&rig).real_lens.unwrap();
    assert_eq!(real.f_number, 8.0);
    // A marked f-number a little wider than the widest, as given, stays until changed.
    let mut given = real_settings();
    given.camera.f_number = Some(2.0);
    let mut rig = rig_for(given);
    assert_eq!(rig.readout().f_number, Some(2.0));
    rig.step_aperture(1);
    assert_eq!(rig.readout().f_number, Some(2.0), "no wider");
    rig.step_aperture(-1);
    assert_close(
        rig.readout().f_number.unwrap(),
        2.0 * 2f64.powf(1.0 / 6.0),
        EPS,
    );
}

#[test]
fn a_real_lens_focuses_no_nearer_than_it_reaches() {
    let mut rig = rig_for(real_settings());
    let fo = double_gauss();
    let nearest = rig.readout().real.unwrap().nearest_focus;
    // 1:1: the subject a focal length before the front focal point (Newton).
    let expected = (fo.entrance_pupil.position_mm - (fo.ffl - fo.efl)) / 1000.0;
    assert_close(nearest, expected, 1e-12);
    // Inside the front focal point the lens cannot focus at all (`CannotFocus`): clamped.
    let front_focus = (fo.entrance_pupil.position_mm - fo.ffl) / 1000.0;
    assert!(nearest > front_focus);
    assert_eq!(rig.set_focus_distance(0.5 * front_focus), Some(nearest));
    assert_eq!(rig.readout().focus_distance, nearest);
    assert_eq!(rig.set_focus_distance(f64::NAN), None);
    rig.step_focus(-8.0);
    assert_eq!(rig.readout().focus_distance, nearest);
    // The camera there resolves (the lens focuses).
    let c = camera(&rig);
    assert_eq!(c.lens.focus_distance, nearest as f32);
    assert!(c.real_lens.is_some());
}

#[test]
fn the_lens_picker_switches_between_thin_and_real_lenses() {
    let mut rig = rig_for(base_settings());
    let thin = rig.readout();
    let choices = rig.lens_choices();
    assert_eq!(choices[0], LensChoice::Thin);
    for name in lensray_core::optics::builtin::names() {
        assert!(choices.contains(&LensChoice::Real(name.into())), "{name}");
    }
    rig.set_lens(&LensChoice::Real("wide-22".into()));
    let r = rig.readout();
    rig.toggle_projection();
    assert_eq!(
        rig.readout().projection,
        ProjectionKind::Perspective,
        "a real lens stays perspective"
    );
    let wide = FirstOrder::of(&lensray_core::optics::builtin::lens("wide-22").unwrap());
    assert_eq!(
        r.f_number,
        Some(wide.f_number),
        "a world-unit lens gives the widest"
    );
    assert_eq!(r.sensor_height_mm, Some(24.0));
    // Another real lens keeps the f-number (within its range) and the sensor.
    rig.set_f_number(5.6);
    rig.set_sensor_height_mm(15.6);
    rig.set_lens(&LensChoice::Real("cooke-triplet-50".into()));
    let r = rig.readout();
    assert_eq!((r.f_number, r.sensor_height_mm), (Some(5.6), Some(15.6)));
    assert_eq!(
        rig.settings().camera.lens.prescription.as_deref(),
        Some("cooke-triplet-50")
    );
    // Back to the thin lens the preview had.
    rig.set_lens(&LensChoice::Thin);
    assert_eq!(rig.readout(), thin);
    assert_eq!(rig.settings().camera.lens.prescription, None);
    assert_eq!(rig.settings().camera.aperture_radius, Some(0.1));
    // An unknown name changes nothing.
    rig.set_lens(&LensChoice::Real("no-such-lens".into()));
    assert_eq!(rig.lens_choice(), LensChoice::Thin);
    // From the orthographic view a real lens switches to the perspective one.
    rig.toggle_projection();
    rig.set_lens(&LensChoice::Real("wide-22".into()));
    assert_eq!(rig.readout().projection, ProjectionKind::Perspective);
    assert!(rig.shot(&unit_cube()).is_ok());
}

#[test]
fn a_physical_lens_hands_its_f_number_to_a_real_one_and_back() {
    let mut rig = rig_for(physical_settings());
    rig.set_f_number(1.0);
    rig.set_lens(&LensChoice::Real("double-gauss-50".into()));
    assert_eq!(
        rig.readout().f_number,
        Some(double_gauss().f_number),
        "clamped"
    );
    rig.step_aperture(-6);
    rig.set_lens(&LensChoice::Thin);
    let r = rig.readout();
    assert_eq!(r.focal_length_mm, Some(50.0));
    assert_eq!(r.f_number, Some(1.0), "the thin lens as it was");
    // Started with a real lens, "thin lens" is the lens's focal length, f-number and sensor.
    let mut rig = rig_for(real_settings());
    rig.set_f_number(4.0);
    rig.set_lens(&LensChoice::Thin);
    let r = rig.readout();
    assert_eq!(r.focal_length_mm, Some(double_gauss().efl));
    assert_eq!(r.f_number, Some(double_gauss().f_number));
    assert!(camera(&rig).real_lens.is_none());
    rig.reset();
    assert_eq!(
        rig.lens_choice(),
        LensChoice::Real("double-gauss-50".into())
    );
}
