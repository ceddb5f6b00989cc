//! Bad input: numbers, aperture shapes, scene files, outputs and GPU options with the CPU
//! renderer, each refused with one line before anything is written; messy but clear input
//! warned about in one line.

use crate::{assert_rejected, lensray, render_args, stderr};

#[test]
fn bad_numbers_are_rejected_with_one_line() {
    assert_rejected(
        &["--vfov", "nan"],
        "camera.vfov_degrees must be a finite number",
    );
    assert_rejected(&["--vfov", "0"], "field of view");
    assert_rejected(&["--vfov", "180"], "field of view");
    assert_rejected(&["--aperture-radius", "-0.1"], "aperture");
    assert_rejected(&["--aperture-radius", "inf"], "aperture_radius");
    assert_rejected(&["--focus-distance", "-2"], "focus distance");
    assert_rejected(&["--focus-distance", "0"], "focus distance");
    assert_rejected(
        &["--projection", "orthographic", "--ortho-height", "0"],
        "height",
    );
    assert_rejected(&["--spp", "0"], "spp");
    assert_rejected(&["--noise-threshold", "-1"], "noise_threshold");
    assert_rejected(&["--noise-threshold", "nan"], "noise_threshold");
    assert_rejected(&["--noise-threshold", "0"], "noise_threshold");
    assert_rejected(&["--noise-threshold", "inf"], "noise_threshold");
    assert_rejected(&["--noise-threshold", "1e-50"], "noise_threshold");
    assert_rejected(&["--noise-threshold", "low"], "noise-threshold");
    assert_rejected(&["--sampler", "bogus"], "sampler");
    assert_rejected(&["--width", "0"], "0x32");
    assert_rejected(&["--height", "20000"], "48x20000");
    assert_rejected(&["--width", "abc"], "width");
    assert_rejected(&["--eye", "1,2"], "three");
    assert_rejected(&["--eye", "1,2,3", "--target", "1,2,3"], "eye and target");
    assert_rejected(
        &["--eye", "0,0,5", "--target", "0,0,0", "--up", "0,0,1"],
        "parallel",
    );
    assert_rejected(&["--near", "-1"], "near");
    assert_rejected(&["--near", "5", "--far", "1"], "far");
    assert_rejected(&["--background", "nan,0,0"], "background");
    assert_rejected(&["--light-intensity", "-1,1,1"], "light intensity");
    assert_rejected(
        &["--focal-length-mm", "0", "--focus-distance", "2"],
        "focal length",
    );
    assert_rejected(&["--focal-length-mm", "50", "--f-number", "-2"], "f-number");
    assert_rejected(
        &["--focal-length-mm", "50", "--focus-distance", "0.04"],
        "focal length",
    );
    assert_rejected(&["--f-number", "2"], "focal length");
}

#[test]
fn bad_aperture_shapes_are_rejected_with_one_line() {
    assert_rejected(&["--aperture-blades", "2"], "aperture blades");
    assert_rejected(&["--aperture-blades", "33"], "aperture blades");
    assert_rejected(&["--aperture-blades", "-1"], "aperture-blades");
    assert_rejected(
        &["--aperture-blades", "6", "--aperture-roundness", "1.5"],
        "roundness",
    );
    assert_rejected(&["--aperture-roundness", "-0.1"], "roundness");
    assert_rejected(&["--aperture-aspect", "0"], "aperture aspect");
    assert_rejected(&["--aperture-aspect", "nan"], "aperture.aspect");
    assert_rejected(&["--aperture-rotation", "inf"], "aperture.rotation");
    // Aperture images: all black, missing, not an image, not PNG or EXR, beside blades.
    let images = tempfile::tempdir().unwrap();
    let path = |name: &str| images.path().join(name).to_str().unwrap().to_owned();
    image::GrayImage::new(8, 8).save(path("black.png")).unwrap();
    image::GrayImage::from_pixel(8, 8, image::Luma([255]))
        .save(path("white.png"))
        .unwrap();
    std::fs::write(path("text.png"), "not a PNG").unwrap();
    std::fs::write(path("mask.txt"), "1 1\n1 1\n").unwrap();
    assert_rejected(&["--aperture-image", &path("black.png")], "all black");
    assert_rejected(&["--aperture-image", &path("missing.png")], "missing.png");
    assert_rejected(&["--aperture-image", &path("text.png")], "text.png");
    assert_rejected(&["--aperture-image", &path("mask.txt")], "png or .exr");
    assert_rejected(
        &[
            "--aperture-image",
            &path("white.png"),
            "--aperture-blades",
            "6",
        ],
        "either aperture blades or an aperture image",
    );
}

#[test]
fn bad_files_are_rejected_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    std::fs::write(p.join("bad.obj"), "v 1 2\nf 1 2 3\n").unwrap();
    std::fs::write(p.join("empty.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    std::fs::write(
        p.join("nomtl.obj"),
        "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    // A missing material library is a real download's mess, not bad input: one warning.
    let out = lensray(
        &render_args(&[
            "--scene",
            p.join("nomtl.obj").to_str().unwrap(),
            "--out",
            "o.png",
        ]),
        p,
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("warning: ") && err.contains("missing.mtl"),
        "{err}"
    );
    std::fs::write(p.join("bad.toml"), "mesh = \"bad.obj\"\n[camera\n").unwrap();
    std::fs::write(p.join("unknown.toml"), "mesh = \"empty.obj\"\nzoom = 3\n").unwrap();
    for (scene, needle) in [
        ("missing.obj", "missing.obj"),
        ("bad.obj", "bad.obj"),
        ("empty.obj", "no triangles"),
        ("bad.toml", "bad.toml"),
        ("unknown.toml", "zoom"),
        ("scene.txt", "scene.txt"),
    ] {
        let dir2 = tempfile::tempdir().unwrap();
        let full = p.join(scene);
        let out = lensray(
            &render_args(&["--scene", full.to_str().unwrap(), "--out", "o.png"]),
            dir2.path(),
        );
        let err = stderr(&out);
        assert!(!out.status.success(), "{scene} accepted");
        assert!(!err.contains("panicked"), "{scene}: {err}");
        assert_eq!(err.lines().count(), 1, "{scene}: {err}");
        assert!(
            err.contains(needle),
            "{scene}: '{err}' does not name '{needle}'"
        );
        assert!(
            !dir2.path().join("o.png").exists(),
            "{scene}: output written"
        );
    }
}

#[test]
fn bad_outputs_are_rejected_before_rendering() {
    assert_rejected(&["--out", "image.jpg"], "extension");
    // The reason, not the name of the temporary file the check made.
    assert_rejected(
        &["--out", "/nonexistent-dir/x.png"],
        "/nonexistent-dir/x.png: cannot write there: no such folder",
    );
    let under_a_file = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml/x.png");
    assert_rejected(&["--out", under_a_file], "a parent is not a folder");
}

/// `--validate` validates the Vulkan renderer and `--gpu` picks a Vulkan device: with the CPU
/// renderer both are errors, never silently ignored.
#[test]
fn gpu_options_with_device_cpu_are_errors() {
    assert_rejected(&["--validate"], "--validate");
    assert_rejected(&["--validate"], "--device cpu");
    assert_rejected(&["--gpu", "0"], "--gpu 0");
    assert_rejected(&["--gpu", "0"], "--device cpu");
}

#[test]
fn bad_mesh_options_are_rejected_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bin: Vec<u8> = [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(dir.path().join("tri.bin"), bin).unwrap();
    let gltf = dir.path().join("tri.gltf");
    std::fs::write(
        &gltf,
        r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
            "materials": [{"doubleSided": true}],
            "buffers": [{"uri": "tri.bin", "byteLength": 36}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]}]}"#,
    )
    .unwrap();
    let scene = gltf.to_str().unwrap();
    assert_rejected(&["--scene", scene, "--camera", "hero"], "has no cameras");
    assert_rejected(&["--scene", scene, "--smooth-normals", "200"], "0 to 180");
    // The same file renders.
    let out = lensray(
        &render_args(&["--scene", scene, "--out", "tri.png"]),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Every option of `render` that takes numbers refuses NaN and infinity in one line. The
/// options are found by their values' types, so one added later is tried without naming it.
#[test]
fn every_number_option_refuses_nan_and_infinity() {
    use std::any::TypeId;
    let command = <lensray::cli::render::RenderArgs as clap::Args>::augment_args(
        clap::Command::new("render"),
    );
    let mut tried = Vec::new();
    for arg in command.get_arguments() {
        let id = arg.get_value_parser().type_id();
        let bad = if id == TypeId::of::<f64>() || id == TypeId::of::<f32>() {
            ["nan", "inf"].map(String::from)
        } else if id == TypeId::of::<[f64; 2]>() {
            ["0,nan", "-inf,0"].map(String::from)
        } else if id == TypeId::of::<[f64; 3]>()
            || id == TypeId::of::<lensray_core::settings::EnvironmentSetting>()
        {
            ["0,NaN,1", "1,1,inf"].map(String::from)
        } else {
            continue;
        };
        let long = arg.get_long().expect("a number option has a long name");
        for value in &bad {
            let option = format!("--{long}");
            // Each is refused: by its own check (naming the option) or the one over all
            // settings (naming the key, `environment_rotation` for `--environment-rotation`).
            let key = long.replace('-', "_");
            let out = crate::lensray(
                &crate::render_args(&[&option, value, "--out", "out.png"]),
                tempfile::tempdir().unwrap().path(),
            );
            let err = stderr(&out);
            let lines = err.lines().filter(|l| !l.trim().is_empty()).count();
            let names = err.contains(&key) || err.contains(long) || err.contains("finite");
            assert!(
                !out.status.success() && lines == 1 && names && !err.contains("panicked"),
                "{option} {value}: exit {:?}, {lines} lines: {err}",
                out.status.code()
            );
        }
        tried.push(long);
    }
    println!("refused NaN and infinity: {}", tried.join(", "));
    assert!(
        tried.len() >= 30,
        "only {} number options found",
        tried.len()
    );
}
