//! A sequence's cost beyond its renders: `lensray render --frames` of the focus pull
//! (`assets/spheres/pull.toml`) as a user runs it.
//!
//! - *CPU*: 120 frames at 640x360, 16 spp in one process. The process's wall time against the
//!   sum of its frames' renders (each frame's `--progress lines` line says both), and each
//!   frame's time beyond its render (shot, exposure, tone map, encode, rename): median and
//!   range. The target is at most 1.05x.
//! - *GPU* (`--path software`, where a Vulkan device is): 12 frames in one process against the
//!   same 12 frames as 12 processes of one frame each: start-up is paid once.
//!
//! `cargo bench --bench sequence -- --bench [--frames N] [--json FILE]` measures (the release
//! binary); under `cargo test --all-targets` (no `--bench` argument) a tiny smoke version runs.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use lensray_core::stats::{median, range};

/// One sequence process: its wall time and each rendered frame's (total, render) seconds.
struct SequenceRun {
    wall: f64,
    frames: Vec<(f64, f64)>,
}

/// Runs `lensray render --scene pull.toml ARGS --progress lines` in `dir`, timed by the wall
/// clock from start to exit.
fn render(dir: &Path, args: &[&str]) -> SequenceRun {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/spheres/pull.toml");
    let start = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .arg("render")
        .arg("--scene")
        .arg(&scene)
        .args(args)
        .args(["--progress", "lines"])
        .current_dir(dir)
        .output()
        .expect("run lensray");
    let wall = start.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "lensray render {args:?}: {stderr}");
    SequenceRun {
        wall,
        frames: stderr.lines().filter_map(frame_seconds).collect(),
    }
}

/// The (total, render) seconds of a `--progress lines` frame line: `frame 12 (3 of 10):
/// shot.0012.exr in 0.524 s (rendering 0.497 s)`.
fn frame_seconds(line: &str) -> Option<(f64, f64)> {
    let (_, rest) = line.strip_prefix("frame ")?.rsplit_once(" in ")?;
    let (total, rest) = rest.split_once(" s (rendering ")?;
    let render = rest.strip_suffix(" s)")?;
    Some((total.parse().ok()?, render.parse().ok()?))
}

/// What the command line asks for.
struct Options {
    measure: bool,
    frames: u32,
    json: Option<String>,
}

impl Options {
    fn from_args() -> Self {
        let argv: Vec<String> = std::env::args().collect();
        let measure = argv.iter().any(|a| a == "--bench");
        let value = |name: &str| {
            argv.iter()
                .position(|a| a == name)
                .and_then(|i| argv.get(i + 1))
                .cloned()
        };
        Options {
            measure,
            frames: value("--frames").map_or(if measure { 120 } else { 3 }, |v| {
                v.parse().expect("--frames N")
            }),
            json: value("--json"),
        }
    }
}

/// The CPU sequence's figures.
struct CpuFigures {
    run: SequenceRun,
    /// Each frame's seconds beyond its render.
    beyond: Vec<f64>,
    rendering: f64,
}

fn cpu_sequence(dir: &Path, options: &Options, size: &[&str]) -> CpuFigures {
    let frames = format!("1-{}", options.frames);
    let mut args = vec![
        "--device",
        "cpu",
        "--frames",
        &frames,
        "--out",
        "cpu.####.png",
    ];
    args.extend_from_slice(size);
    let run = render(dir, &args);
    assert_eq!(
        run.frames.len(),
        options.frames as usize,
        "a line per frame"
    );
    let beyond = run.frames.iter().map(|(t, r)| t - r).collect();
    let rendering = run.frames.iter().map(|(_, r)| r).sum();
    CpuFigures {
        run,
        beyond,
        rendering,
    }
}

/// The GPU path's wall time for `count` frames in one process and in `count` processes; `None`
/// where no Vulkan device opens.
fn gpu_sequence(dir: &Path, count: u32, size: &[&str]) -> Option<(f64, f64)> {
    let probe = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args([
            "render", "--path", "software", "--width", "8", "--height", "8",
        ])
        .args(["--spp", "1", "--progress", "none", "--out", "probe.png"])
        .current_dir(dir)
        .output()
        .expect("run lensray");
    if !probe.status.success() {
        println!(
            "GPU: skipped (no Vulkan device: {})",
            String::from_utf8_lossy(&probe.stderr).trim()
        );
        return None;
    }
    let gpu = ["--device", "gpu", "--path", "software"];
    let frames = format!("1-{count}");
    let mut args: Vec<&str> = gpu.to_vec();
    args.extend(["--frames", &frames, "--out", "one.####.png"]);
    args.extend_from_slice(size);
    let one = render(dir, &args).wall;
    let mut each = 0.0;
    for frame in 1..=count {
        let frame = frame.to_string();
        let mut args: Vec<&str> = gpu.to_vec();
        args.extend(["--frames", &frame, "--out", "each.####.png"]);
        args.extend_from_slice(size);
        each += render(dir, &args).wall;
    }
    Some((one, each))
}

fn main() {
    let options = Options::from_args();
    let (cpu_size, gpu_size): (&[&str], &[&str]) = if options.measure {
        (&[], &["--width", "160", "--height", "90"])
    } else {
        (&["--width", "32", "--height", "18", "--spp", "1"], &[])
    };
    let work = tempfile::tempdir().expect("a temporary folder");
    let machine = lensray::machine::describe();
    let cpu = cpu_sequence(work.path(), &options, cpu_size);
    let (lo, hi) = range(&cpu.beyond);
    let ratio = cpu.run.wall / cpu.rendering;
    println!(
        "focus pull (assets/spheres/pull.toml){}, {} frames, CPU path on {} ({} threads):",
        if options.measure {
            " at 640x360, 16 spp"
        } else {
            " (smoke: 32x18, 1 spp)"
        },
        options.frames,
        machine.cpu,
        machine.threads
    );
    println!(
        "  process {:.2} s, rendering {:.2} s: {ratio:.3}x rendering alone (target <= 1.05x)",
        cpu.run.wall, cpu.rendering
    );
    println!(
        "  beyond rendering, per frame: median {:.1} ms (range {:.1}..{:.1}); start-up and exit {:.2} s once",
        median(&cpu.beyond) * 1e3,
        lo * 1e3,
        hi * 1e3,
        cpu.run.wall - cpu.run.frames.iter().map(|(t, _)| t).sum::<f64>()
    );
    // The smoke version runs what needs no Vulkan device.
    let gpu_frames = 12;
    let gpu = options
        .measure
        .then(|| gpu_sequence(work.path(), gpu_frames, gpu_size))
        .flatten();
    if let Some((one, each)) = gpu {
        println!(
            "  GPU --path software, {gpu_frames} frames at 160x90: one process {one:.2} s, one process a frame {each:.2} s ({:.1}x)",
            each / one
        );
    }
    if let Some(file) = &options.json {
        let json = serde_json::json!({
            "command": "cargo bench --bench sequence -- --bench",
            "machine": machine,
            "frames": options.frames,
            "cpu": {
                "process_s": cpu.run.wall,
                "rendering_s": cpu.rendering,
                "ratio": ratio,
                "beyond_per_frame_s": cpu.beyond,
            },
            "gpu_software": gpu.map(|(one, each)| serde_json::json!({
                "frames": gpu_frames, "one_process_s": one, "process_per_frame_s": each
            })),
        });
        std::fs::write(file, serde_json::to_string_pretty(&json).unwrap()).expect("write JSON");
        println!("wrote {file}");
    }
}
