//! The printed camera reads back to the same camera: the TOML through the scene-file loader, the
//! command line through clap and `merged_settings`, both resolved and compared bit for bit.

use std::path::PathBuf;

use clap::Parser;

use super::*;
use crate::cli::render::{merged_settings, RenderArgs};
use crate::preview::test_scene::unit_cube;
use crate::preview::CameraRig;
use glam::DVec3;
use lensray_core::scene::file::read_scene_file;
use lensray_core::scene::Scene;
use lensray_core::settings::Shading;
use lensray_core::settings::{settings_lights, shot, LightSettings, Lights};

#[derive(Parser)]
#[command(name = "lensray")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Subcommand)]
enum Command {
    Render(RenderArgs),
}

/// What a scene file holds, standing in for the one the preview was opened with.
fn file_settings() -> Settings {
    Settings {
        camera: CameraSettings {
            eye: Some([0.3, 0.7, 5.0]),
            target: Some([0.0, 0.1, 0.0]),
            aperture_radius: Some(0.1),
            focus_distance: Some(4.5),
            ..CameraSettings::default()
        },
        image: ImageSettings {
            width: Some(160),
            height: Some(120),
            spp: Some(8),
            seed: Some(7),
            sampler: Some(lensray_core::sampler::SamplerKind::Independent),
            fps: None,
        },
        render: RenderStyle {
            shading: Some(Shading::Unlit),
            background: Some([0.1, 0.2, 0.3]),
            ..RenderStyle::default()
        },
        // The light is left to resolve: the printout must carry the derived one.
        light: Lights::default(),
    }
}

fn settings_from_toml(tables: &str) -> Settings {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("shot.toml");
    std::fs::write(&path, format!("mesh = \"cube.obj\"\n{tables}")).unwrap();
    let (mesh, settings, _) = read_scene_file(&path).unwrap_or_else(|e| panic!("{e}\n{tables}"));
    assert_eq!(mesh, dir.path().join("cube.obj"));
    settings
}

fn args_from_command(command: &str, file: &Settings) -> (Settings, Option<PathBuf>) {
    let words = command.split_whitespace();
    let Command::Render(args) = Cli::try_parse_from(words)
        .unwrap_or_else(|e| panic!("{e}\n{command}"))
        .command;
    let units = args.view.scene_units.unwrap_or_default();
    (merged_settings(file, units, &args.view), args.view.scene)
}

/// The shot `settings` resolve to on `scene` (a panic naming them where they do not).
fn resolved_shot(settings: &Settings, scene: &Scene) -> Shot {
    shot(settings, scene).unwrap_or_else(|e| panic!("{e}: {settings:?}"))
}

/// Prints the rig's camera both ways and checks each reads back to the same camera.
fn assert_round_trip(rig: &CameraRig, file: &Settings) {
    let scene = unit_cube();
    let original = rig.shot(&scene).unwrap();
    let snippet = camera_snippet(rig.settings(), &original, None, SceneUnits::M);
    let explicit = explicit_settings(rig.settings(), &original);

    let from_toml = settings_from_toml(&snippet.toml);
    assert_eq!(from_toml, explicit, "TOML reads back every value exactly");
    assert_eq!(
        resolved_shot(&from_toml, &scene),
        original,
        "{}",
        snippet.toml
    );

    let (from_command, scene_path) = args_from_command(&snippet.command, file);
    assert_eq!(scene_path, None);
    let lights = |settings: &Settings| settings_lights(settings, &scene).unwrap();
    assert_eq!(
        lights(&from_toml),
        lights(rig.settings()),
        "{}",
        snippet.toml
    );
    assert_eq!(
        lights(&from_command),
        lights(rig.settings()),
        "{}",
        snippet.command
    );
    assert_eq!(
        resolved_shot(&from_command, &scene),
        original,
        "{}",
        snippet.command
    );
}

#[test]
fn thin_lens_camera_after_moving_reads_back_exactly() {
    let file = file_settings();
    let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
    rig.orbit(33.0, -17.0);
    rig.pan(5.5, 2.25);
    rig.dolly(1.3);
    rig.step_aperture(-2);
    rig.step_focus(3.0);
    rig.set_image_size(317, 211);
    assert_round_trip(&rig, &file);
}

#[test]
fn physical_camera_reads_back_exactly() {
    let file = file_settings();
    let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
    rig.set_focal_length_mm(35.0);
    rig.step_aperture(4);
    rig.orbit(-12.0, 40.0);
    assert_round_trip(&rig, &file);
    // And a file in physical units printed after switching back to world units.
    let mut physical_file = file.clone();
    physical_file.camera.aperture_radius = None;
    physical_file.camera.focal_length_mm = Some(50.0);
    physical_file.camera.f_number = Some(4.0);
    physical_file.light = Lights(vec![LightSettings {
        position: Some([1.0, 2.5, -0.3]),
        intensity: Some([3.0, 2.0, 1.0]),
        ..LightSettings::default()
    }]);
    let mut rig = CameraRig::new(physical_file.clone(), &unit_cube()).unwrap();
    rig.set_aperture_radius(0.03);
    assert_round_trip(&rig, &physical_file);
}

#[test]
fn orthographic_camera_reads_back_exactly() {
    let file = file_settings();
    let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
    rig.toggle_projection();
    rig.dolly(-0.7);
    rig.pan(-3.0, 8.0);
    assert_round_trip(&rig, &file);
}

#[test]
fn default_pinhole_camera_reads_back_exactly() {
    let rig = CameraRig::new(Settings::default(), &unit_cube()).unwrap();
    assert_round_trip(&rig, &Settings::default());
}

#[test]
fn every_value_is_written() {
    let file = file_settings();
    let rig = CameraRig::new(file, &unit_cube()).unwrap();
    let resolved = rig.shot(&unit_cube()).unwrap();
    let snippet = camera_snippet(
        rig.settings(),
        &resolved,
        Some(Path::new("scenes/cube.toml")),
        SceneUnits::M,
    );
    for key in [
        "[camera]",
        "projection = \"perspective\"",
        "eye = [0.3, 0.7, 5.0]",
        "target = [0.0, 0.1, 0.0]",
        "up = [0.0, 1.0, 0.0]",
        "vfov_degrees = 40.0",
        "aperture_radius = 0.1",
        "focus_distance = 4.5",
        "near = ",
        "far = ",
        "[image]",
        "width = 160",
        "height = 120",
        "spp = 8",
        "seed = 7",
        "[render]",
        "shading = \"unlit\"",
        "background = [0.1, 0.2, 0.3]",
        "[[light]]",
        "type = \"point\"",
        "position = [",
        "intensity = [",
    ] {
        assert!(
            snippet.toml.contains(key),
            "{key} missing:\n{}",
            snippet.toml
        );
    }
    assert!(!snippet.toml.contains("ortho_height"));
    let near = resolved.camera.near as f64;
    let light = DVec3::from_array(rig.settings().light.0[0].position.unwrap());
    let expected = format!(
        "lensray render --scene scenes/cube.toml --projection perspective --eye 0.3,0.7,5 \
         --target 0,0.1,0 --up 0,1,0 --vfov 40 --aperture-radius 0.1 --focus-distance 4.5 \
         --near {near} --far {} --width 160 --height 120 --spp 8 --seed 7 --sampler independent --shading unlit \
         --background 0.1,0.2,0.3 --light-position {},{},{} --light-intensity ",
        resolved.camera.far as f64, light.x, light.y, light.z,
    );
    assert!(
        snippet.command.starts_with(&expected),
        "{}\n{expected}",
        snippet.command
    );
    let (_, scene_path) = args_from_command(&snippet.command, &Settings::default());
    assert_eq!(scene_path, Some(PathBuf::from("scenes/cube.toml")));
    let printed = snippet.to_string();
    assert!(printed.contains(&snippet.toml) && printed.contains(&snippet.command));
}

#[test]
fn derived_light_is_the_resolved_one() {
    // Light above the eye by half the scene radius, intensity pi d^2 (see resolve).
    let file = file_settings();
    let rig = CameraRig::new(file, &unit_cube()).unwrap();
    let resolved = rig.shot(&unit_cube()).unwrap();
    let explicit = explicit_settings(rig.settings(), &resolved);
    let position = explicit.light.0[0].position.unwrap();
    let expected = resolved.camera.frame.eye + resolved.camera.frame.true_up * (0.5 * 3f32.sqrt());
    for (p, e) in position.iter().zip(expected.to_array()) {
        assert!((p - e as f64).abs() < 1e-6, "{position:?} vs {expected}");
    }
    assert_eq!(explicit.image.width, Some(160));
}

/// In a scene of millimetres the printout's lengths are millimetres, the file's units and
/// `--scene-units mm` say so, and both read back to the same camera to within rounding.
#[test]
fn millimetre_scene_prints_millimetres() {
    let file = file_settings();
    let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
    rig.set_focal_length_mm(50.0);
    rig.orbit(12.0, 4.0);
    let original = rig.shot(&unit_cube()).unwrap();
    let snippet = camera_snippet(rig.settings(), &original, None, SceneUnits::Mm);
    assert!(
        snippet.toml.starts_with("# lengths in mm"),
        "{}",
        snippet.toml
    );
    assert!(
        snippet.toml.contains("focal_length_mm = 50.0"),
        "{}",
        snippet.toml
    );
    assert!(
        snippet
            .command
            .starts_with("lensray render --scene-units mm "),
        "{}",
        snippet.command
    );
    let from_toml = settings_from_toml(&snippet.toml);
    let focus = from_toml.camera.focus_distance.unwrap();
    let metres = f64::from(original.camera.lens.first_order().focus_distance);
    assert!((focus - 1000.0 * metres).abs() < 1e-6 * focus, "{focus} mm");
    let (from_command, _) = args_from_command(&snippet.command, &file);
    for settings in [from_toml.scaled(0.001), from_command] {
        let got = resolved_shot(&settings, &unit_cube()).camera;
        let want = &original.camera;
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * b.abs().max(1.0);
        assert!(
            (got.frame.eye - want.frame.eye).length() < 1e-5,
            "{settings:?}"
        );
        assert!((got.frame.forward - want.frame.forward).length() < 1e-5);
        assert!(close(got.near, want.near) && close(got.far, want.far));
        let (g, w) = (got.lens.first_order(), want.lens.first_order());
        assert!(close(g.focus_distance, w.focus_distance));
        assert!(close(g.aperture_radius, w.aperture_radius));
    }
}

#[test]
fn shell_words() {
    assert_eq!(shell_word("scenes/a-b_c.toml"), "scenes/a-b_c.toml");
    assert_eq!(shell_word("my scene.toml"), "'my scene.toml'");
    assert_eq!(shell_word("it's.toml"), r"'it'\''s.toml'");
    assert_eq!(shell_word(""), "''");
}

/// A real lens: opened with one, stopped down, focused and moved; picked in the
/// panel; read from a prescription file. The printout names it (`[camera.lens]`, `--lens`)
/// with its f-number, focus and sensor, and reads back to the same camera.
#[test]
fn real_lens_camera_reads_back_exactly() {
    use crate::preview::rig::LensChoice;
    let mut file = file_settings();
    file.camera.aperture_radius = None;
    file.camera.lens.prescription = Some("double-gauss-50".into());
    let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
    rig.step_aperture(-4);
    let _ = rig.set_focus_distance(3.7);
    rig.orbit(20.0, -5.0);
    rig.set_sensor_height_mm(15.6);
    assert_round_trip(&rig, &file);
    let resolved = rig.shot(&unit_cube()).unwrap();
    let snippet = camera_snippet(rig.settings(), &resolved, None, SceneUnits::M);
    let f_number = rig.readout().f_number.unwrap();
    for key in [
        "[camera.lens]\nprescription = \"double-gauss-50\"".to_owned(),
        format!("f_number = {f_number}"),
        "focus_distance = 3.7".to_owned(),
        "sensor_height_mm = 15.6".to_owned(),
    ] {
        assert!(snippet.toml.contains(&key), "{key}:\n{}", snippet.toml);
    }
    assert!(!snippet.toml.contains("vfov_degrees"), "{}", snippet.toml);
    for option in [
        "--lens double-gauss-50 ".to_owned(),
        format!("--f-number {f_number} "),
        "--sensor-height-mm 15.6 ".to_owned(),
        "--focus-distance 3.7 ".to_owned(),
    ] {
        assert!(
            snippet.command.contains(&option),
            "{option}: {}",
            snippet.command
        );
    }

    // Picked in the panel over a thin-lens file: wide open.
    let file = file_settings();
    let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
    rig.set_lens(&LensChoice::Real("cooke-triplet-50".into()));
    assert_round_trip(&rig, &file);

    // A prescription file, named by its path.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("my-lens.dat");
    let text = lensray_core::optics::builtin::LENSES
        .iter()
        .find(|(name, _)| *name == "biconvex-50")
        .unwrap()
        .1;
    std::fs::write(&path, text).unwrap();
    let mut file = file_settings();
    file.camera.aperture_radius = None;
    file.camera.lens.prescription = Some(path.display().to_string());
    let mut rig = CameraRig::new(file.clone(), &unit_cube()).unwrap();
    assert!(rig
        .lens_choices()
        .contains(&LensChoice::Real(path.display().to_string())));
    rig.step_aperture(-2);
    assert_round_trip(&rig, &file);
}

/// The panel's exposure and tone map, and a physical exposure with a pinhole's f-number, are
/// printed both ways and read back to the same exposure.
#[test]
fn exposure_and_tone_map_read_back_exactly() {
    use lensray_core::film::tonemap::ToneMap;
    use lensray_core::settings::exposure;
    let mut file = file_settings();
    file.camera.aperture_radius = None;
    file.camera.f_number = Some(8.0);
    file.camera.exposure.iso = Some(400.0);
    file.camera.exposure.shutter = Some(1.0 / 250.0);
    file.camera.exposure.expose_exr = Some(true);
    let scene = unit_cube();
    let mut rig = CameraRig::new(file.clone(), &scene).unwrap();
    rig.set_exposure_ev(-0.5);
    rig.set_tonemap(ToneMap::Agx);
    assert_round_trip(&rig, &file);
    let original = rig.shot(&scene).unwrap();
    let wanted = rig.exposure(&original.camera).unwrap();
    assert_eq!(wanted.physical.unwrap().f_number, 8.0);
    let snippet = camera_snippet(rig.settings(), &original, None, SceneUnits::M);
    assert!(
        snippet.toml.contains("[camera.exposure]"),
        "{}",
        snippet.toml
    );
    assert!(
        snippet.command.contains("--exposure -0.5")
            && snippet.command.contains("--tonemap agx")
            && snippet.command.contains("--expose-exr"),
        "{}",
        snippet.command
    );
    let from_toml = settings_from_toml(&snippet.toml);
    let (from_command, _) = args_from_command(&snippet.command, &Settings::default());
    for settings in [from_toml, from_command] {
        let camera = resolved_shot(&settings, &scene).camera;
        assert_eq!(exposure(&settings, &camera).unwrap(), wanted);
    }
}
