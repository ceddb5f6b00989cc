//! A scene's units: a scene file's `units` scales its mesh and its own lengths to metres, and
//! leaves its lens data in millimetres; the units `load_in` is given win over the file's; a
//! glTF's cameras scale with its meshes, so the framing stays; unknown units are one-line
//! errors naming the accepted ones.

use std::path::Path;

use glam::Vec3;
use lensray_core::scene::file::load_in;
use lensray_core::scene::units::SceneUnits;
use lensray_core::scene::{load, SceneError};
use lensray_core::settings::shot;

use crate::{load_err, write};

const TRIANGLE_OBJ: &str = "v 0 0 0\nv 100 0 0\nv 0 250 0\nf 1 2 3\n";

const SCENE_MM: &str = r#"
mesh = "tri.obj"
units = "mm"
[camera]
eye = [0.0, 100.0, 800.0]
target = [0.0, 100.0, 0.0]
focal_length_mm = 50.0
f_number = 1.4
sensor_height_mm = 24.0
focus_distance = 750.0
near = 10.0
[light]
position = [0.0, 500.0, 500.0]
intensity = [2.0, 2.0, 2.0]
"#;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

#[test]
fn a_scene_file_in_millimetres_is_loaded_in_metres() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "tri.obj", TRIANGLE_OBJ);
    let path = write(dir.path(), "scene.toml", SCENE_MM);
    let d = load(&path).unwrap();
    assert_eq!(d.units, SceneUnits::Mm);
    let positions = &d.scene.meshes[0].positions;
    assert!((positions[2] - Vec3::new(0.0, 0.25, 0.0)).length() < 1e-7);
    let c = &d.settings.camera;
    let [x, y, z] = c.eye.unwrap();
    assert!(close(x, 0.0) && close(y, 0.1) && close(z, 0.8), "{c:?}");
    assert!(close(c.focus_distance.unwrap(), 0.75) && close(c.near.unwrap(), 0.01));
    let light = d.settings.light.0[0].position.unwrap();
    assert!(close(light[1], 0.5) && close(light[2], 0.5));
    // Lens data in millimetres and the light's W/sr are no world lengths.
    assert_eq!(c.focal_length_mm, Some(50.0));
    assert_eq!(c.sensor_height_mm, Some(24.0));
    assert_eq!(d.settings.light.0[0].intensity, Some([2.0; 3]));
    // The physical lens sees a bust-sized scene: the shot resolves, focused at 0.75 m.
    let resolved = shot(&d.settings, &d.scene).unwrap();
    let focus = resolved.camera.lens.first_order().focus_distance;
    assert!((focus - 0.75).abs() < 1e-6, "{focus}");

    // Units given to `load_in` win over the file's: the file's numbers as metres.
    let metres = load_in(&path, Some(SceneUnits::M)).unwrap();
    assert_eq!(metres.units, SceneUnits::M);
    assert_eq!(metres.settings.camera.eye, Some([0.0, 100.0, 800.0]));
    assert_eq!(
        metres.scene.meshes[0].positions[2],
        Vec3::new(0.0, 250.0, 0.0)
    );
    let inches = load_in(&path, Some(SceneUnits::In)).unwrap();
    assert!(close(
        inches.settings.camera.eye.unwrap()[2],
        800.0 * 0.0254
    ));
}

#[test]
fn unknown_units_in_a_scene_file_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "tri.obj", TRIANGLE_OBJ);
    let path = write(
        dir.path(),
        "scene.toml",
        "mesh = \"tri.obj\"\nunits = \"furlong\"\n",
    );
    let err = load_err(&path, "scene.toml");
    assert!(matches!(err, SceneError::Toml { .. }), "{err:?}");
    let message = err.to_string();
    for part in ["scene.toml:2:", "furlong", "m, cm, mm or in"] {
        assert!(message.contains(part), "{part}: {message}");
    }
}

/// A glTF of one triangle (positions in `tri.bin`) and a perspective camera at (0, 50, 400)
/// looking down -z, in the file's units.
fn write_gltf_with_camera(dir: &Path) -> std::path::PathBuf {
    let positions: [f32; 9] = [-60.0, 0.0, 0.0, 60.0, 0.0, 0.0, 0.0, 120.0, -30.0];
    let mut bin: Vec<u8> = positions.iter().flat_map(|v| v.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("tri.bin"), &bin).unwrap();
    let json = r#"{
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 50, 400]}],
  "cameras": [{"name": "front", "type": "perspective",
               "perspective": {"yfov": 0.5, "znear": 1.0, "zfar": 2000.0}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"uri": "tri.bin", "byteLength": 44}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 8}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [-60, 0, -30], "max": [60, 120, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]
}"#;
    write(dir, "camera.gltf", json)
}

#[test]
fn a_gltf_in_centimetres_keeps_its_framing() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_gltf_with_camera(dir.path());
    let metres = load(&path).unwrap();
    let centimetres = load_in(&path, Some(SceneUnits::Cm)).unwrap();
    assert_eq!(centimetres.camera_summary(), metres.camera_summary());
    let eye = centimetres.cameras[0].eye;
    assert!(
        (eye - glam::DVec3::new(0.0, 0.5, 4.0)).length() < 1e-12,
        "{eye}"
    );
    let (in_m, in_cm) = (
        shot(&metres.settings, &metres.scene).unwrap().camera,
        shot(&centimetres.settings, &centimetres.scene)
            .unwrap()
            .camera,
    );
    assert!((in_cm.near - 0.01 * in_m.near).abs() < 1e-6 * in_m.near);
    // Every vertex lands on the same pixel: the scene and its camera scaled alike.
    for (a, b) in metres.scene.meshes[0]
        .positions
        .iter()
        .zip(&centimetres.scene.meshes[0].positions)
    {
        let (pa, pb) = (in_m.project(*a).truncate(), in_cm.project(*b).truncate());
        assert!((pa - pb).length() < 1e-3, "{a}: {pa} vs {pb}");
    }
}
