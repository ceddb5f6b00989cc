//! Rays per second of the compute pass's two traversals (ray queries; the software BVH
//! traversal) on the built-in default scene and on the dense benchmark scene (`lensray generate
//! dense`, ~1M triangles), measured in one run: each traversal is warmed up, then timed
//! `--repeat` times with GPU timestamps; the table gives medians and the software/rayquery ratio.
//! `--bvh-sweep` instead times the software traversal on the default scene (`--dense`: the dense
//! one) for several BVH builds (leaf size, collapse cost, build quality), also interleaved.
//!
//! `cargo bench --bench traversal -- [--repeat N] [--triangles N] [--width W] [--height H]
//! [--spp N] [--unlit] [--separate] [--bvh-sweep [--dense]]`
//! measures; under `cargo test --all-targets` (no `--bench` argument) it only runs a tiny smoke
//! version. Without a Vulkan device it fails, unless LENSRAY_SKIP_GPU_TESTS=1.

#[path = "../../lensray-vulkan/tests/support/mod.rs"]
mod gpu_support;

use lensray_core::scene::{Scene, SceneDescription};
use lensray_core::settings::{Shading, Shot};
use lensray_core::stats::{median, range};
use lensray_vulkan::{bench_renderer, BvhParams, GpuError, GpuOptions, GpuRenderer, Traversal};

struct Args {
    repeat: u32,
    triangles: usize,
    width: u32,
    height: u32,
    spp: u32,
    bvh_sweep: bool,
    /// Open the device once per traversal, for that traversal alone.
    separate: bool,
    /// Unlit (camera rays only) instead of lit (camera + shadow rays).
    unlit: bool,
    /// The BVH sweep on the dense scene instead of the default one.
    dense_sweep: bool,
}

fn args() -> Args {
    let argv: Vec<String> = std::env::args().collect();
    let value = |name: &str| {
        argv.iter()
            .position(|a| a == name)
            .and_then(|i| argv.get(i + 1))
            .map(|v| v.parse::<usize>().expect("a number"))
    };
    let measure = argv.iter().any(|a| a == "--bench");
    Args {
        repeat: value("--repeat").unwrap_or(if measure { 5 } else { 1 }) as u32,
        triangles: value("--triangles").unwrap_or(if measure { 1_000_000 } else { 20_000 }),
        width: value("--width").unwrap_or(if measure { 640 } else { 32 }) as u32,
        height: value("--height").unwrap_or(if measure { 480 } else { 24 }) as u32,
        spp: value("--spp").unwrap_or(if measure { 4 } else { 1 }) as u32,
        bvh_sweep: argv.iter().any(|a| a == "--bvh-sweep"),
        separate: argv.iter().any(|a| a == "--separate"),
        unlit: argv.iter().any(|a| a == "--unlit"),
        dense_sweep: argv.iter().any(|a| a == "--dense"),
    }
}

/// The scene's own camera and settings at the bench's size, lit unless `--unlit`.
fn shot(desc: &SceneDescription, a: &Args) -> Shot {
    use lensray_core::settings::{ImageSettings, RenderStyle, Settings};
    let over = Settings {
        image: ImageSettings {
            width: Some(a.width),
            height: Some(a.height),
            spp: Some(a.spp),
            seed: Some(1),
            sampler: None,
            fps: None,
        },
        render: RenderStyle {
            shading: Some(if a.unlit {
                Shading::Unlit
            } else {
                Shading::Lit
            }),
            background: None,
            environment: None,
            environment_rotation: None,
            environment_intensity: None,
            bounces: None,
            noise_threshold: None,
        },
        ..Default::default()
    };
    lensray_core::settings::shot(&desc.settings.clone().overridden_by(&over), &desc.scene)
        .expect("resolve settings")
}

/// One configuration to time: a renderer with its scene loaded and its traversal set.
struct Contender {
    label: String,
    gpu: GpuRenderer,
    traversal: Traversal,
    /// GPU ms and rays of each timed run.
    runs_ms: Vec<f64>,
    rays: u64,
}

impl Contender {
    fn new(label: String, mut gpu: GpuRenderer, traversal: Traversal) -> Result<Self, GpuError> {
        gpu.set_traversal(traversal)?;
        Ok(Self {
            label,
            gpu,
            traversal,
            runs_ms: Vec::new(),
            rays: 0,
        })
    }

    fn rays_per_second(&self) -> f64 {
        self.rays as f64 / (median(&self.runs_ms) * 1e-3).max(1e-12)
    }
}

/// Warms each contender up (its pipeline's first dispatch is timed apart), then times `repeat`
/// rounds of `shot`, one run of each contender per round, so that other load on the machine
/// falls on all of them alike; prints the medians.
fn time_interleaved(
    contenders: &mut [Contender],
    scene: &Scene,
    shot: &Shot,
    repeat: u32,
) -> Result<(), GpuError> {
    for c in contenders.iter_mut() {
        c.gpu.set_traversal(c.traversal)?;
        bench_renderer(&mut c.gpu, scene, shot, 1)?;
    }
    for _ in 0..repeat.max(1) {
        for c in contenders.iter_mut() {
            c.gpu.set_traversal(c.traversal)?;
            let before = c.gpu.timings();
            c.gpu.render(shot, &mut |_, _| {})?;
            let after = c.gpu.timings();
            c.runs_ms.push(after.trace_gpu_ms - before.trace_gpu_ms);
            c.rays = after.rays_traced - before.rays_traced;
        }
    }
    for c in contenders.iter() {
        let (lo, hi) = range(&c.runs_ms);
        println!(
            "  {:<40} median {:.3} Mrays/s ({} runs, median {:.0} ms GPU, range {lo:.0}..{hi:.0})",
            c.label,
            c.rays_per_second() * 1e-6,
            c.runs_ms.len(),
            median(&c.runs_ms),
        );
    }
    Ok(())
}

fn compare_traversals(name: &str, desc: &SceneDescription, a: &Args) -> Result<(), GpuError> {
    let shot = shot(desc, a);
    let mut gpu = GpuRenderer::new(&GpuOptions::default())?;
    gpu.load_scene(&desc.scene)?;
    let t = gpu.timings();
    println!(
        "{name}: {} triangles, {}x{} at {} spp {:?}, {} | BVH {:.1} MiB (host build {:.0} ms), \
         BLAS+TLAS {:.1} MiB",
        desc.scene.triangle_count(),
        a.width,
        a.height,
        a.spp,
        shot.render.shading,
        gpu.device_name(),
        t.bvh_bytes as f64 / (1 << 20) as f64,
        t.bvh_build_ms,
        t.accel_bytes as f64 / (1 << 20) as f64,
    );
    let mut contenders = Vec::new();
    for traversal in gpu.traversals() {
        let renderer = if a.separate {
            // A device opened for this traversal alone.
            let mut alone = GpuRenderer::new(&GpuOptions {
                traversal: Some(traversal),
                ..Default::default()
            })?;
            alone.load_scene(&desc.scene)?;
            alone
        } else {
            // Both traversals on one device: a second renderer like the first.
            let mut same = GpuRenderer::new(&GpuOptions::default())?;
            same.load_scene(&desc.scene)?;
            same
        };
        contenders.push(Contender::new(traversal.to_string(), renderer, traversal)?);
    }
    time_interleaved(&mut contenders, &desc.scene, &shot, a.repeat)?;
    if let [rq, sw] = &contenders[..] {
        println!(
            "  software / rayquery: {:.2}x",
            sw.rays_per_second() / rq.rays_per_second()
        );
    }
    for c in contenders {
        c.gpu.close()?;
    }
    gpu.close()
}

fn bvh_sweep(desc: &SceneDescription, a: &Args) -> Result<(), GpuError> {
    let shot = shot(desc, a);
    println!(
        "BVH builds ({} triangles), software traversal, {}x{} at {} spp {:?}:",
        desc.scene.triangle_count(),
        a.width,
        a.height,
        a.spp,
        shot.render.shading
    );
    let choices = [(1, true), (2, true), (3, true), (3, false)];
    let mut contenders = Vec::new();
    for (max_leaf_triangles, medium_build) in choices {
        let mut gpu = GpuRenderer::new(&GpuOptions {
            traversal: Some(Traversal::Software),
            ..Default::default()
        })?;
        gpu.set_bvh_params(BvhParams {
            max_leaf_triangles,
            medium_build,
        });
        gpu.load_scene(&desc.scene)?;
        let label = format!(
            "leaf <= {max_leaf_triangles}, {} build, {:.2} MiB",
            if medium_build { "medium" } else { "fast" },
            gpu.timings().bvh_bytes as f64 / (1 << 20) as f64
        );
        contenders.push(Contender::new(label, gpu, Traversal::Software)?);
    }
    time_interleaved(&mut contenders, &desc.scene, &shot, a.repeat)?;
    for c in contenders {
        c.gpu.close()?;
    }
    Ok(())
}

/// `d` lit as its settings say, as `lensray render` lights it.
fn lit(mut d: SceneDescription) -> SceneDescription {
    let settings = d.settings.clone();
    lensray_core::settings::light_scene(&settings, &mut d.scene).expect("the scene's lights");
    d
}

fn main() {
    let a = args();
    let default = lit(lensray_core::scene::builtin::default_scene());
    let result = if a.bvh_sweep && a.dense_sweep {
        bvh_sweep(&lit(lensray_core::scene::generate::dense(a.triangles)), &a)
    } else if a.bvh_sweep {
        bvh_sweep(&default, &a)
    } else {
        compare_traversals("default", &default, &a).and_then(|()| {
            let dense = lit(lensray_core::scene::generate::dense(a.triangles));
            compare_traversals("dense", &dense, &a)
        })
    };
    match result {
        Ok(()) => {}
        Err(e) if gpu_support::may_skip(&e) => {
            gpu_support::record_skip("benches/traversal", &e.to_string())
        }
        Err(e) => panic!("traversal bench: {e}"),
    }
}
