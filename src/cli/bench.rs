//! `lensray bench`: throughput of a renderer on a named scene, median of several runs.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};

use super::args::DeviceChoice;
use crate::gpu::{BenchOptions, GpuOptions};
use crate::reference::Renderer;
use crate::render::Shading;
use crate::resolve::resolve;
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
    /// cpu: the CPU reference; gpu (or auto): the Vulkan compute pass, timed with timestamps.
    #[arg(long, value_enum, default_value_t = DeviceChoice::Cpu)]
    pub device: DeviceChoice,
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

pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
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
    let resolved = resolve(&settings, &description.scene)?;
    let triangles = description.scene.triangle_count();
    if args.device != DeviceChoice::Cpu {
        let options = BenchOptions {
            gpu: GpuOptions::default(),
            repeats: args.runs as u32,
        };
        let report = crate::gpu::bench(
            &description.scene,
            &resolved.camera,
            &resolved.render,
            &options,
        )
        .context("--device gpu")?;
        println!(
            "bench: {} ({} triangles), {:?}, {} sampler",
            description.source, triangles, args.shading, args.sampler
        );
        print!("{report}");
        return Ok(());
    }
    println!(
        "bench: {} ({} triangles), {}x{} px, {} spp, {:?}, {} sampler, CPU reference on {} threads",
        description.source,
        triangles,
        args.width,
        args.height,
        args.spp,
        args.shading,
        args.sampler,
        rayon::current_num_threads()
    );

    let mut builds = Vec::new();
    let mut renderer = None;
    for _ in 0..args.runs.min(3) {
        let r = Renderer::new(&description.scene);
        builds.push(r.bvh_build_time().as_secs_f64());
        renderer = Some(r);
    }
    let renderer = renderer.expect("at least one build");
    println!(
        "  BVH build: median {:.3} s over {} builds",
        median(builds.clone()),
        builds.len()
    );

    // Warm-up: page in the BVH and spin up the thread pool.
    let _ = renderer.render(&resolved.camera, &resolved.render, &mut |_, _| {});
    let mut rates = Vec::new();
    let mut times = Vec::new();
    for run in 0..args.runs {
        let (_, stats) = renderer.render(&resolved.camera, &resolved.render, &mut |_, _| {});
        let rate = stats.rays_per_second() / 1e6;
        println!(
            "  run {}: {:.3} s, {} rays, {:.2} Mrays/s",
            run + 1,
            stats.elapsed.as_secs_f64(),
            stats.rays,
            rate
        );
        rates.push(rate);
        times.push(stats.elapsed.as_secs_f64());
    }
    let per_core = median(rates.clone()) / rayon::current_num_threads() as f64;
    println!(
        "  median: {:.3} s, {:.2} Mrays/s ({:.2} Mrays/s per thread)",
        median(times),
        median(rates),
        per_core
    );
    Ok(())
}
