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

use std::path::Path;
use std::process::Command;
use std::time::Instant;

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

fn main() {
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
    let size: &[&str] = if measure {
        &[]
    } else {
        &["--width", "32", "--height", "24", "--spp", "1"]
    };
    let work = tempfile::tempdir().expect("a temporary folder");
    let out = work.path().join("out.png");
    let (cache, mesa) = (work.path().join("cache"), work.path().join("mesa"));

    // Cold: every cache empty, the default command first, as a new user runs it. Each single
    // path cold too, from its own empty caches.
    let cold_default = render(size, &cache, &mesa, &out);
    // The smoke version runs what needs no Vulkan device.
    let paths: &[&str] = if measure {
        &["cpu", "rayquery", "software"]
    } else {
        &["cpu"]
    };
    let mut cold_single = Vec::new();
    for &path in paths {
        let (c, m) = (
            work.path().join(format!("c-{path}")),
            work.path().join(format!("m-{path}")),
        );
        let args: Vec<&str> = size.iter().copied().chain(["--path", path]).collect();
        cold_single.push(render(&args, &c, &m, &out).seconds);
    }

    // Warm: the commands take turns, `repeat` rounds, with the caches the cold runs left.
    let mut warm_default = Vec::new();
    let mut picked = Vec::new();
    let mut warm_single = vec![Vec::new(); paths.len()];
    for _ in 0..repeat {
        let run = render(size, &cache, &mesa, &out);
        warm_default.push(run.seconds);
        picked.push(run.path);
        for (i, path) in paths.iter().enumerate() {
            // Each path with the caches its own cold run left.
            let (c, m) = (
                work.path().join(format!("c-{path}")),
                work.path().join(format!("m-{path}")),
            );
            let args: Vec<&str> = size.iter().copied().chain(["--path", path]).collect();
            warm_single[i].push(render(&args, &c, &m, &out).seconds);
        }
    }

    let machine = lensray::bench::machine::describe();
    println!(
        "lensray render, built-in scene{} on {} ({} threads); medians of {repeat} warm runs:",
        if measure {
            ", 640x480, 16 spp"
        } else {
            " (smoke: 32x24, 1 spp)"
        },
        machine.cpu,
        machine.threads
    );
    let row = |name: &str, cold: f64, warm: &[f64]| {
        let (lo, hi) = range(warm);
        println!(
            "  {name:<18} cold {cold:6.2} s   warm {:6.2} s (range {lo:.2}..{hi:.2})",
            median(warm)
        );
    };
    row("default (auto)", cold_default.seconds, &warm_default);
    for (i, path) in paths.iter().enumerate() {
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
        median(&warm_default) / fastest
    );
    println!(
        "  default cold / default warm: {:.2}x (target <= 2x)",
        cold_default.seconds / median(&warm_default)
    );
    if let Some(file) = value("--json") {
        let json = serde_json::json!({
            "command": "cargo bench --bench startup",
            "machine": machine,
            "repeat": repeat,
            "default": { "cold_s": cold_default.seconds, "warm_s": warm_default, "picked": picked },
            "single": paths.iter().enumerate().map(|(i, p)| (p.to_string(), serde_json::json!({
                "cold_s": cold_single[i], "warm_s": warm_single[i]
            }))).collect::<serde_json::Map<_, _>>(),
        });
        std::fs::write(&file, serde_json::to_string_pretty(&json).unwrap()).expect("write JSON");
        println!("wrote {file}");
    }
}
