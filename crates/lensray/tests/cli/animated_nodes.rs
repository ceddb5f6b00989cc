//! glTF node animations in a sequence: Khronos's BoxAnimated (`assets/BoxAnimated`: an inner box
//! that rises, turns half a turn about X and sinks, inside nothing but beside an outer box at
//! rest) is posed on each frame, and each frame is the still render of the file posed by hand at
//! that time (its animation removed, the nodes' TRS interpolated here); the GPU paths render the
//! same frames in one process each.

use std::fs;
use std::path::{Path, PathBuf};

use glam::{DQuat, DVec3};
use lensray_core::settings::frame_seed;

use crate::gpu_support::{compare, skip_or_fail, write_comparison};
use crate::{lensray, read_exr, render_args, stderr};

/// Frame 18 (0.75 s at 24 fps): the box rising, not yet turning; frame 42 (1.75 s): at the top,
/// 40 % through its turn.
const FRAMES: [u32; 2] = [18, 42];
const FPS: f64 = 24.0;

/// The view and light of every render here: the default camera and light follow the scene's
/// bounds, which the posed copies change.
const VIEW: [&str; 12] = [
    "--eye",
    "0,3,7",
    "--target",
    "0,1.5,0",
    "--up",
    "0,1,0",
    "--light-position",
    "2,6,5",
    "--light-intensity",
    "60,60,60",
    "--fps",
    "24",
];

fn asset_folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/BoxAnimated")
}

/// Node 0's translation and node 2's rotation at `time` seconds, from the keys as the file's
/// accessors hold them (f32): the translation linear through (0, 0), (1.25, 2.52), (2.5, 2.52),
/// (3.708, 0) in Y; the rotation from -identity at 1.25 s to half a turn about X at 2.5 s by
/// glam's slerp (the shorter arc).
fn pose_by_hand(time: f64) -> (DVec3, DQuat) {
    let (times, heights) = (
        [0.0f32, 1.25, 2.5, 3.708_33].map(f64::from),
        [0.0f32, 2.52, 2.52, 0.0].map(f64::from),
    );
    let k = times.windows(2).position(|w| time < w[1]).unwrap_or(2);
    let u = ((time - times[k]) / (times[k + 1] - times[k])).clamp(0.0, 1.0);
    let translation = DVec3::new(0.0, heights[k] + u * (heights[k + 1] - heights[k]), 0.0);
    let q0 = DQuat::from_array([-0.0, -0.0, -0.0, -1.0]);
    let q1 = DQuat::from_array([1.0f32, 0.0, 0.0, 4.489_659_3e-11].map(f64::from));
    let u = ((time - 1.25) / 1.25).clamp(0.0, 1.0);
    (translation, q0.slerp(q1, u))
}

/// A copy of BoxAnimated in `dir` posed by hand at `time`, without its animation.
fn posed_copy(dir: &Path, time: f64) -> PathBuf {
    let folder = asset_folder();
    let text = fs::read_to_string(folder.join("BoxAnimated.gltf")).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let (translation, rotation) = pose_by_hand(time);
    json["nodes"][0]["translation"] = serde_json::json!(translation.to_array());
    json["nodes"][2]["rotation"] = serde_json::json!(rotation.to_array());
    json.as_object_mut().unwrap().remove("animations");
    fs::copy(
        folder.join("BoxAnimated0.bin"),
        dir.join("BoxAnimated0.bin"),
    )
    .unwrap();
    let path = dir.join(format!("posed-{time}.gltf"));
    fs::write(&path, serde_json::to_string(&json).unwrap()).unwrap();
    path
}

/// Renders `scene` with `extra` on `device` (`gpu`: the path `path`, validation on).
fn render(
    dir: &Path,
    scene: &Path,
    device: &str,
    path: &str,
    extra: &[&str],
) -> std::process::Output {
    let scene = scene.to_str().unwrap();
    let mut args = render_args(&["--scene", scene]);
    args[2] = device;
    if device == "gpu" {
        args.extend(["--path", path, "--validate"]);
    }
    args.extend(VIEW);
    args.extend(extra);
    lensray(&args, dir)
}

#[test]
fn animated_nodes_move_each_frame_as_posed_by_hand() {
    let test = "animated_nodes_move_each_frame_as_posed_by_hand";
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let file = asset_folder().join("BoxAnimated.gltf");
    let frames = format!("{}-{}:{}", FRAMES[0], FRAMES[1], FRAMES[1] - FRAMES[0]);
    let sequence = ["--frames", frames.as_str(), "--out", "cpu.####.exr"];
    let out = render(d, &file, "cpu", "cpu", &sequence);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("animation 0 moves 1 mesh and 0 lights: keys from 0.000 s to 3.708 s"),
        "{err}"
    );
    let frame = |prefix: &str, n: u32| read_exr(&d.join(format!("{prefix}.{n:04}.exr")));
    let moved = compare(
        &frame("cpu", FRAMES[0]),
        &frame("cpu", FRAMES[1]),
        1.0 / 255.0,
    );
    assert!(
        moved.within < 0.95,
        "{test}: the frames hardly differ: {moved:?}"
    );
    for n in FRAMES {
        let posed = posed_copy(d, f64::from(n) / FPS);
        let seed = frame_seed(0, n).to_string();
        let still = format!("still-{n}.exr");
        let out = render(d, &posed, "cpu", "cpu", &["--seed", &seed, "--out", &still]);
        assert!(out.status.success(), "{}", stderr(&out));
        // The loader places the still's nodes with the gltf crate's f32 matrices, the sequence
        // with f64 products of the tracks' TRS: positions agree to float rounding (measured:
        // every pixel within 1.2e-7), which could move an edge sample on a pixel or two.
        let diff = compare(&frame("cpu", n), &read_exr(&d.join(&still)), 1.0 / 255.0);
        println!("{test}: frame {n} against the still posed by hand: {diff:?}");
        if diff.within < 0.999 || diff.mean_abs >= 1e-5 {
            let files = write_comparison(
                &frame("cpu", n),
                &read_exr(&d.join(&still)),
                &format!("{test}-{n}"),
            );
            panic!("{test}: frame {n} is not the still posed by hand: {diff:?}; wrote {files}");
        }
    }
    for path in ["software", "rayquery"] {
        let out_pattern = format!("{path}.####.exr");
        let sequence = ["--frames", frames.as_str(), "--out", out_pattern.as_str()];
        let gpu = render(d, &file, "gpu", path, &sequence);
        if !gpu.status.success() {
            skip_or_fail(test, &stderr(&gpu));
            return;
        }
        assert!(!stderr(&gpu).contains("vulkan:"), "{}", stderr(&gpu));
        for n in FRAMES {
            let (image, reference) = (frame(path, n), frame("cpu", n));
            let diff = compare(&image, &reference, 1.0 / 255.0);
            println!("{test} {path} frame {n}: {diff:?}");
            if diff.within < 0.999 || diff.mean_abs >= 1e-3 {
                let files = write_comparison(&image, &reference, &format!("{test}-{path}-{n}"));
                panic!("{test}: {path} frame {n} differs from the CPU: {diff:?}; wrote {files}");
            }
        }
    }
}
