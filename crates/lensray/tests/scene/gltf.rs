//! glTF loading: node transforms, primitives, materials, cameras (against the glTF
//! specification's projection) and the errors of broken files.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3, Vec4};
use lensray_core::scene::texture::Wrap;
use lensray_core::scene::{load, load_gltf, SceneError};
use lensray_core::settings::shot;

use crate::load_err;

/// Little-endian bytes of `values`.
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A glTF of one triangle (positions in `triangle.bin`, indices after them) under `nodes`
/// (JSON of the node array, node 0 the root), with `extra` top-level JSON members.
pub(crate) fn write_gltf(
    dir: &Path,
    name: &str,
    nodes: &str,
    positions: [f32; 9],
    extra: &str,
) -> PathBuf {
    let mut bin = f32_bytes(&positions);
    bin.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("triangle.bin"), &bin).unwrap();
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": {nodes},
  "meshes": [{{"name": "tri", "primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0}}]}}],
  "materials": [{{"name": "paint", "doubleSided": true, "pbrMetallicRoughness": {{"baseColorFactor": [0.2, 0.4, 0.6, 1.0], "metallicFactor": 0.0}},
                 "emissiveFactor": [1.0, 0.5, 0.0],
                 "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": 4.0}}}}}}],
  "buffers": [{{"uri": "triangle.bin", "byteLength": 44}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
                  {{"buffer": 0, "byteOffset": 36, "byteLength": 8}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [-10, -10, -10], "max": [10, 10, 10]}},
                {{"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}}],
  "extensionsUsed": ["KHR_materials_emissive_strength"]{extra}
}}"#
    );
    let path = dir.join(name);
    std::fs::write(&path, json).unwrap();
    path
}

pub(crate) const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

#[test]
fn node_transforms_compose_parent_first() {
    let dir = tempfile::tempdir().unwrap();
    // Root: translate (10, 0, 0); child: rotate 90 degrees about +z, scale 2, translate +y.
    let s = (PI / 4.0).sin();
    let nodes = format!(
        r#"[{{"translation": [10, 0, 0], "children": [1]}},
            {{"mesh": 0, "rotation": [0, 0, {s}, {s}], "scale": [2, 2, 2], "translation": [0, 1, 0]}}]"#
    );
    let path = write_gltf(dir.path(), "nodes.gltf", &nodes, TRIANGLE, "");
    let file = load_gltf(&path).unwrap();
    let mesh = &file.scene.meshes[0];
    let expected = [
        Vec3::new(10.0, 1.0, 0.0),
        Vec3::new(10.0, 3.0, 0.0),
        Vec3::new(8.0, 1.0, 0.0),
    ];
    for (p, e) in mesh.positions.iter().zip(expected) {
        assert!(
            (*p - e).length() < 1e-5,
            "{:?} != {expected:?}",
            mesh.positions
        );
    }
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    let m = &file.scene.materials[0];
    assert_eq!(m.diffuse, Vec3::new(0.2, 0.4, 0.6));
    // metallicFactor as given, glTF's default roughnessFactor, the full specular lobe.
    assert_eq!((m.metallic, m.roughness, m.specular), (0.0, 1.0, 1.0));
    assert_eq!(m.emission, Vec3::new(4.0, 2.0, 0.0));
    assert!(file.notices.is_empty(), "{:?}", file.notices);

    // A matrix that mirrors keeps the triangle counter-clockwise in the world.
    let nodes = r#"[{"mesh": 0, "matrix": [-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]"#;
    let path = write_gltf(dir.path(), "mirror.gltf", nodes, TRIANGLE, "");
    let mesh = &load_gltf(&path).unwrap().scene.meshes[0];
    assert_eq!(mesh.triangles, vec![[0, 2, 1]]);
}

#[test]
fn vertex_colours_and_tangents_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_gltf(dir.path(), "colours.gltf", r#"[{"mesh": 0}]"#, TRIANGLE, "");
    // COLOR_0 (RGB: alpha 1) reads the positions' accessor.
    let text = std::fs::read_to_string(&path).unwrap().replace(
        r#""attributes": {"POSITION": 0}"#,
        r#""attributes": {"POSITION": 0, "COLOR_0": 0}"#,
    );
    std::fs::write(&path, text).unwrap();
    let file = load_gltf(&path).unwrap();
    assert!(file.notices.is_empty(), "{:?}", file.notices);
    let mesh = &file.scene.meshes[0];
    let expected: Vec<Vec4> = TRIANGLE
        .chunks(3)
        .map(|p| Vec4::new(p[0], p[1], p[2], 1.0))
        .collect();
    assert_eq!(mesh.colours, expected);

    // TANGENT in world space: turned with the node, w negated where the node mirrors.
    let tangents = [1.0f32, 0.0, 0.0, 1.0].repeat(3);
    let mut bin = f32_bytes(&TRIANGLE);
    bin.extend(f32_bytes(&tangents));
    std::fs::write(dir.path().join("tangents.bin"), &bin).unwrap();
    for (matrix, expected) in [
        (
            "0,1,0,0, -1,0,0,0, 0,0,1,0, 0,0,0,1",
            Vec4::new(0.0, 1.0, 0.0, 1.0),
        ),
        (
            "-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1",
            Vec4::new(-1.0, 0.0, 0.0, -1.0),
        ),
    ] {
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, "matrix": [{matrix}]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TANGENT": 1}}}}]}}],
  "buffers": [{{"uri": "tangents.bin", "byteLength": 84}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 48}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}},
                {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC4"}}]}}"#
        );
        let path = dir.path().join("tangents.gltf");
        std::fs::write(&path, json).unwrap();
        let mesh = load_gltf(&path).unwrap().scene.meshes.remove(0);
        for t in &mesh.tangents {
            assert!(
                t.abs_diff_eq(expected, 1e-6),
                "matrix {matrix}: tangent {t}, expected {expected}"
            );
        }
        assert_eq!(mesh.tangents.len(), 3);
    }
}

#[test]
fn the_file_camera_projects_as_the_gltf_specification_says() {
    let dir = tempfile::tempdir().unwrap();
    // The camera at (1, 2, 5) turned 20 degrees about +y (so it looks down -z turned toward -x).
    let half = 10f64.to_radians();
    let (yfov, aspect) = (0.7f64, 1.5f64);
    let nodes = format!(
        r#"[{{"mesh": 0, "children": [1]}},
            {{"camera": 0, "translation": [1, 2, 5], "rotation": [0, {}, 0, {}]}}]"#,
        half.sin(),
        half.cos()
    );
    let cameras = format!(
        r#", "cameras": [{{"name": "hero", "type": "perspective",
             "perspective": {{"yfov": {yfov}, "aspectRatio": {aspect}, "znear": 0.1, "zfar": 100}}}}]"#
    );
    let big = [-2.0, -1.0, -3.0, 3.0, 0.5, -4.0, 0.0, 4.0, -6.0];
    let path = write_gltf(dir.path(), "camera.gltf", &nodes, big, &cameras);
    let description = load(&path).unwrap();
    assert_eq!(
        description.camera_summary().unwrap(),
        "hero (camera 0 of 1 in the file)"
    );
    let resolved = shot(&description.settings, &description.scene).unwrap();
    let camera = &resolved.camera;
    assert_eq!((camera.width, camera.height), (720, 480));

    // The specification: view space by the node's inverse, then the projection matrix.
    let rotation = glam::DQuat::from_rotation_y(2.0 * half);
    let view_from_world = (glam::DMat4::from_translation(DVec3::new(1.0, 2.0, 5.0))
        * glam::DMat4::from_quat(rotation))
    .inverse();
    let t = (0.5 * yfov).tan();
    for p in big.chunks_exact(3) {
        let world = DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
        let v = view_from_world.transform_point3(world);
        let ndc = [v.x / (aspect * t * -v.z), v.y / (t * -v.z)];
        let pixel = [(ndc[0] + 1.0) * 0.5 * 720.0, (1.0 - ndc[1]) * 0.5 * 480.0];
        let got = camera.project(world.as_vec3());
        let error = (f64::from(got.x) - pixel[0]).hypot(f64::from(got.y) - pixel[1]);
        assert!(
            error < 1e-3,
            "vertex {world}: lensray puts it at ({}, {}), the specification at {pixel:?}",
            got.x,
            got.y
        );
    }

    // --camera with a name that is not there names those that are.
    let mut description = description;
    let e = description.use_camera("villain").unwrap_err();
    assert!(e.contains("0: hero"), "{e}");
}

#[test]
fn the_bundled_gltf_loads_alike_from_files_and_data_uris() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/BoxTextured");
    let split = load_gltf(&root.join("BoxTextured.gltf")).unwrap();
    let embedded = load_gltf(&root.join("BoxTextured_embedded.gltf")).unwrap();
    assert_eq!(split.scene, embedded.scene);
    assert_eq!(split.scene.triangle_count(), 12);
    assert!(split
        .scene
        .meshes
        .iter()
        .all(|m| m.normals.len() == m.positions.len()));
    // The Cesium logo, sRGB, mip-mapped down to 1 x 1, read with REPEAT by coordinates
    // reaching 6.
    let textures = &split.scene.textures;
    assert_eq!(textures.len(), 1);
    let logo = &textures[0];
    assert_eq!((logo.levels[0].width, logo.levels[0].height), (256, 256));
    assert_eq!(logo.levels.len(), 9);
    let material = &split.scene.materials[0];
    let base = material.diffuse_texture.expect("a base colour texture");
    assert_eq!(base.wrap, [Wrap::Repeat; 2]);
    assert_eq!(material.alpha_texture, Some(base));
    let reach = split.scene.meshes[0]
        .texcoords
        .iter()
        .fold(0.0f32, |m, t| m.max(t.max_element()));
    assert!(reach > 5.0, "texture coordinates reach {reach}");
}

/// `normalTexture` is read as linear data with its scale and `KHR_texture_transform`; a mesh
/// without texture coordinates has no tangents for it, which one notice says.
#[test]
fn a_normal_texture_loads_with_its_scale_and_transform() {
    use glam::Vec2;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([128u8, 128, 255, 255]))
        .save(d.join("normal.png"))
        .unwrap();
    let path = write_gltf(d, "normal.gltf", r#"[{"mesh": 0}]"#, TRIANGLE, "");
    let materials = r#""materials": [{"name": "bumpy", "doubleSided": true, "normalTexture": {"index": 0,
        "scale": 0.7, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0],
        "scale": [2, 2]}}}}],
      "textures": [{"source": 0}], "images": [{"uri": "normal.png"}],"#;
    let text = std::fs::read_to_string(&path).unwrap();
    let start = text.find(r#""materials""#).unwrap();
    let end = text.find(r#""buffers""#).unwrap();
    std::fs::write(
        &path,
        format!("{}{materials}\n  {}", &text[..start], &text[end..]),
    )
    .unwrap();
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let m = &file.scene.materials[0];
    let normal = m.normal_texture.expect("a normal texture");
    assert_eq!(m.normal_scale, 0.7);
    assert_eq!(
        file.scene.textures[normal.texture as usize].encoding,
        lensray_core::scene::texture::Encoding::Linear
    );
    let uv = normal
        .uv_from_texcoord
        .transform_point2(Vec2::new(1.0, 1.0));
    assert!(uv.abs_diff_eq(Vec2::new(2.5, 2.0), 1e-6), "uv {uv}");
    assert_eq!(file.notices.len(), 1, "{:?}", file.notices);
    assert!(
        file.notices[0].ends_with(
            "renders without the normal maps of tri (no texture coordinates, or no triangle with three \
             distinct corners, to find tangents by)"
        ),
        "{:?}",
        file.notices
    );
}

/// `metallicRoughnessTexture` (B metallic, G roughness) and `occlusionTexture` (R, with its
/// strength) are read as linear data, the same image as base colour as sRGB beside it; none of
/// them is named in a notice.
#[test]
fn metallic_roughness_and_occlusion_textures_load_as_data() {
    use glam::Vec2;
    use lensray_core::scene::texture::FootprintSets;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let pixel = image::Rgba([64u8, 128, 255, 255]);
    image::RgbaImage::from_pixel(2, 2, pixel)
        .save(d.join("data.png"))
        .unwrap();
    let nodes = r#"[{"mesh": 0}]"#;
    let path = write_gltf(d, "pbr.gltf", nodes, TRIANGLE, "");
    let materials = r#""materials": [{"name": "pbr", "doubleSided": true, "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicFactor": 0.8, "roughnessFactor": 0.5,
        "metallicRoughnessTexture": {"index": 0}},
        "occlusionTexture": {"index": 0, "strength": 0.5}}],
      "textures": [{"source": 0}], "images": [{"uri": "data.png"}],"#;
    let text = std::fs::read_to_string(&path).unwrap();
    let start = text.find(r#""materials""#).unwrap();
    let end = text.find(r#""buffers""#).unwrap();
    std::fs::write(
        &path,
        format!("{}{materials}\n  {}", &text[..start], &text[end..]),
    )
    .unwrap();
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let m = &file.scene.materials[0];
    let textures = &file.scene.textures;
    assert_eq!(textures.len(), 2, "the image as colour and as data");
    let (mr, occlusion) = (
        m.metallic_roughness_texture.unwrap(),
        m.occlusion_texture.unwrap(),
    );
    assert_eq!(mr.texture, occlusion.texture);
    assert_ne!(Some(mr.texture), m.diffuse_texture.map(|t| t.texture));
    let footprint = FootprintSets::default();
    let texcoords = [Vec2::splat(0.5); 2];
    let (metallic, roughness) = m.metallic_roughness_at(textures, &texcoords, &footprint);
    // Linear: B 255 -> 1, G 128 -> 128 / 255, R 64 -> 64 / 255.
    let want = (0.8, 0.5 * 128.0 / 255.0);
    println!("metallic, roughness: ({metallic}, {roughness}), want {want:?}");
    assert!((metallic - want.0).abs() < 1e-6 && (roughness - want.1).abs() < 1e-6);
    let got = m.occlusion_at(textures, &texcoords, &footprint);
    let want = 1.0 + 0.5 * (64.0 / 255.0 - 1.0);
    println!("occlusion: {got}, want {want}");
    assert!((got - want).abs() < 1e-6);
    // The base colour is the sRGB decoding of the same texels: R 64 is 0.0513.
    let base = m.diffuse_at(textures, &texcoords, &footprint);
    assert!((base.x - 0.051_269_5).abs() < 1e-4, "{base}");
    assert!(file.notices.is_empty(), "{:?}", file.notices);

    // KHR_materials_specular: its factor weighs the lobe; its colour is named as not drawn.
    let text = std::fs::read_to_string(&path).unwrap().replace(
        r#""strength": 0.5}}"#,
        r#""strength": 0.5},
        "extensions": {"KHR_materials_specular": {"specularFactor": 0.25,
                                                  "specularColorFactor": [1, 0.5, 0.5]}}}"#,
    );
    std::fs::write(&path, text).unwrap();
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(file.scene.materials[0].specular, 0.25);
    assert_eq!(file.notices.len(), 1, "{:?}", file.notices);
    assert!(
        file.notices[0].ends_with("shading: KHR_materials_specular's colour and textures"),
        "{:?}",
        file.notices
    );
}

#[test]
fn broken_gltf_files_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let nodes = r#"[{"mesh": 0}]"#;
    let cases: Vec<(PathBuf, &str)> = vec![
        (
            write_gltf(
                d,
                "required.gltf",
                nodes,
                TRIANGLE,
                r#", "extensionsRequired": ["KHR_draco_mesh_compression"]"#,
            ),
            "requires the extension KHR_draco_mesh_compression",
        ),
        (
            write_gltf(
                d,
                "nan.gltf",
                nodes,
                [f32::NAN, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
                "",
            ),
            "is not finite",
        ),
    ];
    for (path, says) in &cases {
        let e = load_err(path, path.file_name().unwrap().to_str().unwrap());
        assert!(matches!(e, SceneError::Gltf { .. }), "{e:?}");
        assert!(e.to_string().contains(says), "{e}");
        assert!(!e.to_string().contains('\n'), "{e}");
    }

    // A buffer shorter than it says, and a missing one.
    let path = write_gltf(d, "short.gltf", nodes, TRIANGLE, "");
    std::fs::write(d.join("triangle.bin"), [0u8; 20]).unwrap();
    let e = load_err(&path, "short.gltf");
    assert!(
        e.to_string().contains("fewer than its byteLength 44"),
        "{e}"
    );
    std::fs::remove_file(d.join("triangle.bin")).unwrap();
    let e = load_err(&path, "short.gltf");
    assert!(e.to_string().contains("buffer 0 (triangle.bin)"), "{e}");

    // An accessor reaching past its view.
    let text = std::fs::read_to_string(write_gltf(d, "range.gltf", nodes, TRIANGLE, ""))
        .unwrap()
        .replace(
            r#""count": 3, "type": "VEC3""#,
            r#""count": 4, "type": "VEC3""#,
        );
    std::fs::write(d.join("range.gltf"), text).unwrap();
    let e = load_err(&d.join("range.gltf"), "range.gltf");
    assert!(
        e.to_string()
            .contains("accessor 0 (4 elements) ends at byte 48"),
        "{e}"
    );

    // A GLB whose chunk is cut short.
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(100u32.to_le_bytes());
    glb.extend(80u32.to_le_bytes());
    glb.extend(b"JSON{}");
    std::fs::write(d.join("cut.glb"), glb).unwrap();
    let e = load_err(&d.join("cut.glb"), "cut.glb");
    assert!(matches!(e, SceneError::Gltf { .. }), "{e:?}");
}

/// A node hierarchy is walked without recursion: a cycle and a node with two parents are one
/// line naming the nodes, and a chain 100 000 nodes deep loads.
#[test]
fn node_cycles_and_deep_hierarchies_are_walked_without_recursion() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = [
        (
            "cycle.gltf",
            r#"[{"mesh": 0, "children": [1]}, {"children": [2]}, {"children": [1]}]"#,
            "the node hierarchy has a cycle: nodes 1 -> 2 -> 1",
        ),
        (
            "self.gltf",
            r#"[{"mesh": 0, "children": [0]}]"#,
            "the node hierarchy has a cycle: nodes 0 -> 0",
        ),
        (
            "shared.gltf",
            r#"[{"children": [1, 2]}, {"children": [3]}, {"children": [3]}, {"mesh": 0}]"#,
            "node 3 is reached twice",
        ),
    ];
    for (name, nodes, says) in cases {
        let e = load_err(&write_gltf(d, name, nodes, TRIANGLE, ""), name);
        assert!(matches!(e, SceneError::Gltf { .. }), "{e:?}");
        assert!(e.to_string().contains(says), "{name}: {e}");
        assert!(!e.to_string().contains('\n'), "{e}");
    }

    let depth = 100_000;
    let mut nodes: Vec<String> = (1..depth)
        .map(|i| format!(r#"{{"children": [{i}], "translation": [0.0, 0.0, -1e-5]}}"#))
        .collect();
    nodes.push(r#"{"mesh": 0}"#.into());
    let path = write_gltf(
        d,
        "deep.gltf",
        &format!("[{}]", nodes.join(",")),
        TRIANGLE,
        "",
    );
    let file = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let z = file.scene.meshes[0].positions[0].z;
    println!("the deepest node's triangle at z = {z} (expected -1)");
    assert!((z + 1.0).abs() < 1e-3, "z = {z}");
}
