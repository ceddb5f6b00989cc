//! Single-sided surfaces (glTF's `doubleSided: false`) on every path: a ray of any kind that
//! meets one from behind passes through it (`lensray_core::reference::is_back_face`). Two
//! single-sided quads above a floor, one facing up and one facing down, seen from above, from
//! below and through the shadows they cast: each render equals the render of the scene the rule
//! predicts (the quads that are met from the front, made double-sided; the others removed) on
//! the CPU, and every GPU path renders the single-sided scene as the CPU does. A glTF node
//! mirrored by a scale of -1 keeps its quad's front face where the file points it.

mod gpu_support;

use glam::Vec3;
use gpu_support::{
    assert_gpu_paths_match_cpu, compare, floor, material, orthographic_along_z, render_scene,
    settings, write_comparison,
};
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::{Camera, CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::scene::{Light, Material, Mesh, Scene};
use lensray_core::settings::{Shading, Shot};

/// A horizontal 0.8 x 0.8 quad at height 1.5 centred at x, facing up (+y, counter-clockwise
/// seen from above) or down.
fn quad(x: f32, up: bool, material: u32) -> Mesh {
    let h = 0.4;
    let corners = [
        Vec3::new(x - h, 1.5, -h),
        Vec3::new(x - h, 1.5, h),
        Vec3::new(x + h, 1.5, h),
        Vec3::new(x + h, 1.5, -h),
    ];
    let triangles = if up {
        vec![[0, 1, 2], [0, 2, 3]]
    } else {
        vec![[0, 2, 1], [0, 3, 2]]
    };
    Mesh {
        name: format!("quad {}", if up { "up" } else { "down" }),
        positions: corners.to_vec(),
        triangles,
        material_ids: vec![material; 2],
        ..Default::default()
    }
}

/// The floor (double-sided), the quad facing up at x = -0.6 (red) and the one facing down at
/// x = 0.6 (blue), both `double_sided` or not; `keep` says which quads are there (up, down).
fn scene(double_sided: bool, keep: [bool; 2]) -> Scene {
    let quad_material = |name: &str, colour: Vec3| Material {
        double_sided,
        ..material(name, colour, Vec3::ZERO)
    };
    let mut meshes = vec![floor(4.0, 0.0, 0)];
    if keep[0] {
        meshes.push(quad(-0.6, true, 1));
    }
    if keep[1] {
        meshes.push(quad(0.6, false, 2));
    }
    Scene {
        meshes,
        materials: vec![
            material("floor", Vec3::splat(0.7), Vec3::ZERO),
            quad_material("red", Vec3::new(0.9, 0.1, 0.1)),
            quad_material("blue", Vec3::new(0.1, 0.1, 0.9)),
        ],
        textures: vec![],
        lights: vec![Light::point(Vec3::new(0.0, 3.0, 0.0), Vec3::splat(20.0))],
        environment: None,
    }
}

/// Looking straight down from `y` (above the quads: they and the floor; below them: the floor
/// and the quads' shadows) or up from the floor.
fn camera(eye_y: f32, down: bool) -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, eye_y, 0.0),
        target: Vec3::new(0.0, if down { -1.0 } else { 10.0 }, 0.0),
        up: if down { Vec3::NEG_Z } else { Vec3::Z },
        projection: ProjectionParams::Orthographic { height: 4.0 },
        lens: LensParams::Pinhole,
        near: 0.05,
        far: 100.0,
        width: 40,
        height: 40,
        movements: Movements::NONE,
    }
    .build()
    .expect("valid camera")
}

/// The views: name, camera, shading, and which quads the rule keeps (up, down) where the
/// rays of the view meet each quad from one side only: from above only the quad facing up shows
/// its front, from below only the one facing down; a shadow ray from the floor (the camera below
/// the quads) meets the one facing down from the front and the one facing up from behind. Lit
/// from above, the camera sees one quad and the floor the other's shadow: no scene predicts it.
fn views() -> [(&'static str, Camera, Shading, Option<[bool; 2]>); 4] {
    [
        (
            "above",
            camera(4.0, true),
            Shading::Unlit,
            Some([true, false]),
        ),
        ("above-lit", camera(4.0, true), Shading::Lit, None),
        (
            "below",
            camera(0.5, false),
            Shading::Unlit,
            Some([false, true]),
        ),
        (
            "shadows",
            camera(1.0, true),
            Shading::Lit,
            Some([false, true]),
        ),
    ]
}

fn cpu(test: &str, scene: &Scene, shot: &Shot) -> Option<Image> {
    render_scene(test, PathChoice::Only(PathKind::Cpu), scene, shot)
}

/// On the CPU, each view of the single-sided quads equals the view of the scene the rule
/// predicts, and differs from the view of the quads double-sided (so the rule is what decides).
#[test]
fn single_sided_quads_are_culled_from_behind_on_the_cpu() {
    let test = "single_sided_quads_are_culled_from_behind_on_the_cpu";
    for (name, camera, shading, keep) in views() {
        let Some(keep) = keep else { continue };
        let shot = Shot {
            camera,
            render: settings(shading, 4),
        };
        let (Some(single), Some(predicted), Some(both)) = (
            cpu(test, &scene(false, [true, true]), &shot),
            cpu(test, &scene(true, keep), &shot),
            cpu(test, &scene(true, [true, true]), &shot),
        ) else {
            return;
        };
        let same = compare(&single, &predicted, 1.0 / 255.0);
        let unlike = compare(&single, &both, 1.0 / 255.0);
        println!("{name}: single-sided vs predicted {same:?}, vs double-sided {unlike:?}");
        if same.within < 0.999 || same.mean_abs >= 1e-4 {
            let files = write_comparison(&single, &predicted, &format!("sides-{name}-predicted"));
            panic!("{name}: single-sided differs from the predicted scene: {same:?}; {files}");
        }
        // A quad covers 4 % of the image, its shadow more: the double-sided scene differs
        // there.
        assert!(
            unlike.within < 0.98,
            "{name}: the double-sided quads render as the single-sided ones: {unlike:?}"
        );
    }
}

/// Every GPU path (rayquery, rtpipeline, software, raster, and the G-buffer's albedo) renders
/// each view of the single-sided quads as the CPU does; the hybrid renders them as it renders
/// the predicted scene. The front faces the rays see here are Vulkan's facing rule put to the
/// test: a flipped rule would show the other quad.
#[test]
fn gpu_paths_cull_single_sided_quads_as_the_cpu_does() {
    let test = "gpu_paths_cull_single_sided_quads_as_the_cpu_does";
    let single = scene(false, [true, true]);
    let mut shots = Vec::new();
    for (name, camera, shading, _) in views() {
        let shot = Shot {
            camera,
            render: settings(shading, 4),
        };
        if name == "above" {
            // The G-buffer's albedo AOV (the preview's) of the same view.
            let albedo = Shot {
                render: settings(Shading::Albedo, 1),
                ..shot.clone()
            };
            shots.push(("sides-above-albedo".to_string(), albedo));
        }
        shots.push((format!("sides-{name}"), shot));
    }
    assert_gpu_paths_match_cpu(test, &single, &shots);
    for (name, camera, shading, keep) in views() {
        let shot = Shot {
            camera,
            render: settings(shading, 4),
        };
        let Some(keep) = keep else { continue };
        let hybrid = PathChoice::Only(PathKind::Hybrid);
        let (Some(image), Some(predicted)) = (
            render_scene(test, hybrid, &single, &shot),
            render_scene(test, hybrid, &scene(true, keep), &shot),
        ) else {
            return;
        };
        let diff = compare(&image, &predicted, 1.0 / 255.0);
        println!("{name} hybrid vs its predicted scene: {diff:?}");
        if diff.within < 0.999 || diff.mean_abs >= 1e-3 {
            let files = write_comparison(&image, &predicted, &format!("sides-{name}-hybrid"));
            panic!("{name}: the hybrid differs from its predicted scene: {diff:?}; {files}");
        }
    }
}

/// A glTF file of a 1 x 1 quad in the plane z = 0 facing +z (counter-clockwise seen from +z),
/// red and single-sided at x = -1.2 and, mirrored by the scale (-1, 1, 1), at x = 0, and green
/// and double-sided at x = 1.2.
fn mirrored_quads(dir: &std::path::Path) -> Scene {
    let positions: [f32; 12] = [
        -0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0,
    ];
    let mut bin: Vec<u8> = positions.iter().flat_map(|v| v.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("quad.bin"), &bin).expect("write bin");
    let json = r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
  "nodes": [{"mesh": 0, "translation": [-1.2, 0, 0]},
            {"mesh": 0, "scale": [-1, 1, 1]},
            {"mesh": 1, "translation": [1.2, 0, 0]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
             {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1], "metallicFactor": 0}},
                {"doubleSided": true,
                 "pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1], "metallicFactor": 0}}],
  "buffers": [{"uri": "quad.bin", "byteLength": 60}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]}"#;
    let path = dir.join("quads.gltf");
    std::fs::write(&path, json).expect("write gltf");
    lensray_core::scene::load_gltf(&path)
        .expect("the quads load")
        .scene
}

/// Looking at the quads along -z from z = 3 (their front) or along +z from z = -3.
fn front_or_back(front: bool) -> Shot {
    orthographic_along_z(if front { 3.0 } else { -3.0 }, 48, 16, 4)
}

/// Pixels of `image` whose colour is mostly red, and mostly green.
fn red_and_green(image: &Image) -> (usize, usize) {
    let count = |f: &dyn Fn(Vec3) -> bool| image.pixels.iter().filter(|p| f(**p)).count();
    (
        count(&|p| p.x > 0.5 && p.y < 0.2 && p.z < 0.2),
        count(&|p| p.y > 0.5 && p.x < 0.2 && p.z < 0.2),
    )
}

/// The mirrored node's triangles are wound counter-clockwise about +z in the world, as the
/// file's are before the mirror, and its single-sided quad is seen from +z as the unmirrored one
/// is; from -z neither single-sided quad is seen and the double-sided one still is. Each quad
/// covers 8 x 8 pixels (the image is 6 x 2 units at 8 pixels a unit). Every GPU path renders
/// both views as the CPU does.
#[test]
fn a_mirrored_node_keeps_its_front_face() {
    let test = "a_mirrored_node_keeps_its_front_face";
    let dir = tempfile::tempdir().expect("a temporary folder");
    let scene = mirrored_quads(dir.path());
    assert_eq!(scene.meshes.len(), 3, "one mesh per node");
    for (i, mesh) in scene.meshes.iter().enumerate() {
        for t in &mesh.triangles {
            let v = t.map(|i| mesh.positions[i as usize]);
            let normal = (v[1] - v[0]).cross(v[2] - v[0]);
            assert!(
                normal.z > 0.0 && normal.x.abs() + normal.y.abs() < 1e-6,
                "mesh {i} ({}): triangle {t:?} faces {normal} in the world, not +z",
                mesh.name
            );
        }
    }
    let quad = 64;
    let mut shots = Vec::new();
    for (front, expect_red) in [(true, 2 * quad), (false, 0)] {
        let shot = front_or_back(front);
        let Some(image) = cpu(test, &scene, &shot) else {
            return;
        };
        let (red, green) = red_and_green(&image);
        let side = if front { "front" } else { "back" };
        println!(
            "from the {side}: {red} red pixels (expected {expect_red}), {green} green ({quad})"
        );
        assert!(
            red.abs_diff(expect_red) <= 16 && green.abs_diff(quad) <= 8,
            "from the {side}: {red} red pixels, expected {expect_red}; {green} green, expected {quad}"
        );
        shots.push((format!("mirrored-{side}"), shot));
    }
    assert_gpu_paths_match_cpu(test, &scene, &shots);
}
