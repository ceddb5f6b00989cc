//! Scene loading, scene files, the built-in scene, the generators and the committed assets.

use std::fs;
use std::path::{Path, PathBuf};

use clap::Parser;
use glam::Vec3;
use lensray::cli::generate::{ensure_dense_scene, generate, run, GenerateArgs, Which};
use lensray_core::scene::builtin::{default_sphere_centers, DEFAULT_EYE, DEFAULT_SUBJECT};
use lensray_core::scene::file::{read_scene_file, scene_file_text};
use lensray_core::scene::generate::{cornell_box, cuboid, dense, sphere_row, uv_sphere};
use lensray_core::scene::{
    default_scene, load, load_obj, load_scene_file, write_obj, Material, Scene, SceneDescription,
    SceneError,
};
use lensray_core::settings::Shading;
use lensray_core::settings::{ProjectionKind, Settings};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    if let Some(parent) = path.parent() {
        fs::create_dir_all(parent).unwrap();
    }
    fs::write(&path, text).unwrap();
    path
}

fn load_ok(path: &Path) -> Scene {
    load_obj(path).unwrap_or_else(|e| panic!("{} should load, got: {e}", path.display()))
}

/// Loads `path`, expects an error, checks that its message is one line naming `names_file`.
fn load_err(path: &Path, names_file: &str) -> SceneError {
    let err = match load(path) {
        Ok(d) => panic!(
            "{} should fail to load, got a scene of {} triangles",
            path.display(),
            d.scene.triangle_count()
        ),
        Err(e) => e,
    };
    let message = err.to_string();
    assert!(
        message.contains(names_file),
        "message should name {names_file}: {message}"
    );
    assert!(
        !message.contains('\n'),
        "message should be one line: {message:?}"
    );
    err
}

const CUBE_MTL: &str = "\
# materials
newmtl red
Kd 0.1 0.2 0.3
Ke 4 5 6

newmtl grey
Kd 0.5

newmtl plain
Ns 10
";

#[test]
fn quad_and_pentagon_are_triangulated() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "shapes.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 3.5 1 0\nv 2.5 2 0\nv 1.5 1 0\n\
         o quad\nf 1 2 3 4\no pentagon\nf 5 6 7 8 9\no triangle\nf 1 2 3\n",
    );
    let scene = load_ok(&path);
    let counts: Vec<(String, usize)> = scene
        .meshes
        .iter()
        .map(|m| (m.name.clone(), m.triangles.len()))
        .collect();
    assert_eq!(
        counts,
        vec![
            ("quad".to_string(), 2),
            ("pentagon".to_string(), 3),
            ("triangle".to_string(), 1)
        ]
    );
    assert_eq!(scene.triangle_count(), 6);
    assert_eq!(scene.validate(), Ok(()));
    // The pentagon's fan covers its area: 1 + 1 + 0.5 (shoelace area of the pentagon is 2.5?).
    let pentagon = &scene.meshes[1];
    let area: f32 = pentagon
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| pentagon.positions[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    let p = [(2.0, 0.0), (3.0, 0.0), (3.5, 1.0), (2.5, 2.0), (1.5, 1.0)];
    let shoelace: f32 = 0.5
        * (0..5)
            .map(|i| p[i].0 * p[(i + 1) % 5].1 - p[(i + 1) % 5].0 * p[i].1)
            .sum::<f32>()
            .abs();
    assert!(
        (area - shoelace).abs() < 1e-5,
        "fan area {area} != polygon area {shoelace}"
    );
}

#[test]
fn kd_and_ke_are_read_exactly() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.mtl", CUBE_MTL);
    let path = write(
        dir.path(),
        "m.obj",
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\nusemtl grey\nf 1 2 3\nusemtl plain\nf 1 2 3\n",
    );
    let scene = load_ok(&path);
    let expected = vec![
        Material {
            name: "red".into(),
            diffuse: Vec3::new(0.1, 0.2, 0.3),
            emission: Vec3::new(4.0, 5.0, 6.0),
        },
        Material {
            name: "grey".into(),
            diffuse: Vec3::splat(0.5),
            emission: Vec3::ZERO,
        },
        Material {
            name: "plain".into(),
            diffuse: Material::default().diffuse,
            emission: Vec3::ZERO,
        },
    ];
    assert_eq!(scene.materials, expected);
}

#[test]
fn normals_present_absent_or_partial() {
    let dir = tempfile::tempdir().unwrap();
    let with = write(
        dir.path(),
        "with.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0.6 0.8\nf 1//1 2//1 3//2\n",
    );
    let scene = load_ok(&with);
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    // Corner by corner, the normal the file gave.
    let corners: Vec<(Vec3, Vec3)> = mesh.triangles[0]
        .iter()
        .map(|&i| (mesh.positions[i as usize], mesh.normals[i as usize]))
        .collect();
    assert_eq!(
        corners,
        vec![
            (Vec3::ZERO, Vec3::Z),
            (Vec3::X, Vec3::Z),
            (Vec3::Y, Vec3::new(0.0, 0.6, 0.8))
        ]
    );

    let without = write(
        dir.path(),
        "without.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    assert!(load_ok(&without).meshes[0].normals.is_empty());

    let partial = write(
        dir.path(),
        "partial.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n",
    );
    let scene = load_ok(&partial);
    assert!(
        scene.meshes[0].normals.is_empty(),
        "a mesh with normals on some faces only should get none, got {:?}",
        scene.meshes[0].normals
    );
    assert_eq!(scene.validate(), Ok(()));
}

#[test]
fn material_ids_per_triangle_and_one_default_material() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.mtl", CUBE_MTL);
    let path = write(
        dir.path(),
        "ids.obj",
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
         o a\nf 1 2 3\nusemtl grey\nf 2 4 3\nf 1 2 4\nusemtl red\nf 1 2 3 4\n\
         o b\nusemtl plain\nf 1 2 3\n\
         g c\nf 3 2 1\n",
    );
    let scene = load_ok(&path);
    let by_mesh: Vec<(String, Vec<String>)> = scene
        .meshes
        .iter()
        .map(|m| {
            (
                m.name.clone(),
                m.material_ids
                    .iter()
                    .map(|&i| scene.materials[i as usize].name.clone())
                    .collect(),
            )
        })
        .collect();
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    assert_eq!(
        by_mesh,
        vec![
            ("a".into(), s(&["default", "grey", "grey", "red", "red"])),
            ("b".into(), s(&["plain"])),
            // usemtl carries over into the next group, as in OBJ.
            ("c".into(), s(&["plain"])),
        ]
    );
    let defaults = scene
        .materials
        .iter()
        .filter(|m| **m == Material::default())
        .count();
    assert_eq!(defaults, 1, "materials: {:?}", scene.materials);
    assert_eq!(scene.validate(), Ok(()));

    // A file without any material library: all triangles get the one default material.
    let bare = write(
        dir.path(),
        "bare.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no x\nf 1 3 2\n",
    );
    let scene = load_ok(&bare);
    assert_eq!(scene.materials, vec![Material::default()]);
    assert!(scene.meshes.iter().all(|m| m.material_ids == vec![0]));
}

#[test]
fn obj_errors_name_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

    let e = load_err(&d.join("nothing.obj"), "nothing.obj");
    assert!(matches!(e, SceneError::Read { .. }), "{e:?}");

    let cases: Vec<(&str, String, &str)> = vec![
        ("bad_face.obj", format!("{tri}f 1 2 x\n"), ":4:"),
        ("bad_vertex.obj", "v 0 zero 0\n".into(), ":1:"),
        ("short_vertex.obj", "v 0 0\n".into(), ":1:"),
        ("two_corners.obj", format!("{tri}f 1 2\n"), ":4:"),
        // tobj's own error (too many numbers on a vertex), without a line number.
        (
            "tobj_error.obj",
            format!("v 1 2 3 4 5\n{tri}f 1 2 3\n"),
            "malformed OBJ",
        ),
    ];
    for (name, text, expect) in cases {
        let e = load_err(&write(d, name, &text), name);
        assert!(
            matches!(e, SceneError::ObjLine { .. } | SceneError::Obj { .. }),
            "{name}: {e:?}"
        );
        assert!(e.to_string().contains(expect), "{name}: {e}");
    }

    for (name, text) in [
        (
            "nan.obj",
            "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n".to_string(),
        ),
        (
            "inf.obj",
            "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n".to_string(),
        ),
        (
            "nan_normal.obj",
            format!("{tri}vn 0 NaN 1\nf 1//1 2//1 3//1\n"),
        ),
    ] {
        let e = load_err(&write(d, name, &text), name);
        assert!(matches!(e, SceneError::NonFinite { .. }), "{name}: {e:?}");
    }

    for (name, face, kind) in [
        ("index_high.obj", "f 1 2 4", "vertex"),
        ("index_zero.obj", "f 0 1 2", "vertex"),
        ("index_negative.obj", "f -1 -2 -4", "vertex"),
        ("normal_high.obj", "f 1//2 2//1 3//1", "normal"),
        // tobj overflows (and panics in debug builds) on these without the pre-scan.
        ("normal_zero.obj", "f 1//0 2//0 3//0", "normal"),
        ("texcoord_zero.obj", "f 1/0 2/0 3/0", "texture coordinate"),
    ] {
        let text = format!("{tri}vn 0 0 1\nvt 0 0\n{face}\n");
        let e = load_err(&write(d, name, &text), name);
        match &e {
            SceneError::IndexOutOfRange { line, kind: k, .. } => {
                assert_eq!((*line, *k), (6, kind), "{name}: {e}")
            }
            other => panic!("{name}: expected IndexOutOfRange, got {other:?}"),
        }
    }

    for (name, text) in [
        ("empty.obj", String::new()),
        ("vertices_only.obj", tri.to_string()),
        ("lines_only.obj", format!("{tri}l 1 2 3\n")),
    ] {
        let e = load_err(&write(d, name, &text), name);
        assert!(matches!(e, SceneError::NoTriangles { .. }), "{name}: {e:?}");
        assert!(e.to_string().ends_with("contains no triangles"), "{e}");
    }

    let e = load_err(
        &write(
            d,
            "unknown_mtl.obj",
            &format!("{tri}usemtl nowhere\nf 1 2 3\n"),
        ),
        "unknown_mtl.obj",
    );
    assert!(
        matches!(e, SceneError::UnknownMaterial { line: 4, .. }),
        "{e:?}"
    );
}

#[test]
fn mtl_errors_name_the_material_library() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let obj = |name: &str, mtl: &str| {
        write(
            d,
            name,
            &format!("mtllib {mtl}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n"),
        )
    };

    let e = load_err(&obj("no_mtl.obj", "missing.mtl"), "missing.mtl");
    assert!(matches!(e, SceneError::MtlRead { .. }), "{e:?}");
    assert!(e.to_string().contains("no_mtl.obj"), "{e}");

    for (i, (kd, line)) in [
        ("Kd 0.5 abc 0.5", 2),
        ("Kd 0.5 0.5", 2),
        ("Kd 1 2 3 4", 2),
        ("Kd", 2),
        ("Kd nan 0 0", 2),
        ("Kd 0.5 -0.1 0.5", 2),
        ("Kd 0.5 0.5 0.5\nKe inf 0 0", 3),
        ("Kd 0.5 0.5 0.5\nKe -1 0 0", 3),
        ("Kd 0.5 0.5 0.5\nKe 1 x 1", 3),
    ]
    .into_iter()
    .enumerate()
    {
        let mtl = format!("bad_colour_{i}.mtl");
        write(d, &mtl, &format!("newmtl a\n{kd}\n"));
        let e = load_err(&obj(&format!("colour_{i}.obj"), &mtl), &mtl);
        match &e {
            SceneError::Color { line: l, .. } => assert_eq!(*l, line, "{kd:?}: {e}"),
            other => panic!("{kd:?}: expected a colour error, got {other:?}"),
        }
    }

    write(d, "bad_ns.mtl", "newmtl a\nNs shiny\n");
    let e = load_err(&obj("bad_ns.obj", "bad_ns.mtl"), "bad_ns.mtl");
    assert!(matches!(e, SceneError::Mtl { .. }), "{e:?}");

    // A second library that fails must not be hidden by a first that loads.
    write(d, "good.mtl", "newmtl a\nKd 1 1 1\n");
    let path = write(
        d,
        "two_libs.obj",
        "mtllib good.mtl\nmtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    );
    let e = load_err(&path, "gone.mtl");
    assert!(matches!(e, SceneError::MtlRead { .. }), "{e:?}");
}

const SCENE_TOML: &str = r#"
mesh = "meshes/tri.obj"

[camera]
projection = "perspective"
eye = [0.0, 1.0, 3.5]
target = [0.0, 1.0, 0.0]
up = [0.0, 1.0, 0.0]
vfov_degrees = 40.0
aperture_radius = 0.05
focus_distance = 3.0
near = 0.1
far = 20

[image]
width = 640
height = 480
spp = 16
seed = 7
sampler = "independent"

[render]
shading = "lit"
background = [0.1, 0.2, 0.3]

[light]
position = [0.0, 1.9, 0.0]
intensity = [5.0, 5.0, 5.0]
"#;

#[test]
fn scene_file_with_all_sections_and_relative_mesh() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "meshes/tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let path = write(dir.path(), "scene.toml", SCENE_TOML);
    for loaded in [load_scene_file(&path), load(&path)] {
        let d = loaded.unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(d.scene.triangle_count(), 1);
        assert_eq!(d.source, path.display().to_string());
        let s = &d.settings;
        assert_eq!(s.camera.projection, Some(ProjectionKind::Perspective));
        assert_eq!(s.camera.eye, Some([0.0, 1.0, 3.5]));
        assert_eq!(s.camera.target, Some([0.0, 1.0, 0.0]));
        assert_eq!(s.camera.up, Some([0.0, 1.0, 0.0]));
        assert_eq!(s.camera.vfov_degrees, Some(40.0));
        assert_eq!(s.camera.aperture_radius, Some(0.05));
        assert_eq!(s.camera.focus_distance, Some(3.0));
        assert_eq!((s.camera.near, s.camera.far), (Some(0.1), Some(20.0)));
        assert_eq!(s.camera.ortho_height, None);
        assert_eq!(
            (s.image.width, s.image.height, s.image.spp, s.image.seed),
            (Some(640), Some(480), Some(16), Some(7))
        );
        assert_eq!(
            s.image.sampler,
            Some(lensray_core::sampler::SamplerKind::Independent)
        );
        assert_eq!(s.render.shading, Some(Shading::Lit));
        assert_eq!(s.render.background, Some([0.1, 0.2, 0.3]));
        assert_eq!(s.light.position, Some([0.0, 1.9, 0.0]));
        assert_eq!(s.light.intensity, Some([5.0, 5.0, 5.0]));
    }
    let (mesh, _) = read_scene_file(&path).unwrap();
    assert_eq!(mesh, dir.path().join("meshes/tri.obj"));

    // An absolute mesh path, and only a mesh: every setting unset.
    let elsewhere = tempfile::tempdir().unwrap();
    let abs = dir.path().join("meshes/tri.obj");
    let path = write(
        elsewhere.path(),
        "abs.toml",
        &format!("mesh = {:?}\n", abs.display().to_string()),
    );
    let d = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.settings, Settings::default());
    assert_eq!(d.scene.triangle_count(), 1);

    // A bare OBJ: default settings.
    let d = load(&abs).unwrap();
    assert_eq!(d.settings, Settings::default());
    assert_eq!(d.source, abs.display().to_string());
}

#[test]
fn scene_file_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");

    let toml_error = |name: &str, text: &str, position: Option<(usize, usize)>, says: &str| {
        let e = load_err(&write(d, name, text), name);
        match &e {
            SceneError::Toml { position: p, .. } => assert_eq!(*p, position, "{name}: {e}"),
            other => panic!("{name}: expected a TOML error, got {other:?}"),
        }
        assert!(e.to_string().contains(says), "{name}: {e}");
    };
    toml_error(
        "unknown_top.toml",
        "mesh = \"tri.obj\"\nmeshes = 3\n",
        Some((2, 1)),
        "unknown field `meshes`",
    );
    toml_error(
        "unknown_camera.toml",
        "mesh = \"tri.obj\"\n[camera]\nfov = 40.0\n",
        Some((3, 1)),
        "unknown field `fov`",
    );
    toml_error(
        "unknown_section.toml",
        "mesh = \"tri.obj\"\n[lens]\nf = 2\n",
        Some((2, 2)),
        "unknown field `lens`",
    );
    toml_error(
        "missing_mesh.toml",
        "[image]\nwidth = 100\n",
        Some((1, 1)),
        "missing field `mesh`",
    );
    toml_error(
        "type.toml",
        "mesh = \"tri.obj\"\n[image]\nwidth = \"wide\"\n",
        Some((3, 9)),
        "",
    );
    toml_error(
        "syntax.toml",
        "mesh = \"tri.obj\"\n[camera\n",
        Some((2, 8)),
        "",
    );
    toml_error(
        "shading.toml",
        "mesh = \"tri.obj\"\n[render]\nshading = \"shiny\"\n",
        Some((3, 11)),
        "shiny",
    );
    toml_error(
        "sampler.toml",
        "mesh = \"tri.obj\"\n[image]\nsampler = \"bogus\"\n",
        Some((3, 11)),
        "bogus",
    );

    // The mesh file is missing: the message names the scene file and the OBJ.
    let e = load_err(&write(d, "gone.toml", "mesh = \"gone.obj\"\n"), "gone.toml");
    assert!(e.to_string().contains("gone.obj"), "{e}");
    assert!(matches!(e.root(), SceneError::Read { .. }), "{e:?}");

    // The mesh is broken: the OBJ's own error, prefixed with the scene file.
    write(d, "empty.obj", "");
    let e = load_err(
        &write(d, "empty.toml", "mesh = \"empty.obj\"\n"),
        "empty.toml",
    );
    assert!(matches!(e.root(), SceneError::NoTriangles { .. }), "{e:?}");
    assert!(
        e.to_string().contains("empty.obj contains no triangles"),
        "{e}"
    );

    for (name, mesh) in [("blank.toml", ""), ("notobj.toml", "tri.toml")] {
        let e = load_err(&write(d, name, &format!("mesh = {mesh:?}\n")), name);
        assert!(matches!(e, SceneError::MeshPath { .. }), "{name}: {e:?}");
    }

    let e = load_err(&write(d, "scene.yaml", "mesh: tri.obj\n"), "scene.yaml");
    assert!(matches!(e, SceneError::Extension { .. }), "{e:?}");
    assert!(e.to_string().contains(".yaml"), "{e}");
    let e = load_err(&write(d, "noext", ""), "noext");
    assert!(matches!(e, SceneError::Extension { .. }), "{e:?}");

    let e = load_err(&d.join("absent.toml"), "absent.toml");
    assert!(matches!(e, SceneError::Read { .. }), "{e:?}");

    // Extensions are matched without regard to case.
    let upper = write(d, "UPPER.TOML", "mesh = \"tri.obj\"\n");
    assert!(load(&upper).is_ok());
}

/// Every generated or built-in scene.
fn all_generated() -> Vec<(&'static str, SceneDescription)> {
    vec![
        ("default", default_scene()),
        ("cornell", cornell_box()),
        ("spheres", sphere_row()),
        ("dense", dense(30_000)),
    ]
}

#[test]
fn scene_file_text_reads_back_to_the_same_settings() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let mut cases: Vec<(String, Settings)> = all_generated()
        .into_iter()
        .map(|(n, d)| (n.to_string(), d.settings))
        .collect();
    let mut odd = default_scene().settings;
    odd.camera.projection = Some(ProjectionKind::Orthographic);
    odd.camera.ortho_height = Some(2.5);
    odd.camera.focal_length_mm = Some(50.0);
    odd.camera.f_number = Some(1.4);
    odd.camera.sensor_height_mm = Some(24.0);
    odd.camera.eye = Some([1e-7, -3.25e12, 0.1 + 0.2]);
    odd.image.seed = Some(u32::MAX);
    odd.image.sampler = Some(lensray_core::sampler::SamplerKind::Independent);
    odd.render.shading = Some(Shading::Albedo);
    cases.push(("odd".into(), odd));
    cases.push(("empty".into(), Settings::default()));
    for (name, settings) in cases {
        let text = scene_file_text("tri.obj", &settings, "a comment\nover two lines");
        let path = write(dir.path(), &format!("{name}.toml"), &text);
        let back = load_scene_file(&path).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        assert_eq!(back.settings, settings, "{name}:\n{text}");
    }
}

/// Checks the invariants and that every triangle winds counter-clockwise around its normals.
fn check_scene(name: &str, scene: &Scene) {
    assert_eq!(scene.validate(), Ok(()), "{name}");
    for mesh in &scene.meshes {
        assert!(
            !mesh.triangles.is_empty(),
            "{name}/{}: empty mesh",
            mesh.name
        );
        assert_eq!(
            mesh.normals.len(),
            mesh.positions.len(),
            "{name}/{}",
            mesh.name
        );
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            let geometric = (b - a).cross(c - a);
            assert!(
                geometric.length() > 0.0,
                "{name}/{}: triangle {t} is degenerate",
                mesh.name
            );
            for &i in tri {
                let n = mesh.normals[i as usize];
                assert!(
                    (n.length() - 1.0).abs() < 1e-5,
                    "{name}/{}: normal {n}",
                    mesh.name
                );
                assert!(
                    geometric.dot(n) > 0.0,
                    "{name}/{}: triangle {t} {tri:?} winds against its normal {n}",
                    mesh.name
                );
            }
        }
    }
}

#[test]
fn built_in_default_scene() {
    let d = default_scene();
    check_scene("default", &d.scene);
    let n = d.scene.triangle_count();
    assert!((2_000..=10_000).contains(&n), "{n} triangles");
    assert_eq!(d.source, "built-in default");
    let c = &d.settings.camera;
    assert_eq!(c.projection, Some(ProjectionKind::Perspective));
    assert!(c.aperture_radius.unwrap() > 0.0);
    let eye = c.eye.unwrap();
    let target = c.target.unwrap();
    let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
    assert_eq!(v(eye), DEFAULT_EYE);
    let forward = (v(target) - v(eye)).normalize();
    let depth = |p: Vec3| (p - DEFAULT_EYE).dot(forward);
    let focus = c.focus_distance.unwrap() as f32;
    assert!(
        (focus - depth(DEFAULT_SUBJECT)).abs() < 1e-3,
        "focus {focus}"
    );
    // Spheres well in front of and well behind the focal plane, all inside near..far.
    let depths: Vec<f32> = default_sphere_centers().iter().map(|&p| depth(p)).collect();
    assert!(depths.iter().any(|&z| z < 0.5 * focus), "{depths:?}");
    assert!(depths.iter().any(|&z| z > 1.4 * focus), "{depths:?}");
    let bounds = d.scene.bounds().unwrap();
    for corner in bounds.corners() {
        let z = depth(corner) as f64;
        assert!(z < c.far.unwrap(), "corner at depth {z} beyond far");
    }
    assert!(c.near.unwrap() < depths[0] as f64 - 0.5);
    // Distinct colours.
    let mut colours: Vec<[u32; 3]> = d
        .scene
        .materials
        .iter()
        .map(|m| m.diffuse.to_array().map(f32::to_bits))
        .collect();
    colours.sort();
    colours.dedup();
    assert_eq!(colours.len(), d.scene.materials.len());
    let s = &d.settings;
    assert_eq!((s.image.width, s.image.height), (Some(640), Some(480)));
    assert_eq!(s.render.shading, Some(Shading::Lit));
    assert!(s.light.position.is_some() && s.light.intensity.is_some());
    assert!(s.render.background.is_some());
}

#[test]
fn generators() {
    for (name, d) in all_generated() {
        check_scene(name, &d.scene);
        let c = &d.settings.camera;
        assert!(c.aperture_radius.unwrap() > 0.0, "{name}");
        let bounds = d.scene.bounds().unwrap();
        assert!(bounds.diagonal().length() > 1.0, "{name}");
    }

    let cornell = cornell_box();
    let wall_colour = |wall: &str| {
        let mesh = cornell
            .scene
            .meshes
            .iter()
            .find(|m| m.name == wall)
            .unwrap();
        cornell.scene.materials[mesh.material_ids[0] as usize].diffuse
    };
    let (left, right, back) = (
        wall_colour("left_wall"),
        wall_colour("right_wall"),
        wall_colour("back_wall"),
    );
    assert!(left.x > 2.0 * left.y, "left wall should be red: {left}");
    assert!(
        right.y > 2.0 * right.x,
        "right wall should be green: {right}"
    );
    assert!(
        back.x == back.y && back.y == back.z,
        "back wall should be white: {back}"
    );
    assert!(
        cornell
            .scene
            .materials
            .iter()
            .any(|m| m.emission.max_element() > 0.0),
        "no emissive material"
    );
    let light = cornell.settings.light.position.unwrap();
    assert!(
        light[1] > 1.5 && light[1] < 2.0,
        "light {light:?} below the ceiling"
    );

    for min in [0, 5_000, 30_000, 123_457] {
        let n = dense(min).scene.triangle_count();
        assert!(n >= min, "dense({min}) has {n} triangles");
        assert!(
            n <= min.max(10_000) * 13 / 10,
            "dense({min}) has {n} triangles: too many"
        );
    }
}

#[test]
fn dense_reaches_a_million_triangles() {
    let d = dense(1_000_000);
    let n = d.scene.triangle_count();
    assert!((1_000_000..1_100_000).contains(&n), "{n} triangles");
}

#[test]
fn primitives_wind_outwards() {
    let mut scene = Scene::default();
    scene.materials.push(Material::default());
    for (i, yaw) in [0.0f32, 0.3, -2.0].into_iter().enumerate() {
        scene.meshes.push(cuboid(
            &format!("box{i}"),
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.5, 1.0, 2.0),
            yaw,
            0,
        ));
    }
    scene
        .meshes
        .push(uv_sphere("coarse", Vec3::ONE, 2.0, 3, 2, 0));
    scene
        .meshes
        .push(uv_sphere("fine", Vec3::ONE, 0.01, 64, 33, 0));
    check_scene("primitives", &scene);
    // Normals point away from the centre.
    for mesh in &scene.meshes {
        let center = if mesh.name.starts_with("box") {
            Vec3::new(1.0, 2.0, 3.0)
        } else {
            Vec3::ONE
        };
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!(
                (*p - center).dot(*n) > 0.0,
                "{}: normal {n} at {p}",
                mesh.name
            );
        }
    }
}

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
            },
            Material {
                name: "m".into(),
                diffuse: Vec3::Y,
                emission: Vec3::splat(2.0),
            },
        ],
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

/// `[camera.aperture] image` is relative to the scene file's folder, as the mesh is, and the
/// shot reads it as the aperture.
#[test]
fn scene_file_aperture_image_is_relative_to_the_file() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    std::fs::create_dir_all(dir.path().join("masks")).unwrap();
    image::GrayImage::from_fn(4, 2, |x, _| image::Luma([if x < 2 { 255 } else { 0 }]))
        .save(dir.path().join("masks/half.png"))
        .unwrap();
    let path = write(
        dir.path(),
        "scene.toml",
        "mesh = \"tri.obj\"\n[camera]\naperture_radius = 0.1\n[camera.aperture]\nimage = \"masks/half.png\"\nrotation = 90.0\n",
    );
    let d = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        d.settings.camera.aperture.image.as_deref(),
        Some(dir.path().join("masks/half.png").as_path())
    );
    let shot =
        lensray_core::settings::shot(&d.settings, &d.scene).unwrap_or_else(|e| panic!("{e}"));
    let aperture = &shot.camera.lens.aperture;
    let image = aperture.image().expect("an image aperture");
    assert_eq!((image.columns(), image.rows()), (4, 2));
    assert_eq!(
        image.transmission(),
        &[1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0]
    );
    // The left half, turned by 90 degrees counter-clockwise: the bottom half.
    for u in [glam::Vec2::new(0.1, 0.2), glam::Vec2::new(0.9, 0.7)] {
        let p = aperture.unit_point(u);
        assert!(p.y <= 1e-6 && p.x.abs() <= 1.0 + 1e-6, "{p}");
    }
}
