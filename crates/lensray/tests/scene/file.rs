//! Scene files (TOML): every section, paths relative to the file, errors, and the text
//! `scene_file_text` writes.

use lensray_core::scene::builtin::default_scene;
use lensray_core::scene::file::{read_scene_file, scene_file_text};
use lensray_core::scene::{load, load_scene_file, SceneError};
use lensray_core::settings::Shading;
use lensray_core::settings::{ProjectionKind, Settings};

use crate::{all_generated, load_err, write};

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
        assert_eq!(s.light.0[0].position, Some([0.0, 1.9, 0.0]));
        assert_eq!(s.light.0[0].intensity, Some([5.0, 5.0, 5.0]));
    }
    let (mesh, _, _) = read_scene_file(&path).unwrap();
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
    let aperture = &shot.camera.lens.first_order().aperture;
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
