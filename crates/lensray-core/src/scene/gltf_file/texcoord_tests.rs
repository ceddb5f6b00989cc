//! Texture coordinate sets and missing images, read from glTF files written here: each texture
//! keeps its own set and `KHR_texture_transform` (the occlusion and normal textures' too), and a
//! missing image is reported once however many textures use it.

use std::path::{Path, PathBuf};

use base64::Engine;
use glam::Vec2;

use crate::scene::gltf_file::load_gltf;

/// Corner coordinates of the test triangle's two sets.
const SET0: [[f32; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
const SET1: [[f32; 2]; 3] = [[0.5, 0.5], [0.25, 0.5], [0.5, 0.25]];

/// A glTF of one triangle with TEXCOORD_0 and TEXCOORD_1 (its buffer a data URI), material
/// `material` (JSON), and `extra` top-level members, written into `dir`.
pub(in crate::scene::gltf_file) fn write_triangle(
    dir: &Path,
    material: &str,
    extra: &str,
) -> PathBuf {
    let positions = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let floats = positions
        .into_iter()
        .chain(SET0.into_iter().flatten())
        .chain(SET1.into_iter().flatten());
    let mut bin: Vec<u8> = floats.flat_map(f32::to_le_bytes).collect();
    bin.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}],
  "meshes": [{{"name": "tri", "primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1,
    "TEXCOORD_1": 2}}, "indices": 3, "material": 0}}]}}],
  "materials": [{material}],
  "buffers": [{{"uri": "data:application/octet-stream;base64,{data}", "byteLength": {}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
                  {{"buffer": 0, "byteOffset": 36, "byteLength": 24}},
                  {{"buffer": 0, "byteOffset": 60, "byteLength": 24}},
                  {{"buffer": 0, "byteOffset": 84, "byteLength": 8}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}},
                {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}},
                {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}},
                {{"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}}]{extra}
}}"#,
        bin.len()
    );
    let path = dir.join("triangle.gltf");
    std::fs::write(&path, json).expect("write the glTF");
    path
}

/// Writes a 2 x 2 PNG of `rgba` as `texels.png` into `dir`; returns the top-level JSON members
/// that make it texture 0, with `extensions` (a JSON list's items) used.
pub(in crate::scene::gltf_file) fn texels(dir: &Path, rgba: [u8; 4], extensions: &str) -> String {
    image::RgbaImage::from_pixel(2, 2, image::Rgba(rgba))
        .save(dir.join("texels.png"))
        .expect("write the png");
    format!(
        r#",
  "textures": [{{"source": 0}}], "images": [{{"uri": "texels.png"}}],
  "extensionsUsed": [{extensions}]"#
    )
}

/// TEXCOORD_1 is read beside TEXCOORD_0; each texture keeps its `texCoord` (a set past 1 reads
/// set 0, with one notice naming it) and its transform, the occlusion and normal textures'
/// read from the JSON (the extension's `texCoord` overriding the texture's).
#[test]
fn each_texture_keeps_its_set_and_transform() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let material = r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1},
        "metallicRoughnessTexture": {"index": 0}},
      "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0, "texCoord": 3},
      "occlusionTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
        "offset": [0.25, 0.5], "scale": [2, 3], "texCoord": 1}}},
      "normalTexture": {"index": 0, "texCoord": 1, "extensions": {"KHR_texture_transform": {
        "offset": [0.1, 0]}}}}"#;
    let extra = texels(
        dir.path(),
        [200, 100, 50, 255],
        r#""KHR_texture_transform""#,
    );
    let path = write_triangle(dir.path(), material, &extra);
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    println!("notices: {:?}", file.notices);
    let mesh = &file.scene.meshes[0];
    let (set0, set1) = (SET0.map(Vec2::from), SET1.map(Vec2::from));
    println!(
        "TEXCOORD_0 {:?}, TEXCOORD_1 {:?}",
        mesh.texcoords, mesh.texcoords1
    );
    // One triangle: the tangents split no vertex.
    assert_eq!(mesh.texcoords, set0);
    assert_eq!(mesh.texcoords1, set1);

    let m = &file.scene.materials[0];
    let set = |t: Option<crate::scene::TextureRef>| t.expect("a texture").texcoord_set;
    let sets = [
        set(m.diffuse_texture),
        set(m.metallic_roughness_texture),
        set(m.emission_texture),
        set(m.occlusion_texture),
        set(m.normal_texture),
    ];
    println!("sets (base, metallic-roughness, emissive, occlusion, normal): {sets:?}");
    assert_eq!(sets, [1, 0, 0, 1, 1]);
    let uv = |t: Option<crate::scene::TextureRef>| {
        t.unwrap()
            .uv_from_texcoord
            .transform_point2(Vec2::new(1.0, 1.0))
    };
    let (occlusion, normal, base) = (
        uv(m.occlusion_texture),
        uv(m.normal_texture),
        uv(m.diffuse_texture),
    );
    println!("(1, 1) maps to occlusion {occlusion}, normal {normal}, base {base}");
    assert!(occlusion.abs_diff_eq(Vec2::new(2.25, 3.5), 1e-6));
    assert!(normal.abs_diff_eq(Vec2::new(1.1, 1.0), 1e-6));
    assert_eq!(base, Vec2::ONE);
    // Tangents come from the normal map's set: dp/du along -x there (u falls from corner 0 to
    // corner 1 in set 1).
    println!("tangents {:?}", mesh.tangents);
    assert!(mesh.tangents[0].x < -0.99, "{:?}", mesh.tangents);

    assert_eq!(file.notices.len(), 1, "{:?}", file.notices);
    assert!(
        file.notices[0].ends_with(
            "reads textures of TEXCOORD_3 with TEXCOORD_0 (lensray reads TEXCOORD_0 and TEXCOORD_1)"
        ),
        "{:?}",
        file.notices
    );
}

/// One missing image file used by two textures, as colour and as data, gets one notice.
#[test]
fn a_missing_image_is_reported_once() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let material = r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
        "metallicRoughnessTexture": {"index": 0}},
      "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 1}}"#;
    let extra = r#",
  "textures": [{"source": 0}, {"source": 0}], "images": [{"uri": "gone.png"}]"#;
    let path = write_triangle(dir.path(), material, extra);
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    println!("notices: {:?}", file.notices);
    let missing = file
        .notices
        .iter()
        .filter(|n| n.contains("gone.png"))
        .count();
    assert_eq!(missing, 1, "{:?}", file.notices);
    assert_eq!(file.notices.len(), 1, "{:?}", file.notices);
    let m = &file.scene.materials[0];
    assert_eq!(
        (
            m.diffuse_texture,
            m.metallic_roughness_texture,
            m.emission_texture
        ),
        (None, None, None)
    );
    assert!(file.scene.textures.is_empty());
}

/// `KHR_materials_sheen`: the colour factor times its texture's RGB decoded from sRGB, the
/// roughness factor times its texture's alpha (linear), each texture with its own set and
/// transform; the one image serves both, once each encoding.
#[test]
fn the_sheen_reads_its_factors_and_textures() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let material = r#"{"extensions": {"KHR_materials_sheen": {
        "sheenColorFactor": [0.5, 0.25, 1], "sheenColorTexture": {"index": 0, "texCoord": 1},
        "sheenRoughnessFactor": 0.8, "sheenRoughnessTexture": {"index": 0,
          "extensions": {"KHR_texture_transform": {"offset": [0.5, 0]}}}}}}"#;
    let extra = texels(
        dir.path(),
        [200, 100, 50, 102],
        r#""KHR_materials_sheen", "KHR_texture_transform""#,
    );
    let path = write_triangle(dir.path(), material, &extra);
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(file.notices.is_empty(), "{:?}", file.notices);
    let m = &file.scene.materials[0];
    assert_eq!(m.sheen_colour, glam::Vec3::new(0.5, 0.25, 1.0));
    assert_eq!(m.sheen_roughness, 0.8);
    let (colour, roughness) = (
        m.sheen_colour_texture.expect("a colour texture"),
        m.sheen_roughness_texture.expect("a roughness texture"),
    );
    assert_eq!((colour.texcoord_set, roughness.texcoord_set), (1, 0));
    let uv = roughness
        .uv_from_texcoord
        .transform_point2(Vec2::new(0.25, 0.25));
    assert!(uv.abs_diff_eq(Vec2::new(0.75, 0.25), 1e-6), "uv {uv}");
    let encoding = |t: crate::scene::TextureRef| file.scene.textures[t.texture as usize].encoding;
    use crate::scene::texture::{srgb_to_linear, Encoding, FootprintSets};
    assert_eq!(encoding(colour), Encoding::Srgb);
    assert_eq!(encoding(roughness), Encoding::Linear);
    let (got_colour, got_roughness) = m.sheen_at(
        &file.scene.textures,
        &[Vec2::splat(0.5); 2],
        &FootprintSets::default(),
    );
    let want = glam::Vec3::new(
        0.5 * srgb_to_linear(200.0 / 255.0),
        0.25 * srgb_to_linear(100.0 / 255.0),
        srgb_to_linear(50.0 / 255.0),
    );
    println!("sheen at the centre: {got_colour} (want {want}), roughness {got_roughness}");
    assert!(
        got_colour.abs_diff_eq(want, 1e-5),
        "{got_colour} against {want}"
    );
    assert!((got_roughness - 0.8 * 0.4).abs() < 1e-6, "{got_roughness}");
}

/// The clear coat's own normal map is read with its set, transform and scale, without a
/// notice; a mesh whose only normal map is the coat's gets tangents in the coat map's set.
#[test]
fn the_clear_coat_reads_its_own_normal_map() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let material = r#"{"extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1,
        "clearcoatNormalTexture": {"index": 0, "texCoord": 1, "scale": 0.5,
          "extensions": {"KHR_texture_transform": {"offset": [0, 0.25]}}}}}}"#;
    let extra = texels(
        dir.path(),
        [128, 128, 255, 255],
        r#""KHR_materials_clearcoat", "KHR_texture_transform""#,
    );
    let path = write_triangle(dir.path(), material, &extra);
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(file.notices.is_empty(), "{:?}", file.notices);
    let m = &file.scene.materials[0];
    assert_eq!(m.normal_texture, None);
    let (coat, scale) = m.clearcoat_normal_map().expect("the coat's normal map");
    assert_eq!((coat.texcoord_set, scale), (1, 0.5));
    let uv = coat.uv_from_texcoord.transform_point2(Vec2::ONE);
    assert!(uv.abs_diff_eq(Vec2::new(1.0, 1.25), 1e-6), "{uv}");
    // Set 1's u falls from corner 0 to corner 1: the tangent runs along -x.
    let tangents = &file.scene.meshes[0].tangents;
    println!("tangents {tangents:?}");
    assert!(tangents.len() == 3 && tangents[0].x < -0.99, "{tangents:?}");
}
