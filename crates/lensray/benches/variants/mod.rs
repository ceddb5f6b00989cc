//! What the `order` and `textures` benches share: variants of one scene, each loaded into its own
//! instance of every path, timed in turns, and their images compared.
//!
//! Every (variant, path) pair is opened as `lensray render --path P` opens it (`paths::open`),
//! renders once to warm up (pipelines compiled, BVH paged in, thread pool started), then
//! `--repeat` rounds each render every pair once, the variants of a path one after the other
//! in an order that turns by one each round, so that a slow phase of the shared machine falls
//! on every variant alike and no variant always runs first. Times are those `lensray bench`
//! reports (`bench::runs`): GPU timestamps around the trace dispatches on the GPU paths, the
//! host clock around the traversal on the CPU.
#![allow(
    dead_code,
    reason = "each bench includes this module and uses part of it"
)]

use std::fmt::Write as _;

use anyhow::{Context, Result};
use clap::ValueEnum;
use serde::Serialize;

use lensray::bench::runs::{timed_render, Spread};
use lensray::machine::{self, Machine};
use lensray::paths::{self, PathKind, PathOptions, RenderPath};
use lensray_core::film::compare::rmse;
use lensray_core::film::Image;
use lensray_core::scene::{Scene, SceneDescription};
use lensray_core::settings::{ImageSettings, RenderStyle, Settings, Shading, Shot};
use lensray_core::stats::median;
use lensray_vulkan::GpuOptions;

/// The command line: `--bench` (measure, else the smoke version), `--repeat N`, `--width W`,
/// `--height H`, `--spp N`, `--paths a,b`, `--json FILE`, and what each bench reads itself.
pub struct Args {
    pub measure: bool,
    pub repeat: usize,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub paths: Vec<PathKind>,
    pub json: Option<String>,
    argv: Vec<String>,
}

impl Args {
    /// The smoke version runs the CPU path alone on a tiny image: it needs no Vulkan device.
    pub fn from_env() -> Self {
        let argv: Vec<String> = std::env::args().collect();
        let measure = argv.iter().any(|a| a == "--bench");
        let mut args = Args {
            measure,
            repeat: 1,
            width: 32,
            height: 24,
            spp: 1,
            paths: vec![PathKind::Cpu],
            json: None,
            argv,
        };
        let number = |a: &Args, name: &str, default: usize| {
            a.value(name).map_or(default, |v| {
                v.parse()
                    .unwrap_or_else(|_| panic!("{name} takes a number"))
            })
        };
        if measure {
            args.repeat = number(&args, "--repeat", 7);
            args.width = number(&args, "--width", 160) as u32;
            args.height = number(&args, "--height", 120) as u32;
            args.spp = number(&args, "--spp", 4) as u32;
            args.paths = args
                .value("--paths")
                .unwrap_or("cpu,software,rayquery")
                .split(',')
                .map(|p| PathKind::from_str(p, true).unwrap_or_else(|e| panic!("--paths: {e}")))
                .collect();
            args.json = args.value("--json").map(str::to_string);
        }
        args
    }

    /// The value after `name`, if given.
    pub fn value(&self, name: &str) -> Option<&str> {
        let i = self.argv.iter().position(|a| a == name)?;
        self.argv.get(i + 1).map(String::as_str)
    }

    pub fn flag(&self, name: &str) -> bool {
        self.argv.iter().any(|a| a == name)
    }

    /// The shot of `description` (its own camera and lights, lit as `lensray render` lights it)
    /// at the bench's size and spp, lit shading; and its scene, lit.
    pub fn shot(&self, description: &SceneDescription) -> (Shot, Scene) {
        let over = Settings {
            image: ImageSettings {
                width: Some(self.width),
                height: Some(self.height),
                spp: Some(self.spp),
                seed: Some(1),
                sampler: None,
                fps: None,
            },
            render: RenderStyle {
                shading: Some(Shading::Lit),
                background: None,
                environment: None,
                environment_rotation: None,
                environment_intensity: None,
                bounces: None,
                noise_threshold: None,
            },
            ..Default::default()
        };
        let settings = description.settings.clone().overridden_by(&over);
        let mut scene = description.scene.clone();
        lensray_core::settings::light_scene(&settings, &mut scene).expect("the scene's lights");
        let shot = lensray_core::settings::shot(&settings, &scene).expect("resolve the settings");
        (shot, scene)
    }
}

/// One version of the scene under test.
pub struct Variant {
    pub name: String,
    pub scene: Scene,
}

/// One path's renders of one variant.
#[derive(Serialize)]
pub struct Timed {
    pub variant: String,
    pub path: PathKind,
    /// Trace time of each run, and their median and extremes.
    pub runs: Vec<f64>,
    pub trace_seconds: Spread,
    /// The host clock around each whole render call.
    pub wall_seconds: Spread,
    pub rays: u64,
    /// The acceleration structure's build when the path loaded the variant.
    pub build_seconds: f64,
    /// This path's median time over its median time for the first variant.
    pub vs_first: f64,
    /// Against the first variant's image on the same path.
    pub difference: Difference,
    #[serde(skip)]
    pub image: Image,
}

/// How two images of one shot differ.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Difference {
    /// Pixels whose value differs in any channel.
    pub pixels: usize,
    /// The largest difference of one channel (linear).
    pub max_abs: f32,
    pub rmse: f64,
}

impl Difference {
    pub fn of(a: &Image, b: &Image) -> Self {
        Self {
            pixels: a
                .pixels
                .iter()
                .zip(&b.pixels)
                .filter(|(p, q)| p != q)
                .count(),
            max_abs: a
                .pixels
                .iter()
                .zip(&b.pixels)
                .map(|(p, q)| (*p - *q).abs().max_element())
                .fold(0.0, f32::max),
            rmse: rmse(a, b),
        }
    }
}

/// Opens every variant on every path in `args.paths`, warms each up and times `args.repeat`
/// rounds of `shot` in turns; per path, its variants in the order given.
pub fn measure(variants: &[Variant], shot: &Shot, args: &Args) -> Result<Vec<Vec<Timed>>> {
    let mut opened: Vec<Vec<Box<dyn RenderPath>>> = Vec::new();
    for &kind in &args.paths {
        let options = PathOptions {
            path: kind.into(),
            device: kind.device().into(),
            gpu: GpuOptions::default(),
        };
        let mut row = Vec::new();
        for v in variants {
            let mut path = paths::open(&options, &v.scene, shot)
                .with_context(|| format!("--path {kind}, {}", v.name))?
                .path;
            path.render(shot, &mut |_, _| {})?;
            row.push(path);
        }
        opened.push(row);
    }
    let n = variants.len();
    let mut runs = vec![vec![Vec::new(); n]; args.paths.len()];
    let mut images: Vec<Vec<Option<Image>>> = vec![vec![None; n]; args.paths.len()];
    for round in 0..args.repeat {
        for ((row, runs), images) in opened.iter_mut().zip(&mut runs).zip(&mut images) {
            for i in (0..n).map(|k| (k + round) % n) {
                let (run, image) = timed_render(row[i].as_mut(), shot, None)?;
                runs[i].push(run);
                images[i] = Some(image);
            }
        }
    }
    let mut out = Vec::new();
    for ((row, runs), images) in opened.into_iter().zip(runs).zip(images) {
        let mut timed: Vec<Timed> = Vec::new();
        for ((path, runs), (v, image)) in row.iter().zip(runs).zip(variants.iter().zip(images)) {
            let trace: Vec<f64> = runs.iter().map(|r| r.trace_seconds).collect();
            let wall: Vec<f64> = runs.iter().map(|r| r.wall_seconds).collect();
            let image = image.expect("at least one round");
            let trace_seconds = Spread::of(&trace);
            let (vs_first, difference) = match timed.first() {
                Some(first) => (
                    trace_seconds.median / first.trace_seconds.median.max(1e-12),
                    Difference::of(&image, &first.image),
                ),
                None => (1.0, Difference::default()),
            };
            timed.push(Timed {
                variant: v.name.clone(),
                path: path.kind(),
                trace_seconds,
                wall_seconds: Spread::of(&wall),
                rays: runs.last().map_or(0, |r| r.rays),
                build_seconds: path.report().build_seconds,
                runs: trace,
                vs_first,
                difference,
                image,
            });
        }
        for path in row {
            path.close()?;
        }
        out.push(timed);
    }
    Ok(out)
}

/// Seconds in ms with three significant digits.
fn ms(seconds: f64) -> String {
    let ms = seconds * 1e3;
    match ms {
        m if m >= 100.0 => format!("{m:.0} ms"),
        m if m >= 10.0 => format!("{m:.1} ms"),
        m => format!("{m:.2} ms"),
    }
}

/// The table of one measurement: per path and variant the median (min - max), the ratio to the
/// first variant and how its image differs from the first variant's; then, per path, the ratio
/// of the medians of the variants `ratio` names (the first over the second).
pub fn table(
    title: &str,
    results: &SceneResults,
    ratio: Option<(&str, &str)>,
    args: &Args,
) -> String {
    let mut out = String::new();
    let m = machine::describe();
    let _ = writeln!(
        out,
        "{title}: {} ({} triangles), {}x{}, {} spp, lit, median of {} rounds after a warm-up\nmachine: {}, {} threads, {} ({})",
        results.scene,
        results.triangles,
        args.width,
        args.height,
        args.spp,
        args.repeat,
        m.cpu,
        m.threads,
        m.os,
        m.arch
    );
    for timed in &results.paths {
        for (i, t) in timed.iter().enumerate() {
            let (lo, hi) = (t.trace_seconds.min, t.trace_seconds.max);
            let d = &t.difference;
            let image = match (i, d.pixels) {
                (0, _) => "(the image the others are compared with)".to_string(),
                (_, 0) => "image identical".to_string(),
                (_, n) => format!(
                    "{n} of {} pixels differ (max {:.3}, RMSE {:.2e})",
                    t.image.pixels.len(),
                    d.max_abs,
                    d.rmse
                ),
            };
            let _ = writeln!(
                out,
                "  {:<9} {:<10} {:>9} ({} - {})  {:>5.2}x  build {:>9}  {image}",
                t.path.name(),
                t.variant,
                ms(t.trace_seconds.median),
                ms(lo),
                ms(hi),
                t.vs_first,
                ms(t.build_seconds),
            );
        }
    }
    if let Some((a, b)) = ratio {
        let ratios: Vec<String> = results
            .paths
            .iter()
            .filter_map(|timed| {
                let find = |name: &str| timed.iter().find(|t| t.variant == name);
                let (a, b) = (find(a)?, find(b)?);
                let of_medians = a.trace_seconds.median / b.trace_seconds.median;
                let per_round: Vec<f64> = a.runs.iter().zip(&b.runs).map(|(x, y)| x / y).collect();
                Some(format!(
                    "{} {of_medians:.2}x ({:.2}x)",
                    a.path.name(),
                    median(&per_round)
                ))
            })
            .collect();
        let _ = writeln!(
            out,
            "  {a} / {b}, ratio of the medians (median of each round's ratio): {}",
            ratios.join(", ")
        );
    }
    out
}

/// One scene's measurement.
#[derive(Serialize)]
pub struct SceneResults {
    pub scene: String,
    pub triangles: usize,
    /// Per path, its variants in order.
    pub paths: Vec<Vec<Timed>>,
}

/// The JSON of a bench: the machine, the settings and every measurement.
#[derive(Serialize)]
pub struct Report<'a> {
    pub bench: &'a str,
    pub machine: Machine,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub repeat: usize,
    pub scenes: &'a [SceneResults],
}

/// Writes the report of `scenes` to `args.json`, if given.
pub fn write_json(bench: &str, args: &Args, scenes: &[SceneResults]) -> Result<()> {
    let Some(file) = &args.json else {
        return Ok(());
    };
    let report = Report {
        bench,
        machine: machine::describe(),
        width: args.width,
        height: args.height,
        spp: args.spp,
        repeat: args.repeat,
        scenes,
    };
    std::fs::write(file, serde_json::to_string_pretty(&report)? + "\n")
        .with_context(|| format!("cannot write {file}"))?;
    eprintln!("wrote {file}");
    Ok(())
}
