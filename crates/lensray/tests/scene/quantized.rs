//! `KHR_mesh_quantization`: a mesh whose positions, normals and texture coordinates are
//! integers (normalized or not, as gltfpack writes them) loads to the triangles of its float
//! original, within the quantization's step.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use lensray_core::scene::{load_gltf, Mesh};

/// A vertex attribute as the file stores it: its glTF component type, whether it is
/// normalized, its type (VEC2, VEC3), the byte stride of its view and its bytes.
struct Attribute {
    semantic: &'static str,
    component: u32,
    normalized: bool,
    kind: &'static str,
    stride: usize,
    bytes: Vec<u8>,
}

const FLOAT: u32 = 5126;
const BYTE: u32 = 5120;
const UNSIGNED_BYTE: u32 = 5121;
const SHORT: u32 = 5122;
const UNSIGNED_SHORT: u32 = 5123;

/// The float original: five vertices of a bent fan, their normals and texture coordinates.
const POSITIONS: [[f32; 3]; 5] = [
    [-1.3, 0.2, 0.5],
    [2.1, -0.7, 0.1],
    [1.7, 1.9, -0.4],
    [-0.6, 2.05, 0.9],
    [0.3, -1.1, -1.2],
];
const NORMALS: [[f32; 3]; 5] = [
    [0.0, 0.0, 1.0],
    [0.6, 0.0, 0.8],
    [-0.48, 0.6, 0.64],
    [0.0, -0.8, 0.6],
    [0.267, 0.535, 0.802],
];
const TEXCOORDS: [[f32; 2]; 5] = [
    [0.0, 0.0],
    [1.0, 0.1],
    [0.93, 0.77],
    [0.25, 1.0],
    [0.5, 0.33],
];
const INDICES: [u16; 9] = [0, 1, 2, 0, 2, 3, 0, 4, 1];

/// `values` as `component`s, each element padded to `stride` bytes (glTF aligns vertex
/// attributes to 4 bytes).
fn pack<const N: usize>(values: &[[f32; N]], component: u32, stride: usize) -> Vec<u8> {
    let mut out = Vec::new();
    for v in values {
        let start = out.len();
        for &c in v {
            match component {
                FLOAT => out.extend(c.to_le_bytes()),
                BYTE => out.push(c as i8 as u8),
                UNSIGNED_BYTE => out.push(c as u8),
                SHORT => out.extend((c as i16).to_le_bytes()),
                UNSIGNED_SHORT => out.extend((c as u16).to_le_bytes()),
                _ => unreachable!("a vertex attribute's component type"),
            }
        }
        out.resize(start + stride, 0);
    }
    out
}

/// A glTF of the fan's triangles with `attributes`, under one node with `transform` (JSON
/// members of the node), requiring `KHR_mesh_quantization`.
fn write(dir: &Path, name: &str, transform: &str, attributes: &[Attribute]) -> PathBuf {
    let mut bin = Vec::new();
    let (mut views, mut accessors, mut semantics) = (Vec::new(), Vec::new(), Vec::new());
    for (i, a) in attributes.iter().enumerate() {
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}, "byteStride": {}}}"#,
            bin.len(),
            a.bytes.len(),
            a.stride
        ));
        let bounds = if a.semantic == "POSITION" {
            r#", "min": [-40000, -40000, -40000], "max": [70000, 70000, 70000]"#
        } else {
            ""
        };
        accessors.push(format!(
            r#"{{"bufferView": {i}, "componentType": {}, "normalized": {}, "count": 5, "type": "{}"{bounds}}}"#,
            a.component, a.normalized, a.kind
        ));
        semantics.push(format!(r#""{}": {i}"#, a.semantic));
        bin.extend(&a.bytes);
    }
    let n = attributes.len();
    views.push(format!(
        r#"{{"buffer": 0, "byteOffset": {}, "byteLength": 18}}"#,
        bin.len()
    ));
    accessors.push(format!(
        r#"{{"bufferView": {n}, "componentType": {UNSIGNED_SHORT}, "count": 9, "type": "SCALAR"}}"#
    ));
    bin.extend(INDICES.iter().flat_map(|i| i.to_le_bytes()));
    let bin_name = format!("{name}.bin");
    std::fs::write(dir.join(&bin_name), &bin).unwrap();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0{transform}}}],
  "meshes": [{{"primitives": [{{"attributes": {{{}}}, "indices": {n}}}]}}],
  "buffers": [{{"uri": "{bin_name}", "byteLength": {}}}],
  "bufferViews": [{}], "accessors": [{}],
  "extensionsUsed": ["KHR_mesh_quantization"], "extensionsRequired": ["KHR_mesh_quantization"]}}"#,
        semantics.join(", "),
        bin.len(),
        views.join(", "),
        accessors.join(", ")
    );
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

fn attribute<const N: usize>(
    semantic: &'static str,
    values: &[[f32; N]],
    component: u32,
    normalized: bool,
    stride: usize,
) -> Attribute {
    Attribute {
        semantic,
        component,
        normalized,
        kind: if N == 2 { "VEC2" } else { "VEC3" },
        stride,
        bytes: pack(values, component, stride),
    }
}

/// `values` times `scale`, rounded (a quantizer's integers).
fn quantized<const N: usize>(values: &[[f32; N]], scale: f32, offset: f32) -> Vec<[f32; N]> {
    values
        .iter()
        .map(|v| v.map(|c| ((c - offset) * scale).round()))
        .collect()
}

/// The largest differences between two meshes' positions, normals and texture coordinates,
/// after checking that their triangles are the same.
fn differences(a: &Mesh, b: &Mesh) -> (f32, f32, f32) {
    assert_eq!(a.triangles, b.triangles, "the same triangles");
    let worst = |d: f32, w: f32| d.max(w);
    let p = a
        .positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0, worst);
    assert_eq!(a.normals.len(), 5, "normals read");
    assert_eq!(b.normals.len(), 5, "normals read");
    let n = a
        .normals
        .iter()
        .zip(&b.normals)
        .map(|(p, q): (&Vec3, &Vec3)| (*p - *q).abs().max_element())
        .fold(0.0, worst);
    assert_eq!(b.texcoords.len(), 5, "texture coordinates read");
    let t = a
        .texcoords
        .iter()
        .zip(&b.texcoords)
        .map(|(p, q): (&Vec2, &Vec2)| (*p - *q).abs().max_element())
        .fold(0.0, worst);
    (p, n, t)
}

#[test]
fn a_quantized_mesh_loads_to_the_triangles_of_its_float_original() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let original = write(
        d,
        "float",
        "",
        &[
            attribute("POSITION", &POSITIONS, FLOAT, false, 12),
            attribute("NORMAL", &NORMALS, FLOAT, false, 12),
            attribute("TEXCOORD_0", &TEXCOORDS, FLOAT, false, 8),
        ],
    );
    let original = load_gltf(&original).unwrap().scene.meshes.remove(0);

    // gltfpack's way: positions as integers in steps of 1/1024 m from an origin that the node's
    // transform restores, normals as normalized bytes, texture coordinates as normalized
    // unsigned shorts.
    let step = 1.0 / 1024.0;
    let origin = -1.5;
    let unsigned = write(
        d,
        "unsigned",
        &format!(
            r#", "translation": [{origin}, {origin}, {origin}], "scale": [{step}, {step}, {step}]"#
        ),
        &[
            attribute(
                "POSITION",
                &quantized(&POSITIONS, 1024.0, origin),
                UNSIGNED_SHORT,
                false,
                8,
            ),
            attribute("NORMAL", &quantized(&NORMALS, 127.0, 0.0), BYTE, true, 4),
            attribute(
                "TEXCOORD_0",
                &quantized(&TEXCOORDS, 65535.0, 0.0),
                UNSIGNED_SHORT,
                true,
                4,
            ),
        ],
    );
    // Normalized signed positions scaled back by the node (extent 2.5 m), shorts for normals,
    // unsigned bytes for texture coordinates.
    let extent = 2.5;
    let signed = write(
        d,
        "signed",
        &format!(r#", "scale": [{extent}, {extent}, {extent}]"#),
        &[
            attribute(
                "POSITION",
                &quantized(&POSITIONS, 32767.0 / extent, 0.0),
                SHORT,
                true,
                8,
            ),
            attribute("NORMAL", &quantized(&NORMALS, 32767.0, 0.0), SHORT, true, 8),
            attribute(
                "TEXCOORD_0",
                &quantized(&TEXCOORDS, 255.0, 0.0),
                UNSIGNED_BYTE,
                true,
                4,
            ),
        ],
    );
    // Each within half its step (and a float's rounding): positions 1/2048 m and
    // 2.5/65534 m; normals, renormalized, within a step of 1/127 and 1/32767; texture
    // coordinates 1/131070 and 1/510.
    let cases = [
        (
            "unsigned",
            unsigned,
            [0.5 * step, 1.0 / 127.0, 0.5 / 65535.0],
        ),
        (
            "signed",
            signed,
            [0.5 * extent / 32767.0, 1.0 / 32767.0, 0.5 / 255.0],
        ),
    ];
    for (name, path, bounds) in cases {
        let file = load_gltf(&path).unwrap_or_else(|e| panic!("{name} should load: {e}"));
        let mesh = &file.scene.meshes[0];
        let (p, n, t) = differences(&original, mesh);
        println!("{name}: positions within {p} m, normals {n}, texture coordinates {t}");
        let allowed = bounds.map(|b| b * 1.01 + 1e-6);
        assert!(
            p <= allowed[0] && n <= allowed[1] && t <= allowed[2],
            "{name}: positions differ by {p} (allowed {}), normals by {n} ({}), texture coordinates by {t} ({})",
            allowed[0],
            allowed[1],
            allowed[2]
        );
        assert!(file.notices.is_empty(), "{name}: {:?}", file.notices);
    }
}
