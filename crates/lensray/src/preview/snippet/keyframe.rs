//! The camera as a `[[keyframe]]` table (the `C` key's third form): every value a keyframe keys
//! (`settings::Keyframes`) for this camera, so a user frames a shot, prints it and pastes it
//! into the scene file's keyframes. The movements, the aperture's rotation and the exposure are
//! written even at their defaults (0): a key that left them out would take them from the
//! shot's other keys, and the frame would not be the one printed. Numbers are printed in their
//! shortest round-trip form.

use lensray_core::scene::units::SceneUnits;
use lensray_core::settings::Settings;

/// The `[[keyframe]]` table at `frame` of the camera in `settings` (in metres; a rig's, every
/// value explicit), its lengths in the scene's `units`.
pub fn keyframe_table(settings: &Settings, frame: u32, units: SceneUnits) -> String {
    let settings = settings.clone().scaled(1.0 / units.metres());
    let c = &settings.camera;
    let mut table = format!("[[keyframe]]\nframe = {frame}\n");
    let mut key = |name: &str, value: Option<toml::Value>| {
        if let Some(value) = value {
            table += &format!("{name} = {value}\n");
        }
    };
    let number = |x: Option<f64>| x.map(toml::Value::Float);
    let numbers = |v: Option<&[f64]>| {
        v.map(|v| toml::Value::Array(v.iter().map(|x| toml::Value::Float(*x)).collect()))
    };
    key("focus_distance", number(c.focus_distance));
    key("f_number", number(c.f_number));
    key("focal_length_mm", number(c.focal_length_mm));
    key("lens", c.lens.prescription.clone().map(toml::Value::String));
    key("eye", numbers(c.eye.as_ref().map(|v| &v[..])));
    key("target", numbers(c.target.as_ref().map(|v| &v[..])));
    key("up", numbers(c.up.as_ref().map(|v| &v[..])));
    let zero = |x: Option<f64>| number(Some(x.unwrap_or(0.0)));
    key("shift", numbers(Some(&c.shift.unwrap_or([0.0, 0.0])[..])));
    key("tilt", zero(c.tilt));
    key("tilt_direction", zero(c.tilt_direction));
    key("aperture_rotation", zero(c.aperture.rotation));
    key("exposure", zero(c.exposure.ev));
    table
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::preview::test_scene::unit_cube;
    use crate::preview::CameraRig;
    use lensray_core::settings::{CameraSettings, ImageSettings, Keyframes};

    /// The keyframes of a printed table, as a scene file's loader reads them.
    fn parsed(table: &str) -> Keyframes {
        let document: toml::Table = table.parse().unwrap_or_else(|e| panic!("{e}\n{table}"));
        let tables: Vec<toml::Table> = document["keyframe"]
            .as_array()
            .unwrap_or_else(|| panic!("no [[keyframe]] in:\n{table}"))
            .iter()
            .map(|t| t.as_table().unwrap().clone())
            .collect();
        Keyframes::parse(&tables, Path::new("scenes")).unwrap_or_else(|e| panic!("{e}\n{table}"))
    }

    /// `settings` with every keyed camera value changed: the keyframe must set each back.
    fn disturbed(settings: &Settings) -> Settings {
        let mut base = settings.clone();
        let c = &mut base.camera;
        c.eye = Some([9.0, 9.0, 9.0]);
        c.target = Some([0.5, 0.0, 0.0]);
        c.up = Some([0.0, 0.0, 1.0]);
        c.focus_distance = Some(77.0);
        c.f_number = c.f_number.map(|n| n + 1.0);
        c.focal_length_mm = c.focal_length_mm.map(|f| f + 10.0);
        c.lens.prescription = c.lens.prescription.as_ref().map(|_| "wide-22".into());
        c.shift = Some([0.3, 0.3]);
        c.tilt = Some(1.0);
        c.tilt_direction = Some(45.0);
        c.aperture.rotation = Some(-3.0);
        c.exposure.ev = Some(-1.5);
        base
    }

    fn file_settings(camera: CameraSettings) -> Settings {
        Settings {
            camera: CameraSettings {
                eye: Some([0.3, 0.7, 5.0]),
                target: Some([0.0, 0.1, 0.0]),
                ..camera
            },
            image: ImageSettings {
                width: Some(160),
                height: Some(120),
                ..ImageSettings::default()
            },
            ..Settings::default()
        }
    }

    /// `settings` with the defaults the keyframe writes out (0 movements, rotation, exposure).
    fn explicit(settings: &Settings) -> Settings {
        let mut s = settings.clone();
        let c = &mut s.camera;
        c.shift = Some(c.shift.unwrap_or([0.0, 0.0]));
        for x in [
            &mut c.tilt,
            &mut c.tilt_direction,
            &mut c.aperture.rotation,
            &mut c.exposure.ev,
        ] {
            *x = Some(x.unwrap_or(0.0));
        }
        s
    }

    /// Printed at frame 7 and read back, the keyframe gives the rig's settings at frame 7 over
    /// settings whose every keyed value differs, and (its only key) before and after it; the
    /// shot and exposure they resolve to are the rig's, bit for bit.
    fn assert_round_trip(rig: &CameraRig, what: &str) {
        let table = keyframe_table(rig.settings(), 7, SceneUnits::M);
        let keys = parsed(&table);
        assert_eq!(keys.range(), Some((7, 7)), "{what}:\n{table}");
        let base = disturbed(rig.settings());
        for frame in [7, 1, 300] {
            let keyed = keys.settings_at(&base, frame);
            assert_eq!(
                keyed,
                explicit(rig.settings()),
                "{what}, frame {frame}:\n{table}"
            );
        }
        let scene = unit_cube();
        let keyed = keys.settings_at(&base, 7);
        let shot = rig.shot(&scene).unwrap();
        assert_eq!(
            lensray_core::settings::shot(&keyed, &scene).unwrap(),
            shot,
            "{what}:\n{table}"
        );
        let exposure = |s: &Settings| lensray_core::settings::exposure(s, &shot.camera).unwrap();
        assert_eq!(exposure(&keyed), exposure(rig.settings()), "{what}");
    }

    #[test]
    fn a_physical_lens_with_movements_reads_back() {
        let file = file_settings(CameraSettings {
            focal_length_mm: Some(50.0),
            f_number: Some(2.8),
            ..CameraSettings::default()
        });
        let mut rig = CameraRig::new(file, &unit_cube()).unwrap();
        rig.orbit(33.0, -17.0);
        rig.dolly(1.3);
        rig.step_focus(3.0);
        rig.step_aperture(-2);
        rig.set_shift([1.5, -0.75]);
        rig.set_tilt(4.0, 30.0);
        let mut aperture = rig.aperture();
        aperture.blades = Some(6);
        aperture.rotation = Some(12.5);
        rig.set_aperture(aperture);
        rig.set_exposure_ev(0.7);
        let table = keyframe_table(rig.settings(), 7, SceneUnits::M);
        for key in [
            "frame = 7",
            "focal_length_mm = 50.0",
            "shift = [1.5, -0.75]",
            "tilt = 4.0",
            "tilt_direction = 30.0",
            "aperture_rotation = 12.5",
            "exposure = 0.7",
        ] {
            assert!(table.contains(key), "no {key} in:\n{table}");
        }
        assert_round_trip(&rig, "physical lens");
    }

    #[test]
    fn a_world_unit_lens_and_a_real_lens_read_back() {
        let file = file_settings(CameraSettings {
            aperture_radius: Some(0.1),
            focus_distance: Some(4.5),
            ..CameraSettings::default()
        });
        let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
        rig.pan(5.5, 2.25);
        let table = keyframe_table(rig.settings(), 7, SceneUnits::M);
        // Neither a focal length nor an f-number: the aperture radius is no keyframe's key.
        assert!(
            !table.contains("f_number") && !table.contains("focal_length_mm"),
            "{table}"
        );
        for key in ["shift = [0.0, 0.0]", "tilt = 0.0", "exposure = 0.0"] {
            assert!(table.contains(key), "no {key} in:\n{table}");
        }
        assert_round_trip(&rig, "world-unit lens");
        let mut real = file.clone();
        real.camera.lens.prescription = Some("double-gauss-50".into());
        real.camera.aperture_radius = None;
        real.camera.f_number = Some(4.0);
        let rig = CameraRig::new(real, &unit_cube()).unwrap();
        let table = keyframe_table(rig.settings(), 7, SceneUnits::M);
        assert!(table.contains("lens = \"double-gauss-50\""), "{table}");
        assert_round_trip(&rig, "real lens");
    }

    /// In a scene in millimetres, the lengths are printed in millimetres: read back and scaled
    /// to metres as the loader scales them, they are the rig's within rounding.
    #[test]
    fn lengths_are_in_the_scene_s_units() {
        let file = file_settings(CameraSettings {
            aperture_radius: Some(0.1),
            focus_distance: Some(4.5),
            ..CameraSettings::default()
        });
        let rig = CameraRig::new(file, &unit_cube()).unwrap();
        let table = keyframe_table(rig.settings(), 2, SceneUnits::Mm);
        assert!(table.contains("focus_distance = 4500.0"), "{table}");
        assert!(table.contains("eye = [300.0, 700.0, 5000.0]"), "{table}");
        let keyed = parsed(&table)
            .scaled(SceneUnits::Mm.metres())
            .settings_at(&disturbed(rig.settings()), 2);
        let (a, b) = (&keyed.camera, &rig.settings().camera);
        let near = |x: f64, y: f64| (x - y).abs() <= 1e-12 * y.abs().max(1.0);
        assert!(near(a.focus_distance.unwrap(), b.focus_distance.unwrap()));
        for (x, y) in [(a.eye, b.eye), (a.target, b.target)] {
            let (x, y) = (x.unwrap(), y.unwrap());
            assert!((0..3).all(|i| near(x[i], y[i])), "{x:?} vs {y:?}");
        }
    }
}
