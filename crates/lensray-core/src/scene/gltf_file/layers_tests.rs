//! What the layered extensions' JSON puts in a material.

use glam::Vec3;

use super::super::materials::texcoord_tests::{texels, write_triangle};
use crate::interface::DEFAULT_IOR;
use crate::scene::gltf_file::load_gltf;

/// Transmission with its texture, the index of refraction and a volume's attenuation are
/// read, and the extensions are not named as ignored; without a volume (or with a thickness
/// of 0) the surface is a thin wall.
#[test]
fn transmission_index_and_volume_are_read() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let material = r#"{"extensions": {
        "KHR_materials_transmission": {"transmissionFactor": 0.9,
          "transmissionTexture": {"index": 0, "texCoord": 1}},
        "KHR_materials_ior": {"ior": 1.33},
        "KHR_materials_volume": {"thicknessFactor": 0.1,
          "attenuationColor": [0.5, 1.0, 0.25], "attenuationDistance": 2.0}}}"#;
    let extra = texels(
        dir.path(),
        [128, 0, 0, 255],
        r#""KHR_materials_transmission", "KHR_materials_ior",
    "KHR_materials_volume""#,
    );
    let load = |material: &str| {
        let path = write_triangle(dir.path(), material, &extra);
        let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
        println!("notices: {:?}", file.notices);
        assert!(
            file.notices.iter().all(|n| !n.contains("KHR_materials")),
            "{:?}",
            file.notices
        );
        file.scene.materials[0].clone()
    };
    let glass = load(material);
    let wall = load(
        r#"{"extensions": {"KHR_materials_transmission": {"transmissionFactor": 3},
        "KHR_materials_volume": {"thicknessFactor": 0}}}"#,
    );
    assert_eq!(glass.transmission, 0.9);
    assert_eq!(glass.transmission_texture.map(|t| t.texcoord_set), Some(1));
    assert_eq!(glass.ior, 1.33);
    assert!(!glass.thin);
    // glTF's default is single-sided; a volume's boundary is drawn from both sides.
    assert!(glass.double_sided);
    let want = Vec3::new(0.5f32.ln(), 0.0, 0.25f32.ln()) / -2.0;
    println!("attenuation {} against {want}", glass.attenuation);
    assert!(glass.attenuation.abs_diff_eq(want, 1e-6));
    // A factor past 1 is clamped; a thickness of 0 is a thin wall of the default index.
    assert_eq!(wall.transmission, 1.0);
    assert!(wall.thin);
    assert!(!wall.double_sided);
    assert_eq!(wall.ior, DEFAULT_IOR);
    assert_eq!(wall.attenuation, Vec3::ZERO);
}
