//! Sequences (`--frames`, `--chunk`, `--resume`) on the CPU path: a frame is the same file bit
//! for bit however the range is split, `--resume` keeps complete frames and renders partial
//! ones again, and bad ranges, chunks and keyframes are one line each.

use std::fs;
use std::path::{Path, PathBuf};

use crate::gpu_support::skip_or_fail;
use crate::{assert_rejected, lensray, render_args, stderr};

/// The spheres scene with a focus pull from 3 m to 12 m over frames 1 to 6, eased.
pub(crate) fn pull_scene(dir: &Path, keyframes: &str) -> PathBuf {
    let mesh = crate::spheres_beside(dir);
    let text = format!(
        "mesh = {mesh:?}\n\
         [camera]\neye = [0.0, 1.2, 6.5]\ntarget = [0.0, 0.4, 0.0]\nvfov_degrees = 40.0\n\
         aperture_radius = 0.3\nfocus_distance = 6.5\n\
         [render]\nshading = \"lit\"\nbackground = [0.5, 0.65, 0.85]\n\
         [light]\nposition = [3.0, 8.0, 6.0]\nintensity = [300.0, 300.0, 300.0]\n{keyframes}",
    );
    let path = dir.join("pull.toml");
    fs::write(&path, text).unwrap();
    path
}

pub(crate) const PULL: &str =
    "[[keyframe]]\nframe = 1\nfocus_distance = 3.0\ninterpolation = \"smooth\"\n\
                    [[keyframe]]\nframe = 6\nfocus_distance = 12.0\n";

/// Renders `extra` (with the pull scene) in `dir`; the command must succeed.
fn render_in(dir: &Path, scene: &Path, extra: &[&str]) -> String {
    let mut args = vec!["--scene", scene.to_str().unwrap()];
    args.extend_from_slice(extra);
    let out = lensray(&render_args(&args), dir);
    assert!(out.status.success(), "{extra:?} failed: {}", stderr(&out));
    stderr(&out)
}

fn bytes(path: PathBuf) -> Vec<u8> {
    fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn a_frame_is_the_same_however_the_range_is_split() {
    let dir = tempfile::tempdir().unwrap();
    let scene = pull_scene(dir.path(), PULL);
    let (whole, chunks, alone) = (
        dir.path().join("w"),
        dir.path().join("c"),
        dir.path().join("a"),
    );
    for d in [&whole, &chunks, &alone] {
        fs::create_dir(d).unwrap();
    }
    render_in(
        dir.path(),
        &scene,
        &["--frames", "1-6", "--out", "w/f.####.exr"],
    );
    for chunk in ["0/3", "1/3", "2/3"] {
        render_in(
            dir.path(),
            &scene,
            &["--frames", "1-6", "--chunk", chunk, "--out", "c/f.%04d.exr"],
        );
    }
    render_in(
        dir.path(),
        &scene,
        &["--frames", "4", "--out", "a/f.####.exr"],
    );
    let name = |frame: u32| format!("f.{frame:04}.exr");
    for frame in 1..=6 {
        let (w, c) = (
            bytes(whole.join(name(frame))),
            bytes(chunks.join(name(frame))),
        );
        assert!(
            w == c,
            "frame {frame}: the chunked render's file differs from the whole range's"
        );
    }
    assert!(
        bytes(alone.join(name(4))) == bytes(whole.join(name(4))),
        "frame 4 alone differs"
    );
    let files = fs::read_dir(&alone).unwrap().count();
    assert_eq!(files, 1, "--frames 4 writes one file and no temporary ones");
    // The pull moves: the first and last frames differ (their focus and their seeds).
    assert!(
        bytes(whole.join(name(1))) != bytes(whole.join(name(6))),
        "frames 1 and 6 are equal"
    );
}

/// On a GPU path (validation on) each frame uploads its own camera: the range's last frame is
/// the file the frame renders alone, and start-up is said once.
#[test]
fn a_gpu_frame_is_the_same_alone_and_in_a_range() {
    let test = "a_gpu_frame_is_the_same_alone_and_in_a_range";
    let dir = tempfile::tempdir().unwrap();
    let scene = pull_scene(dir.path(), PULL);
    let run = |frames: &str, out: &str| {
        let mut args = render_args(&["--scene", scene.to_str().unwrap(), "--frames", frames]);
        args[2] = "gpu";
        args.extend(["--path", "software", "--validate", "--out", out]);
        lensray(&args, dir.path())
    };
    let range = run("1-6:5", "r.####.exr");
    if !range.status.success() {
        skip_or_fail(test, &stderr(&range));
        return;
    }
    let alone = run("6", "a.####.exr");
    assert!(alone.status.success(), "{}", stderr(&alone));
    let file = |name: &str| bytes(dir.path().join(name));
    assert!(
        file("r.0006.exr") == file("a.0006.exr"),
        "frame 6 differs alone and in the range"
    );
    assert!(
        file("r.0001.exr") != file("r.0006.exr"),
        "frames 1 and 6 are equal"
    );
    let summary = String::from_utf8_lossy(&range.stdout);
    assert_eq!(summary.matches("start-up").count(), 1, "{summary}");
    assert!(
        summary.contains("(2 rendered, 0 complete and skipped)"),
        "{summary}"
    );
}

#[test]
fn resume_keeps_complete_frames_and_renders_partial_ones_again() {
    let dir = tempfile::tempdir().unwrap();
    let scene = pull_scene(dir.path(), PULL);
    let frames = [
        "--frames",
        "1-4",
        "--out",
        "f.####.png",
        "--progress",
        "lines",
    ];
    render_in(dir.path(), &scene, &frames);
    let file = |frame: u32| dir.path().join(format!("f.{frame:04}.png"));
    let first: Vec<Vec<u8>> = (1..=4).map(|f| bytes(file(f))).collect();
    // Frame 1: another complete image of the right size, kept. Frame 2 cut in half, frame 3
    // one byte short (its IEND chunk's CRC), frame 4 a whole image of another size.
    image::RgbImage::new(48, 32).save(file(1)).unwrap();
    let kept = bytes(file(1));
    fs::write(file(2), &first[1][..first[1].len() / 2]).unwrap();
    fs::write(file(3), &first[2][..first[2].len() - 1]).unwrap();
    image::RgbImage::new(10, 10).save(file(4)).unwrap();
    let mut resume = frames.to_vec();
    resume.push("--resume");
    let err = render_in(dir.path(), &scene, &resume);
    assert_eq!(
        bytes(file(1)),
        kept,
        "frame 1 was complete and is rendered again"
    );
    for frame in 2..=4 {
        let i = frame as usize - 1;
        assert!(
            bytes(file(frame)) == first[i],
            "frame {frame} is not the image the first run wrote"
        );
    }
    assert!(
        err.contains("frame 1: f.0001.png is complete, skipped"),
        "{err}"
    );
    for (frame, n) in [(2, 2), (3, 3), (4, 4)] {
        let line = format!("frame {frame} ({n} of 4): f.{frame:04}.png in ");
        assert!(err.contains(&line), "no line '{line}' in: {err}");
    }
    // An EXR cut short is rendered again; a whole one is kept.
    let exr = [
        "--frames",
        "1-2",
        "--out",
        "e.####.exr",
        "--progress",
        "lines",
    ];
    render_in(dir.path(), &scene, &exr);
    let second = bytes(dir.path().join("e.0002.exr"));
    fs::write(dir.path().join("e.0002.exr"), &second[..second.len() - 100]).unwrap();
    let mut resume = exr.to_vec();
    resume.push("--resume");
    let err = render_in(dir.path(), &scene, &resume);
    assert!(
        err.contains("frame 1: e.0001.exr is complete, skipped"),
        "{err}"
    );
    assert!(err.contains("frame 2 (2 of 2): e.0002.exr in "), "{err}");
    assert!(
        bytes(dir.path().join("e.0002.exr")) == second,
        "the cut EXR is not rendered again"
    );
}

/// A key's `focus_at` focuses that frame as `--focus-at` does: the same file bit for bit.
#[test]
fn a_pixel_key_focuses_as_focus_at_does() {
    let dir = tempfile::tempdir().unwrap();
    let keyed = pull_scene(dir.path(), "[[keyframe]]\nframe = 2\nfocus_at = [30, 20]\n");
    fs::rename(&keyed, dir.path().join("keyed.toml")).unwrap();
    let plain = pull_scene(dir.path(), "");
    let keyed = dir.path().join("keyed.toml");
    render_in(
        dir.path(),
        &keyed,
        &["--frames", "2", "--out", "k.####.exr"],
    );
    let err = render_in(
        dir.path(),
        &plain,
        &[
            "--frames",
            "2",
            "--focus-at",
            "30,20",
            "--out",
            "p.####.exr",
        ],
    );
    assert!(!err.contains("error"), "{err}");
    let (k, p) = (
        bytes(dir.path().join("k.0002.exr")),
        bytes(dir.path().join("p.0002.exr")),
    );
    assert!(k == p, "the keyed pixel's focus differs from --focus-at's");
}

#[test]
fn bad_ranges_and_chunks_are_rejected_with_one_line() {
    let seq = |extra: &'static [&'static str]| {
        let mut v = vec!["--out", "f.####.png"];
        v.extend_from_slice(extra);
        v
    };
    assert_rejected(&seq(&["--frames", "5-2"]), "before the first");
    assert_rejected(&seq(&["--frames", "1-4:0"]), "step must be at least 1");
    assert_rejected(&seq(&["--frames", "a-4"]), "frames are N, A-B or A-B:STEP");
    assert_rejected(&seq(&["--frames", "-3"]), "`-3`: the first frame");
    assert_rejected(
        &seq(&["--frames", "1-4", "--chunk", "3/3"]),
        "INDEX must be under SIZE",
    );
    assert_rejected(
        &seq(&["--frames", "1-4", "--chunk", "0/0"]),
        "SIZE must be at least 1",
    );
    assert_rejected(&seq(&["--frames", "1-4", "--chunk", "2"]), "INDEX/SIZE");
    assert_rejected(&["--resume"], "--resume is for sequences");
    assert_rejected(&["--chunk", "0/2"], "--chunk is for sequences");
    assert_rejected(&["--frames", "1-4"], "needs the frame number's place");
    assert_rejected(
        &["--out", "f.%04d.png"],
        "names a frame number: give --frames",
    );
}

#[test]
fn bad_keyframes_are_rejected_with_one_line_naming_key_and_frame() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "[[keyframe]]\nframe = 3\nfocus_distnce = 2.0\n",
            "frame 3: `focus_distnce` is not a keyframe key",
        ),
        (
            "[[keyframe]]\nframe = 8\nf_number = -2.0\n",
            "frame 8: `f_number` must be a positive number",
        ),
        (
            "[[keyframe]]\nframe = 9\neye = [0, 1, 5]\n[[keyframe]]\nframe = 2\neye = [0, 1, 6]\n",
            "keyframe at frame 2: out of order",
        ),
        (
            "[[keyframe]]\nframe = 4\nfocus_at = [900, 2]\n",
            "keyframe at frame 4: `focus_at`",
        ),
    ];
    for (keyframes, needle) in cases {
        let scene = pull_scene(dir.path(), keyframes);
        let scene = scene.to_str().unwrap();
        assert_rejected(
            &["--scene", scene, "--frames", "1-9", "--out", "f.####.png"],
            needle,
        );
    }
}
