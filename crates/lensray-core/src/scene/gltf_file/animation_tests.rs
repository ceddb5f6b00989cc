//! Camera animations read from glTF files written here: a camera node under a parent node, a
//! triangle to render, and the animations' channels; poses against their analytic values.

use std::f64::consts::FRAC_PI_2;
use std::path::PathBuf;

use glam::DVec3;

use crate::scene::gltf_file::{load_gltf, MeshFile};
use crate::scene::CameraAnimation;
use crate::settings::{CameraTimeline, Keyframes, Settings};

/// One animation channel: node (0 the parent, 1 the camera, 2 the triangle), path, sampler
/// interpolation, key times and values (flattened).
struct TestChannel {
    node: usize,
    path: &'static str,
    interpolation: &'static str,
    times: Vec<f32>,
    values: Vec<f32>,
}

fn channel(
    node: usize,
    path: &'static str,
    interpolation: &'static str,
    times: &[f32],
    values: &[f32],
) -> TestChannel {
    TestChannel {
        node,
        path,
        interpolation,
        times: times.to_vec(),
        values: values.to_vec(),
    }
}

/// The binary buffer and the JSON of its views and accessors.
#[derive(Default)]
struct Accessors {
    bin: Vec<u8>,
    json: Vec<String>,
}

impl Accessors {
    /// An accessor of `values` as `kind` (SCALAR, VEC3, VEC4) over a view of its own.
    fn add(&mut self, values: &[f32], kind: &str, width: usize, min_max: bool) -> usize {
        let offset = self.bin.len();
        self.bin.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        let index = self.json.len() / 2;
        let bounds = if min_max {
            let column = |c: usize| values.iter().skip(c).step_by(width).copied();
            let (min, max): (Vec<f32>, Vec<f32>) = (0..width)
                .map(|c| {
                    (
                        column(c).fold(f32::INFINITY, f32::min),
                        column(c).fold(f32::NEG_INFINITY, f32::max),
                    )
                })
                .unzip();
            format!(r#","min":{min:?},"max":{max:?}"#)
        } else {
            String::new()
        };
        self.json.push(format!(
            r#"{{"bufferView":{index},"componentType":5126,"count":{},"type":"{kind}"{bounds}}}"#,
            values.len() / width
        ));
        let view = format!(
            r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#,
            values.len() * 4
        );
        self.json.push(view);
        index
    }
}

/// A glTF in a temporary folder: a parent node (rest TRS `parent`) over the camera node at
/// rest translation `camera_at`, a triangle, and one animation per entry of `animations`.
fn write_gltf(
    dir: &tempfile::TempDir,
    parent: &str,
    camera_at: [f32; 3],
    animations: &[Vec<TestChannel>],
) -> PathBuf {
    let mut data = Accessors::default();
    let triangle = [0.0, 0.0, -10.0, 1.0, 0.0, -10.0, 0.0, 1.0, -10.0];
    data.add(&triangle, "VEC3", 3, true);
    let mut animation_json = Vec::new();
    for channels in animations {
        let (mut samplers, mut targets) = (Vec::new(), Vec::new());
        for (i, c) in channels.iter().enumerate() {
            let input = data.add(&c.times, "SCALAR", 1, true);
            let width = if c.path == "rotation" { 4 } else { 3 };
            let kind = if width == 4 { "VEC4" } else { "VEC3" };
            let output = data.add(&c.values, kind, width, false);
            samplers.push(format!(
                r#"{{"input":{input},"output":{output},"interpolation":"{}"}}"#,
                c.interpolation
            ));
            targets.push(format!(
                r#"{{"sampler":{i},"target":{{"node":{},"path":"{}"}}}}"#,
                c.node, c.path
            ));
        }
        animation_json.push(format!(
            r#"{{"name":"move","samplers":[{}],"channels":[{}]}}"#,
            samplers.join(","),
            targets.join(",")
        ));
    }
    let (accessors, views): (Vec<String>, Vec<String>) = data
        .json
        .chunks(2)
        .map(|p| (p[0].clone(), p[1].clone()))
        .unzip();
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,2]}}],
"nodes":[{{"name":"rig","children":[1]{parent}}},{{"name":"cam","camera":0,"translation":{camera_at:?}}},{{"mesh":0}}],
"cameras":[{{"type":"perspective","perspective":{{"yfov":0.8,"znear":0.1}}}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"animations":[{}],"accessors":[{}],"bufferViews":[{}],
"buffers":[{{"uri":"data.bin","byteLength":{}}}]}}"#,
        animation_json.join(","),
        accessors.join(","),
        views.join(","),
        data.bin.len()
    );
    std::fs::write(dir.path().join("data.bin"), &data.bin).unwrap();
    let path = dir.path().join("anim.gltf");
    std::fs::write(&path, text).unwrap();
    path
}

fn load(parent: &str, camera_at: [f32; 3], animations: &[Vec<TestChannel>]) -> MeshFile {
    let dir = tempfile::tempdir().unwrap();
    let path = write_gltf(&dir, parent, camera_at, animations);
    load_gltf(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn animation_of(file: &MeshFile) -> &CameraAnimation {
    file.cameras[0]
        .animation
        .as_ref()
        .unwrap_or_else(|| panic!("no camera animation; notices {:?}", file.notices))
}

/// The view direction of glTF's camera (-Z) turned by `angle` about +Y.
fn turned(angle: f64) -> DVec3 {
    DVec3::new(-angle.sin(), 0.0, -angle.cos())
}

fn assert_close(what: &str, got: DVec3, want: DVec3) {
    let error = (got - want).abs().max_element();
    assert!(
        error < 1e-5,
        "{what}: {got} against the analytic {want}, off by {error:.2e}"
    );
}

const A: [f32; 3] = [0.0, 1.0, 5.0];
const B: [f32; 3] = [2.0, 1.0, 1.0];
/// The rotation of 90 degrees about +Y, as glTF's (x, y, z, w).
const QUARTER_TURN: [f32; 4] = [
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
];
const REST: [f32; 4] = [0.0, 0.0, 0.0, 1.0];

/// The camera moved from A to B and turned by 90 degrees about +Y over 1 s, sampled as
/// `interpolation` says; CUBICSPLINE's tangents are the constant velocity (B - A) / 1 s for
/// the translation and zero for the rotation.
fn a_to_b(interpolation: &'static str) -> Vec<TestChannel> {
    if interpolation == "CUBICSPLINE" {
        let v = [B[0] - A[0], B[1] - A[1], B[2] - A[2]];
        let translation = [v, A, v, v, B, v].concat();
        let rotation = [[0.0; 4], REST, [0.0; 4], [0.0; 4], QUARTER_TURN, [0.0; 4]].concat();
        return vec![
            channel(1, "translation", interpolation, &[0.0, 1.0], &translation),
            channel(1, "rotation", interpolation, &[0.0, 1.0], &rotation),
        ];
    }
    vec![
        channel(
            1,
            "translation",
            interpolation,
            &[0.0, 1.0],
            &[A, B].concat(),
        ),
        channel(
            1,
            "rotation",
            interpolation,
            &[0.0, 1.0],
            &[REST, QUARTER_TURN].concat(),
        ),
    ]
}

/// A frame, the fraction of the way along the translation and that of the turn (NaN: not
/// checked).
type Along = (u32, f64, f64);

#[test]
fn linear_step_and_cubic_spline_poses_match_the_analytic_ones_at_24_fps() {
    let (a, b) = (DVec3::from(A.map(f64::from)), DVec3::from(B.map(f64::from)));
    let cases: [(&str, [Along; 4]); 3] = [
        (
            "LINEAR",
            [
                (0, 0.0, 0.0),
                (6, 0.25, 0.25),
                (12, 0.5, 0.5),
                (24, 1.0, 1.0),
            ],
        ),
        (
            "STEP",
            [(0, 0.0, 0.0), (6, 0.0, 0.0), (12, 0.0, 0.0), (24, 1.0, 1.0)],
        ),
        // Zero rotation tangents: the Hermite weights of the two keys are equal at 0.5 s, a
        // turn of 45 degrees once normalized; the velocity tangents keep the translation
        // linear (zero ones would put frame 6 at 0.156 of the way).
        (
            "CUBICSPLINE",
            [
                (0, 0.0, 0.0),
                (6, 0.25, f64::NAN),
                (12, 0.5, 0.5),
                (24, 1.0, 1.0),
            ],
        ),
    ];
    for (interpolation, frames) in cases {
        let file = load("", [0.0; 3], &[a_to_b(interpolation)]);
        let timeline = CameraTimeline::new(animation_of(&file).clone(), 24.0);
        assert_eq!(timeline.frame_range(), (0, 24), "{interpolation}");
        for (frame, along, turn) in frames {
            let pose = timeline.animation().pose_at(timeline.time(frame));
            let what = format!("{interpolation} frame {frame}");
            assert_close(&format!("{what} eye"), pose.eye, a + (b - a) * along);
            if !turn.is_nan() {
                assert_close(
                    &format!("{what} view"),
                    pose.forward,
                    turned(turn * FRAC_PI_2),
                );
            }
            assert_close(&format!("{what} up"), pose.up, DVec3::Y);
        }
    }
}

#[test]
fn cubic_spline_tangents_are_scaled_by_the_key_interval() {
    // x(t) = t^3 through keys at 0, 0.5 and 1 s with its derivative 3 t^2 as tangents: the
    // cubic Hermite spline is x itself between keys 0.5 s apart.
    let key = |t: f32| {
        [
            [3.0 * t * t, 0.0, 0.0],
            [t * t * t, 0.0, 0.0],
            [3.0 * t * t, 0.0, 0.0],
        ]
        .concat()
    };
    let values = [key(0.0), key(0.5), key(1.0)].concat();
    let moves = channel(1, "translation", "CUBICSPLINE", &[0.0, 0.5, 1.0], &values);
    let file = load("", [0.0; 3], &[vec![moves]]);
    let timeline = CameraTimeline::new(animation_of(&file).clone(), 24.0);
    for frame in [3, 6, 9, 15, 18, 21] {
        let t = timeline.time(frame);
        let eye = timeline.animation().pose_at(t).eye;
        assert_close(
            &format!("frame {frame}"),
            eye,
            DVec3::new(t * t * t, 0.0, 0.0),
        );
    }
}

#[test]
fn a_parent_nodes_animation_composes_with_the_cameras() {
    // The rig at (1, 0, 0) turns by 90 degrees about +Y while the camera, 5 m along the rig's
    // +Z, rises from 0 to 2 m in the same animation.
    let turn = channel(
        0,
        "rotation",
        "LINEAR",
        &[0.0, 1.0],
        &[REST, QUARTER_TURN].concat(),
    );
    let rise = channel(
        1,
        "translation",
        "LINEAR",
        &[0.0, 1.0],
        &[0.0, 0.0, 5.0, 0.0, 2.0, 5.0],
    );
    let file = load(
        r#","translation":[1.0,0.0,0.0]"#,
        [0.0, 0.0, 5.0],
        &[vec![turn, rise]],
    );
    let animation = animation_of(&file);
    for frame in [0, 12, 24] {
        let t = f64::from(frame) / 24.0;
        let angle = t * FRAC_PI_2;
        let pose = animation.pose_at(t);
        let eye = DVec3::new(1.0 + 5.0 * angle.sin(), 2.0 * t, 5.0 * angle.cos());
        assert_close(&format!("frame {frame} eye"), pose.eye, eye);
        assert_close(&format!("frame {frame} view"), pose.forward, turned(angle));
    }
    // In centimetres the same motion is 100 times shorter.
    let scaled = animation.scaled(0.01).pose_at(0.5).eye;
    assert_close("scaled eye", scaled, animation.pose_at(0.5).eye * 0.01);
}

#[test]
fn bad_animation_data_is_one_notice_and_the_animation_is_skipped() {
    let translation = [A, B].concat();
    let cases = [
        (
            channel(1, "translation", "LINEAR", &[0.0, 0.5, 1.0], &translation),
            "has 3 key times but 2 values",
        ),
        (
            channel(1, "translation", "LINEAR", &[1.0, 0.5], &translation),
            "key times that do not increase (1 then 0.5)",
        ),
        (
            channel(
                1,
                "translation",
                "LINEAR",
                &[0.0, 1.0],
                &[0.0, f32::NAN, 0.0, 1.0, 1.0, 1.0],
            ),
            "not finite",
        ),
        (
            channel(
                1,
                "rotation",
                "LINEAR",
                &[0.0, 1.0],
                &[[0.0; 4], REST].concat(),
            ),
            "zero rotation",
        ),
    ];
    for (bad, reason) in cases {
        // The bad animation comes first; the good one after it is played.
        let file = load("", [0.0; 3], &[vec![bad], a_to_b("LINEAR")]);
        let notices: Vec<&String> = file
            .notices
            .iter()
            .filter(|n| n.contains("animation"))
            .collect();
        assert_eq!(notices.len(), 1, "{reason}: {notices:?}");
        assert!(
            notices[0].contains("animation 0 ('move')")
                && notices[0].contains(reason)
                && notices[0].contains("skipped"),
            "{reason}: {}",
            notices[0]
        );
        assert_eq!(animation_of(&file).name, "animation 1 ('move')");
    }
}

/// An animation of the mesh's node leaves the camera still and moves the mesh: it is the
/// scene's motion, not an animation left unplayed.
#[test]
fn an_animation_of_other_nodes_leaves_the_camera_still() {
    let spin = channel(
        2,
        "rotation",
        "LINEAR",
        &[0.0, 1.0],
        &[REST, QUARTER_TURN].concat(),
    );
    let file = load("", [0.0; 3], &[vec![spin]]);
    assert_eq!(file.cameras[0].animation, None);
    assert!(
        file.other_animations.is_empty(),
        "{:?}",
        file.other_animations
    );
    let motion = file.motion.as_ref().expect("the mesh moves");
    assert_eq!(motion.names, vec!["animation 0 ('move')".to_string()]);
    assert_eq!((motion.meshes.len(), motion.meshes[0].index), (1, 0));
    assert_eq!(motion.time_range(), (0.0, 1.0));
    assert!(
        file.notices.iter().all(|n| !n.contains("animation")),
        "{:?}",
        file.notices
    );
}

#[test]
fn a_sequence_takes_eye_target_and_up_from_the_animation_unless_keys_move_the_camera() {
    let file = load("", [0.0; 3], &[a_to_b("LINEAR")]);
    let timeline = CameraTimeline::new(animation_of(&file).clone(), 24.0);
    let mut base = Settings::default();
    base.camera.eye = Some([0.0, 0.0, 0.0]);
    base.camera.target = Some([0.0, 0.0, -3.0]);
    let focus = Keyframes::parse(
        &[toml::from_str("frame = 0\nfocus_distance = 2.0").unwrap()],
        std::path::Path::new(""),
    )
    .unwrap();
    let (keyframes, warning) = focus.with_camera_timeline(timeline.clone());
    assert_eq!(warning, None);
    // The range (the preview's slider) covers the key at frame 0 and the animation's 24 frames.
    assert_eq!(keyframes.range(), Some((0, 24)));
    let at = keyframes.settings_at(&base, 12).camera;
    let eye = DVec3::new(1.0, 1.0, 3.0);
    assert_close("eye", DVec3::from(at.eye.unwrap()), eye);
    // The target lies at the keyed focus distance along the view.
    let target = eye + turned(FRAC_PI_2 / 2.0) * 2.0;
    assert_close("target", DVec3::from(at.target.unwrap()), target);
    assert_close("up", DVec3::from(at.up.unwrap()), DVec3::Y);
    // Without a focus distance, at the settings' own target distance (3 m).
    let still = Keyframes::default()
        .with_camera_timeline(timeline.clone())
        .0;
    assert_eq!(still.range(), Some((0, 24)), "the animation's frames alone");
    let target = DVec3::from(still.settings_at(&base, 24).camera.target.unwrap());
    assert_close(
        "own distance",
        target,
        DVec3::from(B.map(f64::from)) + turned(FRAC_PI_2) * 3.0,
    );

    let eye_key = Keyframes::parse(
        &[toml::from_str("frame = 5\neye = [0.0, 0.0, 9.0]").unwrap()],
        std::path::Path::new(""),
    )
    .unwrap();
    let (keyframes, warning) = eye_key.with_camera_timeline(timeline);
    let warning = warning.expect("a warning line");
    assert!(
        warning.contains("frame 5") && warning.contains("animation 0 ('move')"),
        "{warning}"
    );
    assert_eq!(keyframes.camera_timeline(), None);
    assert_eq!(
        keyframes.settings_at(&base, 12).camera.eye,
        Some([0.0, 0.0, 9.0])
    );
}

#[test]
fn a_second_animation_of_the_camera_is_named_once_and_not_played() {
    let file = load("", [0.0; 3], &[a_to_b("STEP"), a_to_b("LINEAR")]);
    assert_eq!(animation_of(&file).name, "animation 0 ('move')");
    let notices: Vec<&String> = file
        .notices
        .iter()
        .filter(|n| n.contains("animation"))
        .collect();
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert!(
        notices[0].contains("animation 1 ('move') also moves camera"),
        "{}",
        notices[0]
    );
    assert!(
        file.other_animations.is_empty(),
        "{:?}",
        file.other_animations
    );
}
