//! `--video`: ffmpeg encodes a sequence's frames as H.264 MP4 (checked with ffprobe), showing
//! what the PNG frames show (decoded frames against them), in order, with frames `--resume`
//! skips read back; a missing or failing ffmpeg is one line and leaves no video behind.
//! ffmpeg and ffprobe come with `scripts/setup.sh`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use super::frames::{pull_scene, PULL};
use crate::{assert_rejected, render_args, stderr};

/// What H.264 may change, as a mean over a frame of |decoded - PNG| in 8-bit levels. The
/// codec is lossy twice: yuv420p keeps colour at half resolution, and libx264 at crf 18
/// quantizes what is left. On these 4-spp frames of 64x48, whose noise is most of their detail,
/// that was 1.8-2.6 levels, and a neighbouring frame (its own noise and focus) is 4.2 levels or
/// more away.
const MEAN_TOLERANCE: f64 = 3.0;

/// The decoder's colour: interpolated between the 2x2 blocks yuv420p keeps it in, as players
/// show it (ffmpeg's default takes each block's value as it is).
const DECODE_SCALE: &str = "scale=flags=bicubic+accurate_rnd+full_chroma_int";

fn run(args: &[&str], dir: &Path, path_env: Option<&str>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_lensray"));
    command.args(args).current_dir(dir);
    if let Some(path) = path_env {
        command.env("PATH", path);
    }
    command.output().expect("run lensray")
}

/// Renders the pull scene with `extra`; the command must succeed. Returns stdout.
fn render(dir: &Path, extra: &[&str]) -> String {
    let scene = pull_scene(dir, PULL);
    let mut args = vec!["--scene", scene.to_str().unwrap()];
    args.extend_from_slice(extra);
    let out = run(&render_args(&args), dir, None);
    assert!(out.status.success(), "{extra:?} failed: {}", stderr(&out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `tool` (ffprobe, ffmpeg) with `args` in `dir`; it must succeed. Returns stdout.
fn tool(tool: &str, args: &[&str], dir: &Path) -> String {
    let out = Command::new(tool)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("{tool} does not run ({e}): scripts/setup.sh installs it"));
    assert!(out.status.success(), "{tool} {args:?}: {}", stderr(&out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// ffprobe's view of the video's stream: codec, pixel format, size, rate and frames decoded.
fn probe(dir: &Path, video: &str) -> String {
    let entries = "stream=codec_name,pix_fmt,width,height,r_frame_rate,nb_read_frames";
    let args = [
        "-v",
        "error",
        "-count_frames",
        "-select_streams",
        "v:0",
        "-show_entries",
        entries,
        "-of",
        "default=noprint_wrappers=1",
        video,
    ];
    tool("ffprobe", &args, dir)
}

/// Every frame of the video, decoded to PNG by ffmpeg, in order.
fn decoded_frames(dir: &Path, video: &str) -> Vec<image::RgbImage> {
    let out = dir.join("decoded");
    fs::create_dir(&out).unwrap();
    tool(
        "ffmpeg",
        &[
            "-v",
            "error",
            "-i",
            video,
            "-vf",
            DECODE_SCALE,
            "decoded/%03d.png",
        ],
        dir,
    );
    let mut files: Vec<PathBuf> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files.iter().map(|f| open_rgb(f)).collect()
}

fn open_rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8()
}

/// Mean |a - b| over `b`'s pixels and channels, in 8-bit levels (`a` may be larger: padding).
fn mean_diff(a: &image::RgbImage, b: &image::RgbImage) -> f64 {
    let mut sum = 0u64;
    for (x, y, p) in b.enumerate_pixels() {
        let q = a.get_pixel(x, y);
        sum += (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>();
    }
    sum as f64 / (3 * b.width() * b.height()) as f64
}

/// Each decoded frame is within [`MEAN_TOLERANCE`] of its PNG and nearer it than any other
/// frame's PNG (so the frames are in order).
fn assert_shows(decoded: &[image::RgbImage], pngs: &[image::RgbImage]) {
    assert_eq!(decoded.len(), pngs.len(), "frames decoded");
    for (i, frame) in decoded.iter().enumerate() {
        let diffs: Vec<f64> = pngs.iter().map(|png| mean_diff(frame, png)).collect();
        let own = diffs[i];
        println!(
            "decoded frame {}: mean |diff| against each PNG {diffs:.2?}",
            i + 1
        );
        assert!(
            own < MEAN_TOLERANCE,
            "frame {}: mean |decoded - PNG| {own:.3} levels, tolerance {MEAN_TOLERANCE}",
            i + 1
        );
        let nearest = (0..diffs.len()).min_by(|&a, &b| diffs[a].total_cmp(&diffs[b]));
        assert_eq!(
            nearest,
            Some(i),
            "frame {} is out of order: {diffs:?}",
            i + 1
        );
    }
}

#[test]
fn the_video_is_h264_at_the_fps_and_shows_the_png_frames_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let stdout = render(
        d,
        &[
            "--width",
            "64",
            "--height",
            "48",
            "--spp",
            "4",
            "--frames",
            "1-6",
            "--fps",
            "12",
            "--out",
            "f.####.png",
            "--video",
            "pull.mp4",
        ],
    );
    assert!(
        stdout.contains("video pull.mp4: 6 frames at 12 fps, 64x48 px"),
        "{stdout}"
    );
    let probed = probe(d, "pull.mp4");
    for field in [
        "codec_name=h264",
        "pix_fmt=yuv420p",
        "width=64",
        "height=48",
        "r_frame_rate=12/1",
        "nb_read_frames=6",
    ] {
        assert!(probed.contains(field), "ffprobe lacks {field}: {probed}");
    }
    let pngs: Vec<_> = (1..=6)
        .map(|f| open_rgb(&d.join(format!("f.{f:04}.png"))))
        .collect();
    assert_shows(&decoded_frames(d, "pull.mp4"), &pngs);
    let names: Vec<String> = fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(names.is_empty(), "temporary files left: {names:?}");
}

/// An odd size (63x47) padded to 64x48; EXR frames exposed into the file (`--expose-exr`), the
/// first three already there and read back under `--resume`: the video shows all six as PNGs
/// of the same frames show them, and the padding repeats the last column and row.
#[test]
fn resumed_exr_frames_of_an_odd_size_are_all_in_the_video() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let common = [
        "--width",
        "63",
        "--height",
        "47",
        "--spp",
        "4",
        "--exposure",
        "0.7",
        "--expose-exr",
        // The frames `MEAN_TOLERANCE` was measured on: PBR Neutral's deeper shadows give the
        // codec more contrast in the noise to lose (3.3 levels on frame 2).
        "--tonemap",
        "agx",
    ];
    let with = |extra: &[&'static str]| [&common[..], extra].concat();
    render(d, &with(&["--frames", "1-3", "--out", "e.####.exr"]));
    let stdout = render(
        d,
        &with(&[
            "--frames",
            "1-6",
            "--out",
            "e.####.exr",
            "--resume",
            "--video",
            "v.mp4",
        ]),
    );
    assert!(
        stdout.contains("(3 rendered, 3 complete and skipped)"),
        "{stdout}"
    );
    assert!(
        stdout.contains("6 frames at 24 fps, 64x48 px (63x47 padded to even sides)"),
        "{stdout}"
    );
    let probed = probe(d, "v.mp4");
    for field in [
        "width=64",
        "height=48",
        "r_frame_rate=24/1",
        "nb_read_frames=6",
    ] {
        assert!(probed.contains(field), "ffprobe lacks {field}: {probed}");
    }
    render(d, &with(&["--frames", "1-6", "--out", "p.####.png"]));
    let pngs: Vec<_> = (1..=6)
        .map(|f| open_rgb(&d.join(format!("p.{f:04}.png"))))
        .collect();
    let decoded = decoded_frames(d, "v.mp4");
    assert_shows(&decoded, &pngs);
    // The padding column against the last one, and the padding row against the last one.
    for frame in &decoded {
        let column = |x| image::imageops::crop_imm(frame, x, 0, 1, 47).to_image();
        let row = |y| image::imageops::crop_imm(frame, 0, y, 63, 1).to_image();
        let (dc, dr) = (
            mean_diff(&column(63), &column(62)),
            mean_diff(&row(47), &row(46)),
        );
        println!("padding against the last column {dc:.2}, row {dr:.2} levels");
        assert!(dc < MEAN_TOLERANCE && dr < MEAN_TOLERANCE, "{dc} {dr}");
    }
}

/// Files in `dir` but the scene's.
fn outputs(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        // The scene file and its mesh are the test's own.
        .filter(|n| ![".toml", ".obj", ".mtl"].iter().any(|e| n.ends_with(e)))
        .collect()
}

/// Without ffmpeg on PATH: one line saying so and how to install it, before any rendering.
#[test]
fn no_ffmpeg_is_one_line_and_no_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = pull_scene(d, PULL);
    let empty = tempfile::tempdir().unwrap();
    let args = render_args(&[
        "--scene",
        scene.to_str().unwrap(),
        "--frames",
        "1-6",
        "--out",
        "f.####.png",
        "--video",
        "v.mp4",
    ]);
    let out = run(&args, d, empty.path().to_str());
    let err = stderr(&out);
    assert!(!out.status.success(), "accepted without ffmpeg: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("ffmpeg, which is not on PATH") && err.contains("sudo apt-get install ffmpeg"),
        "{err}"
    );
    assert!(outputs(d).is_empty(), "files left: {:?}", outputs(d));
}

/// An ffmpeg that fails (right away, or after reading every frame) after writing part of its
/// file: one line with its last stderr line, a non-zero exit, no video and no temporary file.
#[test]
fn a_failing_ffmpeg_is_one_line_and_leaves_no_video() {
    for read in ["", "cat >/dev/null"] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let scene = pull_scene(d, PULL);
        let bin = tempfile::tempdir().unwrap();
        let fake = bin.path().join("ffmpeg");
        let script = format!(
            "#!/bin/sh\ncase \"$*\" in *encoder=libx264*) echo 'Encoder libx264'; exit 0;; esac\n\
             for last; do :; done\necho partial > \"$last\"\n{read}\n\
             echo 'first line' >&2\necho 'fake ffmpeg: No space left on device' >&2\nexit 1\n"
        );
        fs::write(&fake, script).unwrap();
        let mode = std::os::unix::fs::PermissionsExt::from_mode(0o755);
        fs::set_permissions(&fake, mode).unwrap();
        let path = format!(
            "{}:{}",
            bin.path().display(),
            std::env::var("PATH").unwrap()
        );
        let args = render_args(&[
            "--scene",
            scene.to_str().unwrap(),
            "--frames",
            "1-3",
            "--video",
            "v.mp4",
        ]);
        let out = run(&args, d, Some(&path));
        let err = stderr(&out);
        assert!(!out.status.success(), "{read:?}: accepted: {err}");
        assert_eq!(err.lines().count(), 1, "{read:?}: {err}");
        assert!(
            err.contains("--video v.mp4: ffmpeg failed: fake ffmpeg: No space left on device"),
            "{read:?}: {err}"
        );
        assert!(
            outputs(d).is_empty(),
            "{read:?}: files left: {:?}",
            outputs(d)
        );
    }
}

#[test]
fn bad_video_options_are_one_line() {
    fn seq<'a>(extra: &[&'a str]) -> Vec<&'a str> {
        [&["--frames", "1-4", "--out", "f.####.png"], extra].concat()
    }
    assert_rejected(&["--video", "v.mp4"], "--video is for sequences");
    assert_rejected(
        &seq(&["--chunk", "0/2", "--video", "v.mp4"]),
        "not a --chunk",
    );
    assert_rejected(
        &["--frames", "1-4", "--resume", "--video", "v.mp4"],
        "give --out with the frame number's place",
    );
    assert_rejected(&seq(&["--video", "v.mov"]), "name it .mp4");
    for fps in ["0", "-2", "NaN", "1e9"] {
        assert_rejected(
            &seq(&["--video", "v.mp4", "--fps", fps]),
            "--fps: fps must be a positive number up to 1000",
        );
        // A sequence of frames and a still name it too.
        assert_rejected(
            &seq(&["--fps", fps]),
            "--fps: fps must be a positive number up to 1000",
        );
        assert_rejected(&["--fps", fps], "fps must be a positive number up to 1000");
    }
}
