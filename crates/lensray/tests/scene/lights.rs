//! Lights from files: glTF `KHR_lights_punctual` under node transforms, a scene file's
//! `[[light]]` tables (and its one `[light]` table), the default light, and bad lights.

use std::f32::consts::PI;

use glam::Vec3;
use lensray_core::scene::generate::cornell_box;
use lensray_core::scene::texture::{Encoding, Texture, TextureRef};
use lensray_core::scene::{load, load_gltf, LightKind, Material, Mesh, Scene};
use lensray_core::settings::{
    emitters_light_share, light_scene, settings_lights, Settings, EMITTERS_LIGHT_SHARE,
};

use super::gltf::{write_gltf, TRIANGLE};
use crate::write;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn gltf_punctual_lights_take_their_nodes_transforms() {
    let dir = tempfile::tempdir().unwrap();
    // Node 1 holds the point light at (1, 2, 3) under the root's translation (10, 0, 0); node 2
    // the spot, turned -90 degrees about +x so its -Z axis points down; node 3 the sun, turned
    // 90 degrees about +y so it shines towards -x.
    let s = (PI / 4.0).sin();
    let nodes = format!(
        r#"[{{"mesh": 0, "translation": [10, 0, 0], "children": [1]}},
            {{"translation": [1, 2, 3], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
            {{"translation": [0, 5, 0], "rotation": [-{s}, 0, 0, {s}],
              "extensions": {{"KHR_lights_punctual": {{"light": 1}}}}}},
            {{"rotation": [0, {s}, 0, {s}], "extensions": {{"KHR_lights_punctual": {{"light": 2}}}}}}]"#
    );
    let extra = r#",
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 8.0, "range": 12.0},
    {"type": "spot", "intensity": 20.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
    {"type": "directional", "color": [0.5, 0.5, 1.0], "intensity": 3.0}
  ]}}"#;
    let path = write_gltf(dir.path(), "lights.gltf", &nodes, TRIANGLE, extra);
    // Only the root is in the scene's node list: add the others as its siblings.
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace(r#""nodes": [0]}"#, r#""nodes": [0, 2, 3]}"#);
    std::fs::write(&path, text).unwrap();
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let lights = &file.scene.lights;
    assert_eq!(lights.len(), 3, "{lights:?}");
    let point = &lights[0];
    assert_eq!(point.kind, LightKind::Point);
    assert!(
        close(point.position, Vec3::new(11.0, 2.0, 3.0)),
        "{point:?}"
    );
    assert!(close(point.intensity, Vec3::new(8.0, 4.0, 2.0)) && point.range == 12.0);
    let spot = &lights[1];
    assert!(close(spot.position, Vec3::new(0.0, 5.0, 0.0)), "{spot:?}");
    assert!(close(spot.direction, Vec3::NEG_Y), "{spot:?}");
    let LightKind::Spot {
        cos_inner,
        cos_outer,
    } = spot.kind
    else {
        panic!("{spot:?}");
    };
    assert!((cos_inner - 0.2f32.cos()).abs() < 1e-6 && (cos_outer - 0.5f32.cos()).abs() < 1e-6);
    let sun = &lights[2];
    assert_eq!(sun.kind, LightKind::Directional);
    assert!(close(sun.direction, Vec3::NEG_X), "{sun:?}");
    assert!(close(sun.intensity, Vec3::new(1.5, 1.5, 3.0)));
    // The file's lights light the scene: no default light is added.
    let mut description = load(&path).unwrap();
    let settings = description.settings.clone();
    assert!(settings_lights(&settings, &description.scene)
        .unwrap()
        .is_empty());
    light_scene(&settings, &mut description.scene).unwrap();
    assert_eq!(description.scene.lights.len(), 3);
    assert!(
        !description.notices.iter().any(|n| n.contains("KHR_lights")),
        "{:?}",
        description.notices
    );
}

#[test]
fn scene_files_add_lights_to_the_file_s_and_the_default_lights_only_a_dark_scene() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let path = write(
        dir.path(),
        "lights.toml",
        r#"mesh = "tri.obj"
[[light]]
position = [0.0, 2.0, 1.0]
intensity = [4.0, 4.0, 4.0]
[[light]]
type = "spot"
position = [0.0, 3.0, 0.0]
direction = [0.0, -2.0, 0.0]
intensity = [9.0, 9.0, 9.0]
inner_cone_degrees = 10.0
outer_cone_degrees = 30.0
[[light]]
type = "directional"
direction = [0.0, 0.0, -1.0]
intensity = [0.5, 0.5, 0.5]
"#,
    );
    let mut d = load(&path).unwrap();
    let settings = d.settings.clone();
    light_scene(&settings, &mut d.scene).unwrap();
    let lights = &d.scene.lights;
    assert_eq!(lights.len(), 3, "{lights:?}");
    assert!(close(lights[1].direction, Vec3::NEG_Y));
    assert!(matches!(lights[1].kind, LightKind::Spot { cos_inner, .. }
        if (cos_inner - 10f32.to_radians().cos()).abs() < 1e-6));
    assert_eq!(lights[2].kind, LightKind::Directional);
    // Lighting again adds nothing.
    light_scene(&settings, &mut d.scene).unwrap();
    assert_eq!(d.scene.lights.len(), 3);

    // No lights and no environment: one point light above the eye; with an environment, none.
    let bare = write(dir.path(), "bare.toml", "mesh = \"tri.obj\"\n");
    let d = load(&bare).unwrap();
    assert_eq!(settings_lights(&d.settings, &d.scene).unwrap().len(), 1);
    let sky = write(
        dir.path(),
        "sky.toml",
        "mesh = \"tri.obj\"\n[render]\nenvironment = [0.2, 0.2, 0.2]\n",
    );
    let d = load(&sky).unwrap();
    assert!(settings_lights(&d.settings, &d.scene).unwrap().is_empty());
    assert_eq!(
        d.settings.render.environment,
        Some(lensray_core::settings::EnvironmentSetting::Sky([0.2; 3]))
    );
}

#[test]
fn bad_lights_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    for (light, expected) in [
        (
            "intensity = [-1.0, 0.0, 0.0]",
            "light intensity must be finite and not negative",
        ),
        (
            "type = \"spot\"\ninner_cone_degrees = 40.0\nouter_cone_degrees = 20.0",
            "inner cone must not be wider than its outer cone",
        ),
        (
            "type = \"spot\"\nouter_cone_degrees = 120.0",
            "must be 0 to 90 degrees",
        ),
        (
            "type = \"directional\"\ndirection = [0.0, 0.0, 0.0]",
            "light direction",
        ),
        ("range = -2.0", "range must be finite and not negative"),
    ] {
        let path = write(
            dir.path(),
            "bad.toml",
            &format!("mesh = \"tri.obj\"\n[[light]]\n{light}\n"),
        );
        let d = load(&path).unwrap();
        let err = settings_lights(&d.settings, &d.scene)
            .unwrap_err()
            .to_string();
        assert!(err.contains(expected), "{light}: {err}");
        assert!(!err.contains('\n'), "{err}");
    }
    let path = write(
        dir.path(),
        "typo.toml",
        "mesh = \"tri.obj\"\n[[light]]\ntype = \"area\"\n",
    );
    let err = load(&path).unwrap_err().to_string();
    assert!(err.contains("area") && err.contains("typo.toml"), "{err}");
}

/// A quad of `material` from `corner` along `a` and `b` (counter-clockwise seen from a x b).
fn quad(corner: Vec3, a: Vec3, b: Vec3, material: u32) -> Mesh {
    Mesh {
        name: "quad".into(),
        positions: vec![corner, corner + a, corner + a + b, corner + b],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![material; 2],
        ..Default::default()
    }
}

/// Emitters that light the scene replace the default light; a glowing label does not: a model
/// with one keeps the light that shows the rest of it (ClearCoatTest's labels left its tiles
/// black when any emitter did).
#[test]
fn only_emitters_that_light_the_scene_replace_the_default_light() {
    let cornell = cornell_box();
    let share = emitters_light_share(&cornell.scene);
    // A 2 m grey board with a 0.4 m x 0.1 m label glowing at 1.
    let board = Scene {
        meshes: vec![
            quad(Vec3::new(-1.0, -1.0, 0.0), 2.0 * Vec3::X, 2.0 * Vec3::Y, 0),
            quad(Vec3::new(-0.2, 0.8, 0.01), 0.4 * Vec3::X, 0.1 * Vec3::Y, 1),
        ],
        materials: vec![
            Material::new("board", Vec3::splat(0.5), Vec3::ZERO),
            Material::new("label", Vec3::ONE, Vec3::ONE),
        ],
        ..Default::default()
    };
    let label_share = emitters_light_share(&board);
    println!(
        "the Cornell box's patch gives {share:.4} of the default light's irradiance, the label \
         {label_share:.4}; the threshold is {EMITTERS_LIGHT_SHARE}"
    );
    assert!(share >= EMITTERS_LIGHT_SHARE && label_share < EMITTERS_LIGHT_SHARE);
    let settings = Settings::default();
    assert!(settings_lights(&cornell.settings, &cornell.scene)
        .unwrap()
        .is_empty());
    let lights = settings_lights(&settings, &board).unwrap();
    assert_eq!(lights.len(), 1, "{lights:?}");
    assert_eq!(lights[0].kind, LightKind::Point);
    // The board itself emitting at 1 through a texture black but for one texel in 64 (a
    // body whose emissive texture lights its lamps, as ToyCar's): its texture's mean counts.
    let texels: Vec<u8> = (0..64)
        .flat_map(|i| {
            if i == 0 {
                [255, 255, 255, 255]
            } else {
                [0, 0, 0, 255]
            }
        })
        .collect();
    let textured = Scene {
        materials: vec![Material {
            emission_texture: Some(TextureRef::new(0)),
            ..Material::new("body", Vec3::splat(0.5), Vec3::ONE)
        }],
        textures: vec![Texture::from_rgba8(
            "lamps",
            8,
            8,
            &texels,
            Encoding::Linear,
        )],
        meshes: vec![board.meshes[0].clone()],
        ..Default::default()
    };
    let body_share = emitters_light_share(&textured);
    println!("a board lit by one texel in 64: {body_share:.4}");
    assert!(body_share < EMITTERS_LIGHT_SHARE);
    assert_eq!(settings_lights(&settings, &textured).unwrap().len(), 1);
}
