//! `lensray bench`: throughput of a renderer on a named scene, median of several runs.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::args::PathArgs;
use crate::paths::{self, OpenedPath};
use crate::render::stats::median;
use crate::render::Shading;
use crate::resolve::{resolve, Resolved};
use crate::sampler::SamplerKind;
use crate::scene::file::SceneDescription;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BenchScene {
    /// The built-in default scene.
    Default,
    /// The generated dense scene (>= 1M triangles; generated into assets/generated on first use).
    Dense,
}

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(flatten)]
    pub path: PathArgs,
    /// A named scene...
    #[arg(long, value_enum, default_value_t = BenchScene::Default, conflicts_with = "scene_file")]
    pub scene: BenchScene,
    /// ...or a scene file / mesh.
    #[arg(long, value_name = "FILE")]
    pub scene_file: Option<PathBuf>,
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    #[arg(long, default_value_t = 480)]
    pub height: u32,
    #[arg(long, default_value_t = 16)]
    pub spp: u32,
    #[arg(long, value_enum, default_value_t = Shading::Unlit)]
    pub shading: Shading,
    #[arg(long, value_enum, default_value_t = SamplerKind::default())]
    pub sampler: SamplerKind,
    /// Timed runs (after one warm-up run).
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// Triangles of the dense scene.
    #[arg(long, default_value_t = 1_000_000)]
    pub dense_triangles: usize,
}

fn bench_scene(args: &BenchArgs) -> Result<SceneDescription> {
    if let Some(path) = &args.scene_file {
        return Ok(crate::scene::file::load(path)?);
    }
    Ok(match args.scene {
        BenchScene::Default => crate::scene::builtin::default_scene(),
        BenchScene::Dense => {
            let path = crate::cli::generate::ensure_dense_scene(
                std::path::Path::new("assets/generated"),
                args.dense_triangles,
            )?;
            crate::scene::file::load(&path)?
        }
    })
}

pub fn run(args: &BenchArgs) -> Result<()> {
    anyhow::ensure!(args.runs >= 1, "--runs must be at least 1");
    let description = bench_scene(args)?;
    let mut settings = description.settings.clone();
    settings.image.width = Some(args.width);
    settings.image.height = Some(args.height);
    settings.image.spp = Some(args.spp);
    settings.render.shading = Some(args.shading);
    settings.image.sampler = Some(args.sampler);
    let Resolved { camera, render } = resolve(&settings, &description.scene)?;
    let triangles = description.scene.triangle_count();
    let OpenedPath { mut path, why } =
        paths::open(&args.path.options(), &description.scene, (&camera, &render))?;
    println!(
        "bench: {} ({} triangles), {}x{} px, {} spp, {:?}, {} sampler, path {} ({why}) on {}",
        description.source,
        triangles,
        args.width,
        args.height,
        args.spp,
        args.shading,
        args.sampler,
        path.kind(),
        path.device_name()
    );
    // Warm-up: compiles pipelines, pages in the BVH, spins up the thread pool.
    path.render(&camera, &render, &mut |_, _| {})?;
    let mut rates = Vec::new();
    let mut times = Vec::new();
    for run in 0..args.runs {
        let before = path.report();
        path.render(&camera, &render, &mut |_, _| {})?;
        let report = path.report().since(&before);
        let rate = report.rays_per_second() / 1e6;
        println!(
            "  run {}: {:.3} s, {} rays, {:.2} Mrays/s",
            run + 1,
            report.trace_seconds,
            report.rays,
            rate
        );
        rates.push(rate);
        times.push(report.trace_seconds);
    }
    println!(
        "  median: {:.3} s, {:.2} Mrays/s",
        median(&times),
        median(&rates)
    );
    path.close()
}
