//! The main job's wall time: `lensray render` with no options (the built-in scene, 640x480,
//! 16 spp, `--device auto --path auto`), as a user starts it, against each single path's own
//! wall time (`--path cpu`, `rayquery`, `software`), all in one run, the commands taking turns.
//!
//! - *cold*: the first run on a fresh machine: an empty lensray cache (no calibration, no
//!   pipeline cache) and an empty Mesa shader cache (`MESA_SHADER_CACHE_DIR`), as after a
//!   clean build;
//! - *warm*: later runs with the caches the earlier ones left.
//!
//! Also how stable `auto` is: the path it picks in every warm run.
//!
//! `cargo bench --bench startup -- [--repeat N] [--json FILE]` measures (the release binary);
//! under `cargo test --all-targets` (no `--bench` argument) it runs a tiny smoke version.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use lensray::machine::Machine;
use lensray_core::stats::{median, range};

struct Run {
    seconds: f64,
    path: String,
}

/// Runs `lensray render ARGS` with its caches in `cache` and Mesa's in `mesa`, timed by the wall
/// clock from start to exit.
fn render(args: &[&str], cache: &Path, mesa: &Path, out: &Path) -> Run {
    let start = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .arg("render")
        .args(args)
        .args(["--progress", "none", "--out"])
        .arg(out)
        .env("LENSRAY_CACHE_DIR", cache)
        .env("MESA_SHADER_CACHE_DIR", mesa)
        .output()
        .expect("run lensray");
    let seconds = start.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "lensray render {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let path = stdout
        .split_once(", path ")
        .and_then(|(_, rest)| rest.split(' ').next())
        .unwrap_or("?")
        .to_string();
    Run { seconds, path }
}

/// What the command line asks for.
struct Options {
    /// `--bench` given: measure (else the smoke version).
    measure: bool,
    /// Warm rounds.
    repeat: usize,
    /// Where to write the JSON report, if anywhere.
    json: Option<String>,
}

impl Options {
    /// Reads `--bench`, `--repeat N` and `--json FILE` from the command line.
    fn from_args() -> Self {
        let argv: Vec<String> = std::env::args().collect();
        let measure = argv.iter().any(|a| a == "--bench");
        let value = |name: &str| {
            argv.iter()
                .position(|a| a == name)
                .and_then(|i| argv.get(i + 1))
                .cloned()
        };
        let repeat: usize = value("--repeat").map_or(if measure { 5 } else { 1 }, |v| {
            v.parse().expect("--repeat N")
        });
        Options {
            measure,
            repeat,
            json: value("--json"),
        }
    }
}

/// The commands and where they keep their caches.
struct Setup<'a> {
    /// Image size arguments (none when measuring: the defaults).
    size: &'a [&'a str],
    /// The single paths run against the default command.
    paths: &'a [&'a str],
    work: &'a Path,
    out: PathBuf,
    /// The default command's lensray and Mesa caches.
    cache: PathBuf,
    mesa: PathBuf,
}

impl Setup<'_> {
    /// `lensray render --path PATH` with that path's own caches.
    fn render_single(&self, path: &str) -> Run {
        let (c, m) = (
            self.work.join(format!("c-{path}")),
            self.work.join(format!("m-{path}")),
        );
        let args: Vec<&str> = self.size.iter().copied().chain(["--path", path]).collect();
        render(&args, &c, &m, &self.out)
    }
}

/// Every run's wall time, and the path `auto` picked.
struct Timings {
    cold_default: Run,
    /// Per single path.
    cold_single: Vec<f64>,
    warm_default: Vec<f64>,
    /// The path `auto` picked in each warm run.
    picked: Vec<String>,
    /// Per single path, its warm runs.
    warm_single: Vec<Vec<f64>>,
}

fn main() {
    let options = Options::from_args();
    let measure = options.measure;
    let size: &[&str] = if measure {
        &[]
    } else {
        &["--width", "32", "--height", "24", "--spp", "1"]
    };
    // The smoke version runs what needs no Vulkan device.
    let paths: &[&str] = if measure {
        &["cpu", "rayquery", "software"]
    } else {
        &["cpu"]
    };
    let work = tempfile::tempdir().expect("a temporary folder");
    let setup = Setup {
        size,
        paths,
        work: work.path(),
        out: work.path().join("out.png"),
        cache: work.path().join("cache"),
        mesa: work.path().join("mesa"),
    };
    let timings = run_all(&setup, options.repeat);
    let machine = lensray::machine::describe();
    print_summary(&options, &setup, &timings, &machine);
    if let Some(file) = &options.json {
        let json = serde_json::json!({
            "command": "cargo bench --bench startup",
            "machine": machine,
            "repeat": options.repeat,
            "default": {
                "cold_s": timings.cold_default.seconds,
                "warm_s": timings.warm_default,
                "picked": timings.picked,
            },
            "single": paths.iter().enumerate().map(|(i, p)| (p.to_string(), serde_json::json!({
                "cold_s": timings.cold_single[i], "warm_s": timings.warm_single[i]
            }))).collect::<serde_json::Map<_, _>>(),
        });
        std::fs::write(file, serde_json::to_string_pretty(&json).unwrap()).expect("write JSON");
        println!("wrote {file}");
    }
}

/// The cold runs, then `repeat` warm rounds.
fn run_all(setup: &Setup, repeat: usize) -> Timings {
    // Cold: every cache empty, the default command first, as a new user runs it. Each single
    // path cold too, from its own empty caches.
    let cold_default = render(setup.size, &setup.cache, &setup.mesa, &setup.out);
    let mut cold_single = Vec::new();
    for &path in setup.paths {
        cold_single.push(setup.render_single(path).seconds);
    }

    // Warm: the commands take turns, `repeat` rounds, with the caches the cold runs left.
    let mut warm_default = Vec::new();
    let mut picked = Vec::new();
    let mut warm_single = vec![Vec::new(); setup.paths.len()];
    for _ in 0..repeat {
        let run = render(setup.size, &setup.cache, &setup.mesa, &setup.out);
        warm_default.push(run.seconds);
        picked.push(run.path);
        for (i, path) in setup.paths.iter().enumerate() {
            // Each path with the caches its own cold run left.
            warm_single[i].push(setup.render_single(path).seconds);
        }
    }
    Timings {
        cold_default,
        cold_single,
        warm_default,
        picked,
        warm_single,
    }
}

/// The table of cold and warm times, what `auto` picked, and the ratios against their targets.
fn print_summary(options: &Options, setup: &Setup, timings: &Timings, machine: &Machine) {
    let Timings {
        cold_default,
        cold_single,
        warm_default,
        picked,
        warm_single,
    } = timings;
    println!(
        "lensray render, built-in scene{} on {} ({} threads); medians of {} warm runs:",
        if options.measure {
            ", 640x480, 16 spp"
        } else {
            " (smoke: 32x24, 1 spp)"
        },
        machine.cpu,
        machine.threads,
        options.repeat
    );
    let row = |name: &str, cold: f64, warm: &[f64]| {
        let (lo, hi) = range(warm);
        println!(
            "  {name:<18} cold {cold:6.2} s   warm {:6.2} s (range {lo:.2}..{hi:.2})",
            median(warm)
        );
    };
    row("default (auto)", cold_default.seconds, warm_default);
    for (i, path) in setup.paths.iter().enumerate() {
        row(&format!("--path {path}"), cold_single[i], &warm_single[i]);
    }
    let fastest = warm_single
        .iter()
        .map(|w| median(w))
        .fold(f64::INFINITY, f64::min);
    let stable = picked.iter().filter(|p| **p == picked[0]).count();
    println!(
        "  auto picked {} in {stable} of {} warm runs (cold: {})",
        picked[0],
        picked.len(),
        cold_default.path
    );
    println!(
        "  default warm / fastest single path warm: {:.2}x (target <= 1.15x)",
        median(warm_default) / fastest
    );
    println!(
        "  default cold / default warm: {:.2}x (target <= 2x)",
        cold_default.seconds / median(warm_default)
    );
}
