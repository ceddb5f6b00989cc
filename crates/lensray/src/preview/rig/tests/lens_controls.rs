//! Focus, aperture, f-number, focal length and projection with thin lenses.

use glam::DVec3;

use super::*;
use lensray_core::camera::Projection;

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
    assert_close(lens.first_order().focus_distance as f64, before, 1e-6);
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
    assert_close(
        camera(&rig).lens.first_order().aperture_radius as f64,
        0.079370,
        1e-6,
    );
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
    assert_close(
        camera(&rig).lens.first_order().aperture_radius as f64,
        0.05 / 11.2,
        1e-7,
    );
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
