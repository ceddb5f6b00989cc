//! `lensray bench`: throughput of a renderer on a named scene, median of several runs.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::args::DeviceChoice;
use super::backend::Backend;
use crate::gpu::GpuOptions;
use crate::reference::Renderer;
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
    /// cpu: the CPU reference; gpu: the Vulkan passes, timed with timestamps; auto: the GPU
    /// when a device with ray queries exists, else the CPU (as `render`).
    #[arg(long, value_enum, default_value_t = DeviceChoice::Auto)]
    pub device: DeviceChoice,
    /// Use this Vulkan device (index from `lensray info`).
    #[arg(long, value_name = "INDEX")]
    pub gpu: Option<usize>,
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
    let options = GpuOptions {
        validate: false,
        device_index: args.gpu,
        ..Default::default()
    };
    match Backend::open(args.device, &options, &description.scene)? {
        Backend::Gpu(mut gpu) => {
            let report = crate::gpu::bench_renderer(
                &mut gpu,
                &description.scene,
                &camera,
                &render,
                args.runs as u32,
            )?;
            println!(
                "bench: {} ({} triangles), {:?}, {} sampler",
                description.source, triangles, args.shading, args.sampler
            );
            println!("{report}");
            Ok(gpu.close()?)
        }
        Backend::Cpu(_) => {
            println!(
                "bench: {} ({} triangles), {}x{} px, {} spp, {:?}, {} sampler, CPU reference \
                 on {} threads",
                description.source,
                triangles,
                args.width,
                args.height,
                args.spp,
                args.shading,
                args.sampler,
                rayon::current_num_threads()
            );
            bench_cpu(args, &description, &camera, &render);
            Ok(())
        }
    }
}

fn bench_cpu(
    args: &BenchArgs,
    description: &SceneDescription,
    camera: &crate::camera::Camera,
    render: &crate::render::RenderSettings,
) {
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
        median(&builds),
        builds.len()
    );

    // Warm-up: page in the BVH and spin up the thread pool.
    let _ = renderer.render(camera, render, &mut |_, _| {});
    let mut rates = Vec::new();
    let mut times = Vec::new();
    for run in 0..args.runs {
        let (_, stats) = renderer.render(camera, render, &mut |_, _| {});
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
    let per_core = median(&rates) / rayon::current_num_threads() as f64;
    let what = if render.shading.is_aov() {
        // An AOV is one traced ray per pixel centre: say how many images per second that is.
        format!(", {:.1} AOV images/s", 1.0 / median(&times).max(1e-9))
    } else {
        String::new()
    };
    println!(
        "  median: {:.3} s, {:.2} Mrays/s ({:.2} Mrays/s per thread){what}",
        median(&times),
        median(&rates),
        per_core
    );
}
