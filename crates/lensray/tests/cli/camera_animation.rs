//! A glTF camera animation played by `--frames` on the CPU path: each frame is its own pose,
//! frame 1 is the still render at the pose interpolated by hand, and a bad animation is one
//! warning line and a render of the camera at rest.

use std::fs;
use std::path::{Path, PathBuf};

use glam::DVec3;
use lensray_core::settings::frame_seed;

use crate::{lensray, render_args, stderr};

/// The camera's keys: at 0 s at `EYE_0` facing -Z, at 0.5 s at `EYE_1` turned by `TURN_DEGREES`
/// about +Y. At 4 fps frame 1 is 0.25 s, halfway.
const EYE_0: [f32; 3] = [0.0, 0.8, 4.0];
const EYE_1: [f32; 3] = [0.6, 0.8, 3.4];
const TURN_DEGREES: f64 = 20.0;
const FOCUS: f64 = 3.0;

/// Two triangles (a quad) from corner `a` along `u` and `v`.
pub(crate) fn quad(a: [f32; 3], u: [f32; 3], v: [f32; 3]) -> Vec<f32> {
    let p = |s: f32, t: f32| [0, 1, 2].map(|i| a[i] + s * u[i] + t * v[i]);
    [
        p(0.0, 0.0),
        p(1.0, 0.0),
        p(1.0, 1.0),
        p(0.0, 0.0),
        p(1.0, 1.0),
        p(0.0, 1.0),
    ]
    .concat()
}

/// A glTF (with `data.bin` beside it) of a floor and two upright quads, and a camera node
/// animated as the constants say; `times` are the key times as written (bad data included).
fn animated_gltf(dir: &Path, times: [f32; 2]) -> PathBuf {
    let positions = [
        quad([-3.0, 0.0, 2.0], [6.0, 0.0, 0.0], [0.0, 0.0, -8.0]),
        quad([-1.5, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.2, 0.0]),
        quad([0.8, 0.0, -3.0], [1.0, 0.0, 0.3], [0.0, 1.6, 0.0]),
    ]
    .concat();
    let half = (TURN_DEGREES.to_radians() / 2.0) as f32;
    let rotations = [0.0, 0.0, 0.0, 1.0, 0.0, half.sin(), 0.0, half.cos()];
    let translations = [EYE_0, EYE_1].concat();
    let mut bin = Vec::new();
    let mut views = Vec::new();
    for data in [
        &positions[..],
        &times[..],
        &translations[..],
        &rotations[..],
    ] {
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            data.len() * 4
        ));
        bin.extend(data.iter().flat_map(|x| x.to_le_bytes()));
    }
    let (lo, hi) = (times[0].min(times[1]), times[0].max(times[1]));
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"name":"cam","camera":0,"translation":{EYE_0:?}}},{{"mesh":0}}],
"cameras":[{{"type":"perspective","perspective":{{"yfov":0.9,"znear":0.05}}}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"animations":[{{"name":"dolly","samplers":[{{"input":1,"output":2}},{{"input":1,"output":3}}],
"channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}},{{"sampler":1,"target":{{"node":0,"path":"rotation"}}}}]}}],
"accessors":[
{{"bufferView":0,"componentType":5126,"count":{},"type":"VEC3","min":[-3,0,-6],"max":[3,1.6,2]}},
{{"bufferView":1,"componentType":5126,"count":2,"type":"SCALAR","min":[{lo}],"max":[{hi}]}},
{{"bufferView":2,"componentType":5126,"count":2,"type":"VEC3"}},
{{"bufferView":3,"componentType":5126,"count":2,"type":"VEC4"}}],
"bufferViews":[{}],"buffers":[{{"uri":"data.bin","byteLength":{}}}]}}"#,
        positions.len() / 3,
        views.join(","),
        bin.len()
    );
    fs::write(dir.join("data.bin"), &bin).unwrap();
    let path = dir.join("dolly.gltf");
    fs::write(&path, text).unwrap();
    path
}

/// The scene file over the glTF: focus at `FOCUS`, so the target lies there.
fn scene_file(dir: &Path, gltf: &Path) -> PathBuf {
    let path = dir.join("dolly.toml");
    let text = format!(
        "mesh = {:?}\n[camera]\nfocus_distance = {FOCUS:?}\n[render]\nbackground = [0.2, 0.3, 0.5]\n",
        gltf.to_str().unwrap()
    );
    fs::write(&path, text).unwrap();
    path
}

fn run(dir: &Path, args: &[&str]) -> String {
    // A light of its own: a default light would follow the first frame's eye.
    let extra: Vec<&str> = [
        "--width",
        "32",
        "--height",
        "24",
        "--fps",
        "4",
        "--light-position",
        "1,3,2",
        "--light-intensity",
        "20,20,20",
    ]
    .into_iter()
    .chain(args.iter().copied())
    .collect();
    let out = lensray(&render_args(&extra), dir);
    let err = stderr(&out);
    assert!(out.status.success(), "{args:?} failed: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    err
}

fn pixels(path: PathBuf) -> Vec<u8> {
    image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
        .into_raw()
}

/// The number of 8-bit channels that differ, and the largest difference.
fn differences(a: &[u8], b: &[u8]) -> (usize, u8) {
    let d = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y));
    (d.clone().filter(|&d| d > 0).count(), d.max().unwrap_or(0))
}

fn triple(v: DVec3) -> String {
    format!("{:?},{:?},{:?}", v.x, v.y, v.z)
}

#[test]
fn an_animated_camera_moves_each_frame_and_frame_1_is_the_interpolated_still() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let gltf = animated_gltf(d, [0.0, 0.5]);
    let scene = scene_file(d, &gltf);
    let scene = scene.to_str().unwrap();
    let err = run(
        d,
        &["--scene", scene, "--frames", "0-2", "--out", "f.####.png"],
    );
    assert!(
        err.contains("animation 0 ('dolly') moves the camera")
            && err.contains("frames 0 to 2 at 4 fps"),
        "{err}"
    );
    let frames: Vec<Vec<u8>> = (0..3)
        .map(|n| pixels(d.join(format!("f.000{n}.png"))))
        .collect();
    for (a, b) in [(0, 1), (1, 2), (0, 2)] {
        let (count, largest) = differences(&frames[a], &frames[b]);
        assert!(
            count > 50,
            "frames {a} and {b} differ in only {count} channels (largest {largest})"
        );
    }
    // Frame 1 (0.25 s) by hand: halfway along the translation, turned by half the angle.
    let (e0, e1) = (
        DVec3::from(EYE_0.map(f64::from)),
        DVec3::from(EYE_1.map(f64::from)),
    );
    let eye = (e0 + e1) / 2.0;
    let half = (TURN_DEGREES / 2.0).to_radians();
    let target = eye + DVec3::new(-half.sin(), 0.0, -half.cos()) * FOCUS;
    let seed = frame_seed(0, 1).to_string();
    let (eye, target) = (triple(eye), triple(target));
    let still = [
        "--scene",
        scene,
        "--eye",
        &eye,
        "--target",
        &target,
        "--up",
        "0,1,0",
        "--seed",
        &seed,
        "--out",
        "still.png",
    ];
    let err = run(d, &still);
    assert!(err.contains("this render is the camera at rest"), "{err}");
    let (count, largest) = differences(&frames[1], &pixels(d.join("still.png")));
    // The same seed and the same pose (the animation's and the one by hand agree to float
    // rounding, which the camera's f32 absorbs here): the same image, bit for bit.
    assert!(
        count == 0,
        "frame 1 and the still at the interpolated pose differ in {count} channels, by up to {largest}"
    );
    // The glTF given directly plays its animation too (its target at the scene's depth, the
    // same view through the default pinhole).
    let gltf = gltf.to_str().unwrap();
    run(
        d,
        &[
            "--scene",
            gltf,
            "--frames",
            "1",
            "--out",
            "m.####.png",
            "--background",
            "0.2,0.3,0.5",
        ],
    );
    let (count, largest) = differences(&frames[1], &pixels(d.join("m.0001.png")));
    assert!(
        count == 0,
        "the glTF's frame 1 and the scene file's differ in {count} channels, by up to {largest}"
    );
}

#[test]
fn a_bad_animation_is_one_warning_and_the_camera_renders_at_rest() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let gltf = animated_gltf(d, [0.5, 0.5]);
    let gltf = gltf.to_str().unwrap();
    let err = run(
        d,
        &["--scene", gltf, "--frames", "0-1", "--out", "b.####.png"],
    );
    let warnings: Vec<&str> = err.lines().filter(|l| l.contains("animation")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(
        warnings[0].starts_with("warning: ")
            && warnings[0].contains("key times that do not increase (0.5 then 0.5)")
            && warnings[0].contains("skipped"),
        "{err}"
    );
    // Frame 1 is the still of the camera at rest with frame 1's seed, bit for bit.
    let seed = frame_seed(0, 1).to_string();
    run(d, &["--scene", gltf, "--seed", &seed, "--out", "still.png"]);
    let (a, b) = (pixels(d.join("b.0001.png")), pixels(d.join("still.png")));
    assert_eq!(differences(&a, &b), (0, 0), "the camera moved");
}
