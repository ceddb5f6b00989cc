//! What a mesh's vertices add to its material, from glTF files: vertex colours (COLOR_0, float
//! RGB and normalized UNSIGNED_BYTE RGBA) multiply the base colour, and a normal map
//! (`normalTexture` with its scale, tangents from MikkTSpace) tilts the shading normal; a clear
//! coat's own map (`clearcoatNormalTexture`) tilts the coat's normal alone. The CPU reference is
//! checked against the formulas, every GPU path against the CPU.

mod gpu_support;

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use gpu_support::{assert_gpu_paths_match_cpu, render_scene, settings, write_png};
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::sampler::CameraSample;
use lensray_core::scene::{load_gltf, Light, LightKind, Scene};
use lensray_core::settings::{Shading, Shot};

/// The quad's base colour factor.
const BASE: Vec3 = Vec3::new(0.8, 0.6, 1.0);

/// Little-endian bytes of `values`.
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Float RGB colours of the quad's corners (x = -1, 1, 1, -1): red falls and blue rises
/// from left to right.
const LEFT_RGB: [f32; 3] = [1.0, 0.5, 0.25];
const RIGHT_RGB: [f32; 3] = [0.25, 0.5, 1.0];
/// Normalized UNSIGNED_BYTE RGBA colours of the second quad's left and right corners.
const LEFT_U8: [u8; 4] = [51, 255, 102, 128];
const RIGHT_U8: [u8; 4] = [204, 0, 153, 255];

/// A glTF file of two 2 x 2 quads facing +z at x in [-2.1, -0.1] (COLOR_0 float RGB) and
/// [0.1, 2.1] (COLOR_0 normalized UNSIGNED_BYTE RGBA), with normals and texture coordinates
/// (u along +x, v down along -y), the colours only where `coloured`, each quad's material given
/// by `materials` (JSON, the `materials` array) and `extra` top-level JSON members.
fn write_quads(dir: &Path, name: &str, coloured: bool, materials: &str, extra: &str) -> PathBuf {
    let positions = [
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ];
    let normals = [0.0, 0.0, 1.0].repeat(4);
    let texcoords = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let rgb: Vec<f32> = [LEFT_RGB, RIGHT_RGB, RIGHT_RGB, LEFT_RGB].concat();
    let mut bin = f32_bytes(&positions); // 0: 48 bytes
    bin.extend(f32_bytes(&normals)); // 48: 48
    bin.extend(f32_bytes(&texcoords)); // 96: 32
    bin.extend(f32_bytes(&rgb)); // 128: 48
    bin.extend([LEFT_U8, RIGHT_U8, RIGHT_U8, LEFT_U8].concat()); // 176: 16
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes())); // 192: 12
    std::fs::write(dir.join("quads.bin"), &bin).unwrap();
    let view = |offset: usize, length: usize| {
        format!(r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {length}}}"#)
    };
    let views = [
        view(0, 48),
        view(48, 48),
        view(96, 32),
        view(128, 48),
        view(176, 16),
        view(192, 12),
    ]
    .join(", ");
    let attributes = |colour: u32| {
        let colour = if coloured {
            format!(r#", "COLOR_0": {colour}"#)
        } else {
            String::new()
        };
        format!(r#"{{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2{colour}}}"#)
    };
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{{"mesh": 0, "translation": [-1.1, 0, 0]}}, {{"mesh": 1, "translation": [1.1, 0, 0]}}],
  "meshes": [{{"primitives": [{{"attributes": {a}, "indices": 5, "material": 0}}]}},
             {{"primitives": [{{"attributes": {b}, "indices": 5, "material": 1}}]}}],
  "materials": {materials},
  "buffers": [{{"uri": "quads.bin", "byteLength": {len}}}],
  "bufferViews": [{views}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}},
    {{"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 4, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC4"}},
    {{"bufferView": 5, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
  "extensionsUsed": ["KHR_materials_specular"]{extra}
}}"#,
        a = attributes(3),
        b = attributes(4),
        len = bin.len(),
    );
    let path = dir.join(name);
    std::fs::write(&path, json).unwrap();
    path
}

/// A Lambert material (`KHR_materials_specular` 0) of base colour `BASE` with `more` JSON
/// members.
fn lambert(more: &str) -> String {
    format!(
        r#"{{"doubleSided": true,
            "pbrMetallicRoughness": {{"baseColorFactor": [{}, {}, {}, 1], "metallicFactor": 0}},
            "extensions": {{"KHR_materials_specular": {{"specularFactor": 0}}}}{more}}}"#,
        BASE.x, BASE.y, BASE.z
    )
}

/// An orthographic camera looking down -z at both quads, `width` x `width / 2` pixels.
fn camera(width: u32) -> Camera {
    camera_at(0.0, 2.4, width, width / 2)
}

/// An orthographic camera looking down -z at (0, `y`, 0), `ortho_height` high, `width` x
/// `height` pixels.
fn camera_at(y: f32, ortho_height: f64, width: u32, height: u32) -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, y, 5.0),
        target: Vec3::new(0.0, y, 0.0),
        up: Vec3::Y,
        projection: ProjectionParams::Orthographic {
            height: ortho_height,
        },
        lens: LensParams::Pinhole,
        near: 0.1,
        far: 100.0,
        width,
        height,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera")
}

/// The pixel whose centre ray meets z = 0 nearest `p`, and the point it meets there.
fn pixel_at(camera: &Camera, p: Vec3) -> ((u32, u32), Vec3) {
    let raster = camera.project(p);
    let pixel = (raster.x as u32, raster.y as u32);
    let ray = camera.first_order_ray(CameraSample::new(
        Vec2::new(pixel.0 as f32 + 0.5, pixel.1 as f32 + 0.5),
        Vec2::splat(0.5),
    ));
    let t = -ray.origin.z / ray.direction.z;
    (pixel, ray.at(t))
}

fn value(image: &Image, (x, y): (u32, u32)) -> Vec3 {
    image.pixels[(y * image.width + x) as usize]
}

/// `scene` through `camera` on the CPU path, shaded `shading` at `spp` samples a pixel.
fn cpu_render(
    test: &str,
    scene: &Scene,
    camera: &Camera,
    shading: Shading,
    spp: u32,
) -> Option<Image> {
    let shot = Shot {
        camera: camera.clone(),
        render: settings(shading, spp),
    };
    render_scene(test, PathChoice::Only(PathKind::Cpu), scene, &shot)
}

/// The two quads of vertex colours under a point light.
fn coloured_quads(dir: &Path) -> Scene {
    let materials = format!("[{}, {}]", lambert(""), lambert(""));
    let path = write_quads(dir, "colours.gltf", true, &materials, "");
    let file = load_gltf(&path).expect("the quads load");
    assert!(file.notices.is_empty(), "{:?}", file.notices);
    file.scene
}

/// The albedo AOV (the aperture-centre ray through each pixel centre) is the base colour times
/// the colour interpolated along x: float RGB as written, UNSIGNED_BYTE as c / 255.
#[test]
fn vertex_colours_multiply_the_base_colour() {
    let test = "vertex_colours_multiply_the_base_colour";
    let dir = tempfile::tempdir().unwrap();
    let scene = coloured_quads(dir.path());
    let camera = camera(64);
    let Some(image) = cpu_render(test, &scene, &camera, Shading::Albedo, 1) else {
        return;
    };
    let u8_colour = |c: [u8; 4]| Vec3::new(c[0].into(), c[1].into(), c[2].into()) / 255.0;
    let quads = [
        (-1.1, Vec3::from(LEFT_RGB), Vec3::from(RIGHT_RGB)),
        (1.1, u8_colour(LEFT_U8), u8_colour(RIGHT_U8)),
    ];
    for (centre, left, right) in quads {
        for x in [-0.7, -0.2, 0.3, 0.8] {
            let (pixel, p) = pixel_at(&camera, Vec3::new(centre + x, 0.3, 0.0));
            let f = (p.x - centre + 1.0) / 2.0;
            let expected = BASE * left.lerp(right, f);
            let got = value(&image, pixel);
            assert!(
                (got - expected).abs().max_element() < 1e-4,
                "pixel {pixel:?} at x = {}: {got}, expected {BASE} x {} = {expected}",
                p.x,
                left.lerp(right, f)
            );
        }
    }
}

/// A normal map of one texel, `name`, its normal tilted by `degrees` about the bitangent
/// towards the tangent (+x): (sin, 0, cos) encoded as 8-bit 2 c - 1; returns the normal as the
/// file holds it, decoded from the bytes.
fn write_normal_map(dir: &Path, name: &str, degrees: f32) -> Vec3 {
    let (sin, cos) = degrees.to_radians().sin_cos();
    let byte = |c: f32| ((c + 1.0) / 2.0 * 255.0).round() as u8;
    let bytes = [byte(sin), byte(0.0), byte(cos), 255];
    image::RgbaImage::from_pixel(4, 4, image::Rgba(bytes))
        .save(dir.join(name))
        .unwrap();
    Vec3::new(bytes[0].into(), bytes[1].into(), bytes[2].into()) / 255.0 * 2.0 - Vec3::ONE
}

/// Under a directional light arriving at 40 degrees from +x, a Lambert quad's radiance is
/// Kd / pi E n.l with n the map's normal (m.x s, m.y s, m.z) normalized, s its scale, in the
/// frame (+x, +y, +z) MikkTSpace gives the quad: the left quad's map at scale 1, the right
/// one's at scale 0.5 (tilted less). Every GPU path renders it as the CPU does.
/// The quads with the normal map (scale 1 on the left, 0.5 on the right) under a directional
/// light arriving from `to_light` with irradiance `irradiance`; the map's normal.
fn normal_mapped_quads(dir: &Path, to_light: Vec3, irradiance: f32) -> (Scene, Vec3) {
    let m = write_normal_map(dir, "normal.png", 30.0);
    let normal_texture =
        |scale: f32| format!(r#", "normalTexture": {{"index": 0, "scale": {scale}}}"#);
    let materials = format!(
        "[{}, {}]",
        lambert(&normal_texture(1.0)),
        lambert(&normal_texture(0.5))
    );
    let textures = r#", "images": [{"uri": "normal.png"}], "textures": [{"source": 0}]"#;
    let path = write_quads(dir, "normal.gltf", false, &materials, textures);
    let file = load_gltf(&path).expect("the quads load");
    assert!(file.notices.is_empty(), "{:?}", file.notices);
    let mut scene = file.scene;
    scene.lights = vec![Light {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: -to_light,
        intensity: Vec3::splat(irradiance),
        range: 0.0,
    }];
    (scene, m)
}

/// Under a directional light arriving at 40 degrees from +x, a Lambert quad's radiance is
/// Kd / pi E n.l with n the map's normal (m.x s, m.y s, m.z) normalized, s its scale, in the
/// frame (+x, +y, +z) MikkTSpace gives the quad: the left quad's map at scale 1, the right
/// one's at scale 0.5 (tilted less).
#[test]
fn a_normal_map_tilts_the_shading_normal() {
    let test = "a_normal_map_tilts_the_shading_normal";
    let dir = tempfile::tempdir().unwrap();
    let to_light = Vec3::new(40f32.to_radians().sin(), 0.0, 40f32.to_radians().cos());
    let irradiance = 3.0;
    let (scene, m) = normal_mapped_quads(dir.path(), to_light, irradiance);
    // Both corners of an edge share a tangent: no vertex is split.
    assert_eq!(
        scene.meshes[0].tangents.len(),
        4,
        "{:?}",
        scene.meshes[0].tangents
    );
    let camera = camera(64);
    let Some(image) = cpu_render(test, &scene, &camera, Shading::Lit, 4) else {
        return;
    };
    for (centre, scale) in [(-1.1, 1.0), (1.1, 0.5)] {
        let n = Vec3::new(m.x * scale, m.y * scale, m.z).normalize();
        let expected = BASE / std::f32::consts::PI * irradiance * n.dot(to_light);
        let flat = BASE / std::f32::consts::PI * irradiance * to_light.z;
        for (x, y) in [(-0.5, 0.5), (0.4, -0.3)] {
            let (pixel, _) = pixel_at(&camera, Vec3::new(centre + x, y, 0.0));
            let got = value(&image, pixel);
            if (got - expected).abs().max_element() > 1e-4 {
                write_png(&image, "normal-map-cpu.png");
                panic!(
                    "scale {scale}, pixel {pixel:?}: {got}, expected Kd / pi E n.l = {expected} \
                     (n = {n}; unmapped: {flat})"
                );
            }
        }
    }
}

/// The coat's roughness in `coated_quads`.
const COAT_ROUGHNESS: f32 = 0.4;

/// The quads with the base's normal map (30 degrees, scale 1) under a clear coat of weight 1 and
/// roughness `COAT_ROUGHNESS`: on the left the coat has its own map (-20 degrees, scale 0.8),
/// on the right none. Under a directional light arriving from `to_light` with irradiance
/// `irradiance`. Returns the scene and both maps' normals (base, coat) as the files hold them.
fn coated_quads(dir: &Path, to_light: Vec3, irradiance: f32) -> (Scene, Vec3, Vec3) {
    let (scene, m) = normal_mapped_quads(dir, to_light, irradiance);
    let mc = write_normal_map(dir, "coat-normal.png", -20.0);
    let coat = |own: &str| {
        format!(r#"{{"clearcoatFactor": 1, "clearcoatRoughnessFactor": {COAT_ROUGHNESS}{own}}}"#)
    };
    let material = |own: &str| {
        format!(
            r#"{{"doubleSided": true, "normalTexture": {{"index": 0}},
                "pbrMetallicRoughness": {{"baseColorFactor": [{}, {}, {}, 1], "metallicFactor": 0}},
                "extensions": {{"KHR_materials_specular": {{"specularFactor": 0}},
                                "KHR_materials_clearcoat": {}}}}}"#,
            BASE.x,
            BASE.y,
            BASE.z,
            coat(own)
        )
    };
    let materials = format!(
        "[{}, {}]",
        material(r#", "clearcoatNormalTexture": {"index": 1, "scale": 0.8}"#),
        material("")
    );
    let textures = r#", "images": [{"uri": "normal.png"}, {"uri": "coat-normal.png"}],
        "textures": [{"source": 0}, {"source": 1}]"#;
    let path = write_quads(dir, "coated.gltf", false, &materials, textures);
    let file = load_gltf(&path).expect("the coated quads load");
    assert!(file.notices.is_empty(), "{:?}", file.notices);
    let mut coated = file.scene;
    coated.lights = scene.lights;
    (coated, m, mc)
}

/// What a clear coat of weight 1 over a Lambert base reflects of a directional light of
/// irradiance `e` from `l`, seen from `v`: the specification's layering written out, each layer
/// at its own normal's cosine: Kd / pi (1 - Fc) ns.l + Fc D(nc.h) V(nc.l, nc.v) nc.l, with
/// Fc = 0.04 + 0.96 (1 - nc.v)^5, GGX's D and the height-correlated V at alpha = roughness^2.
fn coat_over_lambert(ns: Vec3, nc: Vec3, l: Vec3, v: Vec3, e: f32) -> Vec3 {
    let a2 = COAT_ROUGHNESS.powi(4);
    let h = (l + v).normalize();
    let (nl, nv, nh) = (nc.dot(l), nc.dot(v), nc.dot(h));
    let d = a2 / (std::f32::consts::PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
    let vis =
        0.5 / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt());
    let fc = 0.04 + 0.96 * (1.0 - nv).powi(5);
    (BASE / std::f32::consts::PI * (1.0 - fc) * ns.dot(l) + Vec3::splat(fc * d * vis * nl)) * e
}

/// A clear coat's own normal map tilts the coat's normal alone, and without one the coat
/// follows the vertex normal, not the base's map: under a directional light 35 degrees
/// towards -x, near the mirror of the view about the left coat's normal, each quad's radiance
/// is `coat_over_lambert` with the base's normal tilted by its map and the coat's by its own
/// (left) or not at all (right).
#[test]
fn a_clear_coat_follows_its_own_normal_map() {
    let test = "a_clear_coat_follows_its_own_normal_map";
    let dir = tempfile::tempdir().unwrap();
    let to_light = Vec3::new(-35f32.to_radians().sin(), 0.0, 35f32.to_radians().cos());
    let irradiance = 3.0;
    let (scene, m, mc) = coated_quads(dir.path(), to_light, irradiance);
    let camera = camera(64);
    let Some(image) = cpu_render(test, &scene, &camera, Shading::Lit, 4) else {
        return;
    };
    let ns = m.normalize();
    let own = Vec3::new(mc.x * 0.8, mc.y * 0.8, mc.z).normalize();
    for (centre, nc) in [(-1.1, own), (1.1, Vec3::Z)] {
        let expected = coat_over_lambert(ns, nc, to_light, Vec3::Z, irradiance);
        let unlayered = coat_over_lambert(ns, ns, to_light, Vec3::Z, irradiance);
        for (x, y) in [(-0.5, 0.5), (0.4, -0.3)] {
            let (pixel, _) = pixel_at(&camera, Vec3::new(centre + x, y, 0.0));
            let got = value(&image, pixel);
            if (got - expected).abs().max_element() > 1e-4 * expected.max_element() {
                write_png(&image, "coat-normal-cpu.png");
                panic!(
                    "coat normal {nc}, pixel {pixel:?}: {got}, expected {expected} (base \
                     normal {ns}; the coat on the base's normal would give {unlayered})"
                );
            }
        }
        println!("coat normal {nc}: {expected} (on the base's normal: {unlayered})");
    }
}

/// `scene` with `other`'s meshes moved `dy` along y, its materials, textures and lights.
fn append(scene: &mut Scene, other: Scene, dy: f32) {
    let (materials, textures) = (scene.materials.len() as u32, scene.textures.len() as u32);
    for mut mesh in other.meshes {
        for p in &mut mesh.positions {
            p.y += dy;
        }
        for id in &mut mesh.material_ids {
            *id += materials;
        }
        scene.meshes.push(mesh);
    }
    for mut material in other.materials {
        for t in [
            &mut material.normal_texture,
            &mut material.clearcoat_normal_texture,
        ]
        .into_iter()
        .flatten()
        {
            t.texture += textures;
        }
        scene.materials.push(material);
    }
    scene.textures.extend(other.textures);
    scene.lights = other.lights;
}

/// Every GPU path (the raster path and its G-buffer's albedo included) renders the coloured
/// quads and, below them, the normal-mapped ones and the coated ones with the coat's own map,
/// lit and as albedo, as the CPU does.
#[test]
fn gpu_paths_render_vertex_colours_and_normal_maps_as_the_cpu_does() {
    let test = "gpu_paths_render_vertex_colours_and_normal_maps_as_the_cpu_does";
    let dir = tempfile::tempdir().unwrap();
    let mut scene = coloured_quads(dir.path());
    let to_light = Vec3::new(0.3, 0.5, 1.0).normalize();
    let (mapped, _) = normal_mapped_quads(dir.path(), to_light, 3.0);
    append(&mut scene, mapped, -2.2);
    let (coated, _, _) = coated_quads(dir.path(), to_light, 3.0);
    append(&mut scene, coated, -4.4);
    let camera = camera_at(-2.2, 6.8, 64, 64);
    let shots = [Shading::Lit, Shading::Albedo].map(|shading| {
        let shot = Shot {
            camera: camera.clone(),
            render: settings(shading, 4),
        };
        (format!("surface-{shading:?}"), shot)
    });
    assert_gpu_paths_match_cpu(test, &scene, &shots);
}
