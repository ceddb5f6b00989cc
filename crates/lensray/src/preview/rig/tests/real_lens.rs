//! Real lenses: pinning, their f-number and focus limits, and the lens picker.

use super::*;
use lensray_core::optics::paraxial::FirstOrder;

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
    let (a, b) = (pinned.lens.real().unwrap(), given.lens.real().unwrap());
    assert_eq!((a.f_number, a.film_z()), (b.f_number, b.film_z()));
    assert!(a.pupil() == b.pupil());
    assert!(pinned.lens.real().is_some());
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
    let traced = pinned.lens.real().unwrap().pinhole_vfov().to_degrees();
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
    let real = camera(&rig).lens.real().unwrap().clone();
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
    assert_eq!(c.lens.first_order().focus_distance, nearest as f32);
    assert!(c.lens.real().is_some());
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
    // Dispersion: on by default, off from the panel, kept across lenses, and in the settings
    // (so in the printed command) only when off.
    let real = rig.readout().real.expect("a real lens");
    assert!(real.dispersive_glass && real.dispersion);
    assert_eq!(rig.settings().camera.lens.dispersion, None);
    rig.set_dispersion(false);
    assert_eq!(
        rig.settings().camera.lens.dispersion,
        Some(lensray_core::settings::Switch::Off)
    );
    rig.set_lens(&LensChoice::Real("double-gauss-50".into()));
    assert!(!rig.readout().real.expect("a real lens").dispersion);
    rig.set_dispersion(true);
    assert_eq!(rig.settings().camera.lens.dispersion, None);
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
    assert!(camera(&rig).lens.real().is_none());
    rig.reset();
    assert_eq!(
        rig.lens_choice(),
        LensChoice::Real("double-gauss-50".into())
    );
}
