//! The generated textured scene (`lensray generate textured`): its glTF and its OBJ (through the
//! scene file) load to the same geometry, textures and camera and render the same image on the
//! CPU, but for the leaf's edge where MTL cannot say MASK; every GPU path renders the glTF as the
//! CPU does.

mod gpu_support;

use glam::{Vec2, Vec3};
use gpu_support::{compare, open_path_with, write_comparison, write_png};
use lensray::cli::generate::{generate, Which};
use lensray::paths::{OpenedPath, PathKind};
use lensray_core::camera::Camera;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::scene::{load, AlphaMode, Mesh, Scene, SceneDescription};
use lensray_core::settings::{shot, Shading, Shot};

/// The scene generated into a temporary folder, loaded from its glTF and from its scene file.
fn generated() -> (tempfile::TempDir, SceneDescription, SceneDescription) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let (toml, triangles) = generate(Which::Textured, dir.path(), 0).expect("generate textured");
    assert_eq!(triangles, 10);
    // Lit as `lensray render` lights them: the glTF by its own lights, the OBJ by its scene
    // file's.
    let load = |path: &std::path::Path| {
        let mut d = load(path).unwrap_or_else(|e| panic!("{} should load: {e}", path.display()));
        let settings = d.settings.clone();
        lensray_core::settings::light_scene(&settings, &mut d.scene).expect("its lights");
        d
    };
    let gltf = load(&dir.path().join("textured.gltf"));
    let obj = load(&toml);
    (dir, gltf, obj)
}

/// Every triangle's corners: position, normal, texture coordinates.
fn corners(mesh: &Mesh) -> Vec<[(Vec3, Vec3, Vec2); 3]> {
    mesh.triangles
        .iter()
        .map(|t| {
            t.map(|i| {
                let i = i as usize;
                (mesh.positions[i], mesh.normals[i], mesh.texcoords[i])
            })
        })
        .collect()
}

/// The texels of the texture `texture` of `scene` as RGBA8 (every level), or only their alpha.
fn texels(scene: &Scene, texture: u32, alpha_only: bool) -> Vec<u32> {
    let mask = if alpha_only { 0xff00_0000 } else { u32::MAX };
    let t = &scene.textures[texture as usize];
    t.texels.iter().map(|&x| x & mask).collect()
}

#[test]
fn the_gltf_and_the_obj_load_to_the_same_scene() {
    let (_dir, gltf, obj) = generated();
    let view = |s: &lensray_core::settings::Settings| (s.camera.clone(), s.image.clone());
    assert_eq!(
        view(&gltf.settings),
        view(&obj.settings),
        "the scene file's camera is the glTF's"
    );
    assert_eq!(
        gltf.scene.lights, obj.scene.lights,
        "the scene file's lights are the glTF's"
    );
    assert_eq!(gltf.scene.lights.len(), 1);
    assert_eq!(gltf.settings.image.width, Some(640));
    // The exported materials are factors and colour textures, all of which lensray draws:
    // neither file gets a notice.
    assert!(gltf.notices.is_empty(), "{:?}", gltf.notices);
    assert!(obj.notices.is_empty(), "{:?}", obj.notices);

    let (a, b) = (&gltf.scene, &obj.scene);
    assert_eq!(a.meshes.len(), 5);
    assert_eq!(a.meshes.len(), b.meshes.len());
    for (ma, mb) in a.meshes.iter().zip(&b.meshes) {
        assert_eq!(ma.name, mb.name);
        assert_eq!(corners(ma), corners(mb), "mesh {}", ma.name);
        assert_eq!(ma.material_ids, mb.material_ids, "mesh {}", ma.name);
    }
    assert_eq!(a.materials.len(), b.materials.len());
    for (ma, mb) in a.materials.iter().zip(&b.materials) {
        let what = &ma.name;
        assert_eq!(ma.name, mb.name);
        assert_eq!(
            (ma.diffuse, ma.emission, ma.alpha),
            (mb.diffuse, mb.emission, mb.alpha)
        );
        let (ta, tb) = (ma.diffuse_texture.unwrap(), mb.diffuse_texture.unwrap());
        assert_eq!(
            (ta.wrap, ta.uv_from_texcoord),
            (tb.wrap, tb.uv_from_texcoord),
            "{what}"
        );
        assert_eq!(
            texels(a, ta.texture, false),
            texels(b, tb.texture, false),
            "{what}"
        );
        match (ma.alpha_mode, mb.alpha_mode) {
            (AlphaMode::Opaque, AlphaMode::Opaque) => {}
            // MTL has no mask: map_d is a stochastic cut. The coverage is the same alpha.
            (AlphaMode::Mask { cutoff }, AlphaMode::Blend) if cutoff == 0.5 && what == "leaf" => {
                let (ca, cb) = (ma.alpha_texture.unwrap(), mb.alpha_texture.unwrap());
                let alpha = texels(a, ca.texture, true);
                assert_eq!(alpha, texels(b, cb.texture, true), "{what}");
                let level0 = &alpha[..128 * 128];
                let opaque = level0.iter().filter(|&&x| x == 0xff00_0000).count();
                assert!(
                    level0.iter().all(|&x| x == 0 || x == 0xff00_0000),
                    "alpha 0 or 1"
                );
                assert!((3000..9000).contains(&opaque), "{opaque} leaf texels");
            }
            modes => panic!("{what}: alpha modes {modes:?}"),
        }
    }
}

/// `description`'s shot at 64 x 48, `spp` samples, focused on the checker card through a wide
/// aperture.
fn small_shot(description: &SceneDescription, shading: Shading, spp: u32) -> Shot {
    let mut settings = description.settings.clone();
    settings.image.width = Some(64);
    settings.image.height = Some(48);
    settings.image.spp = Some(spp);
    settings.render.shading = Some(shading);
    settings.camera.aperture_radius = Some(0.05);
    settings.camera.focus_distance = Some(5.4);
    shot(&settings, &description.scene).expect("a valid shot")
}

fn cpu_render(scene: &Scene, shot: &Shot) -> Image {
    Renderer::new(scene).render(shot, &mut |_, _| {}).0
}

/// Pixels that differ at all, and the largest difference.
fn differences(a: &Image, b: &Image) -> (usize, f32) {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .fold((0, 0.0f32), |(n, worst), (p, q)| {
            let d = (*p - *q).abs().max_element();
            (n + usize::from(d > 0.0), worst.max(d))
        })
}

#[test]
fn the_gltf_and_the_obj_render_the_same_image_on_the_cpu() {
    let (_dir, gltf, obj) = generated();
    // The OBJ's leaf as the glTF has it: what MTL cannot say.
    let mut masked = obj.scene.clone();
    let leaf = masked
        .materials
        .iter_mut()
        .find(|m| m.name == "leaf")
        .unwrap();
    leaf.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
    for shading in [Shading::Unlit, Shading::Lit] {
        let shot = small_shot(&gltf, shading, 8);
        assert_eq!(shot, small_shot(&obj, shading, 8), "the same shot");
        let from_gltf = cpu_render(&gltf.scene, &shot);
        let from_obj = cpu_render(&masked, &shot);
        let (count, worst) = differences(&from_gltf, &from_obj);
        println!("{shading:?}, the OBJ masked: {count} pixels differ, by {worst} at most");
        if count > 0 {
            let files =
                write_comparison(&from_obj, &from_gltf, &format!("textured-{shading:?}-obj"));
            panic!("{shading:?}: the OBJ's image differs from the glTF's in {count} pixels, by {worst} at most; wrote {files}");
        }

        // As written, the OBJ's leaf blends: only where its filtered alpha lies between 0 and 1,
        // along its edge (lit, also its shadow's), may a pixel differ, and not along all of it:
        // each outline is about 40 pixels long (measured: 10 pixels differ unlit, 12 lit, by
        // 0.066 and 0.086 at most).
        let blended = cpu_render(&obj.scene, &shot);
        let (count, worst) = differences(&from_gltf, &blended);
        let diff = compare(&blended, &from_gltf, 1.0 / 255.0);
        println!(
            "{shading:?}, the OBJ blended: {count} pixels differ, by {worst} at most: {diff:?}"
        );
        let leaf_pixels = leaf_edge_pixels(&gltf.scene, &shot);
        let outside = (0..blended.pixels.len())
            .filter(|&i| blended.pixels[i] != from_gltf.pixels[i] && !leaf_pixels[i])
            .count();
        if outside > 0 || count > 60 {
            write_png(&blended, &format!("textured-{shading:?}-obj-blended.png"));
            write_png(&from_gltf, &format!("textured-{shading:?}-gltf.png"));
            panic!("{shading:?}: the blended leaf changes {count} pixels, {outside} away from its edge");
        }
    }
}

/// Whether each pixel of `shot` may see the leaf card's edge or, lit, the edge of its shadow:
/// within the blur of the card's projected bounds, or of its shadow's on the ground.
fn leaf_edge_pixels(scene: &Scene, shot: &Shot) -> Vec<bool> {
    let leaf = scene.meshes.iter().find(|m| m.name == "leaf").unwrap();
    let camera = &shot.camera;
    let light = scene.lights[0].position;
    let on_ground = |c: Vec3| light + (c - light) * (light.y / (light.y - c.y));
    let mut boxes = vec![bounds(camera, leaf.positions.iter().copied())];
    if shot.render.shading == Shading::Lit {
        boxes.push(bounds(camera, leaf.positions.iter().map(|&c| on_ground(c))));
    }
    let (w, h) = (camera.width, camera.height);
    (0..w * h)
        .map(|i| {
            let p = Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            boxes
                .iter()
                .any(|(lo, hi)| p.cmpge(*lo - 3.0).all() && p.cmple(*hi + 3.0).all())
        })
        .collect()
}

/// The raster bounds of `points` seen by `camera`.
fn bounds(camera: &Camera, points: impl Iterator<Item = Vec3>) -> (Vec2, Vec2) {
    points.fold((Vec2::MAX, Vec2::MIN), |(lo, hi), p| {
        let q = camera.project(p);
        let q = Vec2::new(q.x, q.y);
        (lo.min(q), hi.max(q))
    })
}

/// The ray-query, software and raster paths render the glTF as the CPU reference does, unlit
/// and lit (raster with the samples shared by every pixel, as it draws them), within the
/// textured test card's tolerances. Each path is opened once for both shadings.
#[test]
fn gpu_paths_render_the_textured_gltf_as_the_cpu_does() {
    let test = "gpu_paths_render_the_textured_gltf_as_the_cpu_does";
    let (_dir, gltf, _) = generated();
    let scene = &gltf.scene;
    for kind in [
        PathKind::RayQuery,
        PathKind::RtPipeline,
        PathKind::Software,
        PathKind::Raster,
    ] {
        let shots = [Shading::Unlit, Shading::Lit].map(|shading| {
            let mut shot = small_shot(&gltf, shading, 8);
            shot.render.shared_samples = kind == PathKind::Raster;
            shot
        });
        let Some(OpenedPath { mut path, .. }) = open_path_with(test, kind.into(), scene, &shots[1])
        else {
            return;
        };
        for shot in &shots {
            let shading = shot.render.shading;
            let image = path.render(shot, &mut |_, _| {}).expect("render");
            let reference = cpu_render(scene, shot);
            let diff = compare(&image, &reference, 1.0 / 255.0);
            println!("{shading:?} {kind}: {diff:?}");
            if diff.within < 0.999 || diff.mean_abs >= 1e-3 {
                let name = format!("textured-gltf-{shading:?}-{kind}-vs-cpu");
                let files = write_comparison(&image, &reference, &name);
                panic!("{shading:?} {kind}: differs from the CPU: {diff:?}; wrote {files}");
            }
        }
        path.close().expect("close: validation messages or leaks");
    }
}
