//! Writing scenes out: `write_obj`, the committed assets and the `generate` command.

use std::fs;
use std::path::{Path, PathBuf};

use clap::Parser;
use glam::Vec3;
use lensray::cli::generate::{ensure_dense_scene, generate, run, GenerateArgs, Which};
use lensray_core::scene::builtin::default_scene;
use lensray_core::scene::generate::{cornell_box, sphere_row, uv_sphere};
use lensray_core::scene::{load, write_obj, Material, Scene};

use crate::{all_generated, load_ok};

/// The two scenes have the same meshes, triangles (corner positions and normals, within
/// `tolerance`) and materials.
fn assert_same_geometry(what: &str, a: &Scene, b: &Scene, tolerance: f32) {
    assert_eq!(a.meshes.len(), b.meshes.len(), "{what}: mesh count");
    assert_eq!(a.materials, b.materials, "{what}: materials");
    for (ma, mb) in a.meshes.iter().zip(&b.meshes) {
        assert_eq!(ma.name, mb.name, "{what}");
        assert_eq!(ma.triangles.len(), mb.triangles.len(), "{what}/{}", ma.name);
        assert_eq!(ma.material_ids, mb.material_ids, "{what}/{}", ma.name);
        assert_eq!(
            ma.normals.is_empty(),
            mb.normals.is_empty(),
            "{what}/{}",
            ma.name
        );
        for (t, (ta, tb)) in ma.triangles.iter().zip(&mb.triangles).enumerate() {
            let corners = |m: &lensray_core::scene::Mesh, tri: &[u32; 3]| {
                tri.map(|i| {
                    let n = m.normals.get(i as usize).copied().unwrap_or(Vec3::ZERO);
                    (m.positions[i as usize], n)
                })
            };
            let (ca, cb) = (corners(ma, ta), corners(mb, tb));
            let close = ca.iter().zip(&cb).all(|((pa, na), (pb, nb))| {
                pa.abs_diff_eq(*pb, tolerance) && na.abs_diff_eq(*nb, tolerance)
            });
            assert!(close, "{what}/{}: triangle {t}: {ca:?} != {cb:?}", ma.name);
        }
    }
}

#[test]
fn write_obj_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    for (name, d) in all_generated() {
        let path = dir.path().join(format!("{name}.obj"));
        write_obj(&d.scene, &path).unwrap();
        assert!(dir.path().join(format!("{name}.mtl")).is_file());
        let back = load_ok(&path);
        assert_same_geometry(name, &d.scene, &back, 0.0);
    }

    // Duplicate names are made unique, materials keep their identity, meshes without normals
    // stay without.
    let mut scene = Scene {
        meshes: Vec::new(),
        materials: vec![
            Material {
                name: "m".into(),
                diffuse: Vec3::X,
                emission: Vec3::ZERO,
                ..Default::default()
            },
            Material {
                name: "m".into(),
                diffuse: Vec3::Y,
                emission: Vec3::splat(2.0),
                ..Default::default()
            },
        ],
        ..Default::default()
    };
    for _ in 0..2 {
        let mut mesh = uv_sphere("s", Vec3::ZERO, 1.0, 4, 3, 0);
        mesh.normals.clear();
        mesh.material_ids[1] = 1;
        scene.meshes.push(mesh);
    }
    let path = dir.path().join("dupes.obj");
    write_obj(&scene, &path).unwrap();
    let back = load_ok(&path);
    let names: Vec<&str> = back.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["s", "s_2"]);
    let materials: Vec<(&str, Vec3, Vec3)> = back
        .materials
        .iter()
        .map(|m| (m.name.as_str(), m.diffuse, m.emission))
        .collect();
    assert_eq!(
        materials,
        [
            ("m", Vec3::X, Vec3::ZERO),
            ("m_2", Vec3::Y, Vec3::splat(2.0))
        ]
    );
    for (a, b) in scene.meshes.iter().zip(&back.meshes) {
        assert_eq!(a.material_ids, b.material_ids);
        assert!(b.normals.is_empty());
    }
}

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets")
}

#[test]
fn committed_assets_match_their_generators() {
    for (file, generated) in [
        ("cornell/cornell.toml", cornell_box()),
        ("spheres/spheres.toml", sphere_row()),
    ] {
        let path = assets().join(file);
        let d = load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            d.scene.triangle_count(),
            generated.scene.triangle_count(),
            "{file}: regenerate with `lensray generate`"
        );
        // Not bit for bit: sin and cos may round differently on another platform.
        assert_same_geometry(file, &generated.scene, &d.scene, 1e-5);
        assert_eq!(
            d.settings, generated.settings,
            "{file}: settings differ from the generator's"
        );
    }
}

#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    generate: GenerateArgs,
}

#[test]
fn generate_command() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("nested/out");
    let args = Cli::try_parse_from(["generate", "cornell", "--out", out.to_str().unwrap()])
        .unwrap()
        .generate;
    assert_eq!(args.which, Which::Cornell);
    run(&args).unwrap();
    for ext in ["obj", "mtl", "toml"] {
        assert!(
            out.join(format!("cornell.{ext}")).is_file(),
            "cornell.{ext} missing"
        );
    }
    let d = load(&out.join("cornell.toml")).unwrap();
    assert_eq!(
        d.scene.triangle_count(),
        cornell_box().scene.triangle_count()
    );
    let leftovers: Vec<_> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers.len(), 3, "{leftovers:?}");

    let args = Cli::try_parse_from(["generate", "spheres", "--triangles", "5"])
        .unwrap()
        .generate;
    let e = run(&args).unwrap_err();
    assert!(e.to_string().contains("--triangles"), "{e}");
    assert!(Cli::try_parse_from(["generate", "teapot"]).is_err());
    let args = Cli::try_parse_from(["generate", "dense"]).unwrap().generate;
    assert_eq!(
        (args.triangles, args.out.as_path()),
        (None, Path::new("assets/generated"))
    );

    let (path, n) = generate(Which::Dense, &out, 20_000).unwrap();
    assert!(n >= 20_000);
    assert_eq!(load(&path).unwrap().scene.triangle_count(), n);
}

/// `generate default` writes the built-in default scene: the same triangles, materials and
/// settings (so other renderers can load what `lensray render` draws without `--scene`).
#[test]
fn generate_default_writes_the_builtin_scene() {
    let dir = tempfile::tempdir().unwrap();
    let (path, n) = generate(Which::Default, dir.path(), 0).unwrap();
    let builtin = default_scene();
    assert_eq!(n, builtin.scene.triangle_count());
    let d = load(&path).unwrap();
    assert_same_geometry("default", &builtin.scene, &d.scene, 0.0);
    assert_eq!(d.settings, builtin.settings);
}

#[test]
fn ensure_dense_scene_generates_only_when_needed() {
    let dir = tempfile::tempdir().unwrap();
    let path = ensure_dense_scene(dir.path(), 12_000).unwrap();
    assert_eq!(path, dir.path().join("dense.toml"));
    let obj = dir.path().join("dense.obj");
    let stamp = fs::metadata(&obj).unwrap().modified().unwrap();
    let first = load(&path).unwrap().scene.triangle_count();
    assert!(first >= 12_000);

    std::thread::sleep(std::time::Duration::from_millis(20));
    assert_eq!(ensure_dense_scene(dir.path(), 12_000).unwrap(), path);
    assert_eq!(
        fs::metadata(&obj).unwrap().modified().unwrap(),
        stamp,
        "regenerated needlessly"
    );

    // Another count, or a missing OBJ, regenerates.
    ensure_dense_scene(dir.path(), 40_000).unwrap();
    assert!(load(&path).unwrap().scene.triangle_count() >= 40_000);
    fs::remove_file(&obj).unwrap();
    ensure_dense_scene(dir.path(), 40_000).unwrap();
    assert!(obj.is_file());
}

/// `generate --gltf` writes the scene's meshes as glTF (binary vertex data) with the same scene
/// file: it loads to the same triangles and materials and renders the OBJ's image.
#[test]
fn generate_gltf_renders_as_the_obj_does() {
    use lensray::cli::generate::{generate_as, MeshFormat};
    use lensray_core::reference::Renderer;
    use lensray_core::settings::{light_scene, shot};
    let dir = tempfile::tempdir().unwrap();
    let render = |format: MeshFormat, sub: &str| {
        let (path, n) = generate_as(Which::Default, &dir.path().join(sub), 0, format).unwrap();
        let mut d = load(&path).unwrap();
        assert_eq!(d.scene.triangle_count(), n, "{sub}");
        let mut names: Vec<_> = d.scene.materials.iter().map(|m| m.name.clone()).collect();
        names.sort();
        (d.settings.image.width, d.settings.image.height) = (Some(80), Some(60));
        d.settings.image.spp = Some(4);
        light_scene(&d.settings, &mut d.scene).unwrap();
        let shot = shot(&d.settings, &d.scene).unwrap();
        let (image, _) = Renderer::new(&d.scene).render(&shot, &mut |_, _| {});
        (image, names)
    };
    let (obj, obj_materials) = render(MeshFormat::Obj, "obj");
    let (gltf, gltf_materials) = render(MeshFormat::Gltf, "gltf");
    assert_eq!(obj_materials, gltf_materials);
    let pixels = obj.pixels.len();
    let close = (obj.pixels.iter().zip(&gltf.pixels))
        .filter(|(a, b)| (**a - **b).abs().max_element() <= 1.0 / 255.0)
        .count();
    assert!(
        close as f64 >= 0.999 * pixels as f64,
        "glTF against OBJ: {close} of {pixels} pixels within 1/255"
    );
    let files = std::fs::read_dir(dir.path().join("gltf")).unwrap().count();
    assert_eq!(files, 3, "default.gltf, default.bin and default.toml");
}

/// `generate studio` writes an equirectangular HDR environment that loads back at 1024x512,
/// the key light where the studio puts it.
#[test]
fn generate_studio_writes_an_environment_map() {
    use lensray_core::scene::environment::{studio, EnvironmentMap};
    let dir = tempfile::tempdir().unwrap();
    let (path, _) = generate(Which::Studio, dir.path(), 0).unwrap();
    assert_eq!(path, dir.path().join("studio.hdr"));
    let (map, mended) = EnvironmentMap::load(&path).unwrap();
    assert_eq!((map.width, map.height, mended.texels), (1024, 512, 0));
    let key = map.radiance(studio::direction(-45.0, 35.0));
    assert_eq!(key, glam::Vec3::new(30.0, 27.0, 24.0));
}
