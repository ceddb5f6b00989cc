//! OBJ and MTL loading: triangulation, materials, normals, and errors that name the file.

use glam::Vec3;
use lensray_core::scene::{load_obj, Material, SceneError};

use crate::{load_err, load_ok, write};

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
            ..Default::default()
        },
        Material {
            name: "grey".into(),
            diffuse: Vec3::splat(0.5),
            emission: Vec3::ZERO,
            ..Default::default()
        },
        Material {
            name: "plain".into(),
            diffuse: Material::default().diffuse,
            emission: Vec3::ZERO,
            ..Default::default()
        },
    ];
    assert_eq!(scene.materials, expected);
}

/// MTL's Phong terms and the PBR extension as the metallic-roughness model: no `Ks` is
/// Lambert (specular 0, whatever `Ns`); `Ks` with `Ns` 98 a dielectric of roughness
/// sqrt(2 / (98 + 2)); `Pm` and `Pr` as given.
#[test]
fn ks_ns_and_the_pbr_keys_map_to_metallic_and_roughness() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl phong\nKd 0.5\nKs 0.5 0.5 0.5\nNs 98\n\
               newmtl metal\nKd 0.9 0.6 0.3\nPm 1\nPr 0.3\n";
    write(dir.path(), "m.mtl", mtl);
    let path = write(
        dir.path(),
        "m.obj",
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl phong\nf 1 2 3\nusemtl metal\nf 1 2 3\n",
    );
    let scene = load_ok(&path);
    let got: Vec<_> = scene
        .materials
        .iter()
        .map(|m| (m.name.as_str(), m.metallic, m.roughness, m.specular))
        .collect();
    let want = [("phong", 0.0, 0.141_421_36, 1.0), ("metal", 1.0, 0.3, 1.0)];
    let close = got
        .iter()
        .zip(&want)
        .all(|(g, w)| g.0 == w.0 && g.1 == w.1 && (g.2 - w.2).abs() < 1e-6 && g.3 == w.3);
    assert!(close, "{got:?} against {want:?}");
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
}

/// The scene and notices of an OBJ that must load.
fn load_with_notices(path: &std::path::Path) -> (lensray_core::scene::Scene, Vec<String>) {
    let file = load_obj(path).unwrap_or_else(|e| panic!("{} should load: {e}", path.display()));
    (file.scene, file.notices)
}

#[test]
fn messy_real_files_load_with_one_notice_each() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let default = Material::default();

    // A usemtl with no library, and one naming no material: the default material.
    let (scene, notices) = load_with_notices(&write(
        d,
        "unknown_mtl.obj",
        &format!("{tri}usemtl nowhere\nf 1 2 3\nusemtl elsewhere\nf 1 2 3\n"),
    ));
    assert_eq!(scene.materials, vec![default.clone()]);
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert!(
        notices[0].contains("`nowhere` (line 4) and 1 more names no material"),
        "{notices:?}"
    );

    // A missing library: a notice naming it, the default material.
    let (scene, notices) = load_with_notices(&write(
        d,
        "no_mtl.obj",
        &format!("mtllib missing.mtl\n{tri}usemtl a\nf 1 2 3\n"),
    ));
    assert_eq!(scene.materials, vec![default]);
    assert!(
        notices
            .iter()
            .any(|n| n.contains("missing.mtl") && n.contains("no_mtl.obj")),
        "{notices:?}"
    );

    // A byte-order mark keeps the first vertex; a Latin-1 byte in a comment is dropped.
    let mut bytes =
        b"\xEF\xBB\xBFv 0 0 0\n# \xA9 2024 someone\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec();
    std::fs::write(d.join("bom.obj"), &bytes).unwrap();
    let (scene, notices) = load_with_notices(&d.join("bom.obj"));
    assert_eq!(scene.meshes[0].positions.len(), 3);
    assert_eq!(scene.meshes[0].positions[0], Vec3::ZERO);
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert!(
        notices[0].contains("1 comment lines are not UTF-8"),
        "{notices:?}"
    );

    // Outside a comment, such a byte is still an error naming the line.
    bytes = b"v 0 0 0\nv 1 0 0\nv 0 \xA9 0\nf 1 2 3\n".to_vec();
    std::fs::write(d.join("latin1.obj"), &bytes).unwrap();
    let e = load_err(&d.join("latin1.obj"), "latin1.obj:3");
    assert!(matches!(e, SceneError::ObjLine { line: 3, .. }), "{e:?}");
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

    // A second library that is malformed must not be hidden by a first that loads.
    write(d, "good.mtl", "newmtl a\nKd 1 1 1\n");
    let path = write(
        d,
        "two_libs.obj",
        "mtllib good.mtl\nmtllib bad_ns.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    );
    let e = load_err(&path, "bad_ns.mtl");
    assert!(matches!(e, SceneError::Mtl { .. }), "{e:?}");
}
