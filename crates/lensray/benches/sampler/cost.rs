//! Part 5: the cost of sample generation as a fraction of the render time, CPU and GPU.

use std::hint::black_box;
use std::time::Instant;

use glam::UVec2;
use rayon::prelude::*;

use lensray_core::reference::Renderer;
use lensray_core::sampler::{pixel_camera_samples, pixel_sampler};
use lensray_core::settings::{RenderSettings, Shot};
use lensray_vulkan::{GpuOptions, GpuRenderer};

use crate::{render, resolved, scenes, Options, KINDS};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Seconds to generate every camera sample of a render of `shot`, as the renderer does (rows in
/// parallel; per pixel the set-up, then packets of 16 samples).
fn generation_seconds(shot: &Shot) -> f64 {
    let (camera, settings) = (&shot.camera, &shot.render);
    let start = Instant::now();
    let total: f32 = (0..camera.height)
        .into_par_iter()
        .map(|y| {
            let mut sum = [0.0f32; 16];
            for x in 0..camera.width {
                let state = pixel_sampler(
                    settings.sampler,
                    settings.seed,
                    UVec2::new(x, y),
                    camera.width,
                );
                for first in (0..settings.spp).step_by(16) {
                    let dims = pixel_camera_samples::<16>(&state, first);
                    for dim in black_box(dims) {
                        for (s, v) in sum.iter_mut().zip(dim) {
                            *s += v;
                        }
                    }
                }
            }
            sum.iter().sum::<f32>()
        })
        .sum();
    black_box(total);
    start.elapsed().as_secs_f64()
}

pub fn cost(o: &Options) {
    let (_, desc) = scenes().remove(0);
    let runs = if o.full { 5 } else { 1 };
    println!(
        "== Cost of sample generation (default scene, {}x{}, 16 spp, lit; medians of {runs})",
        o.cost_width, o.cost_height
    );
    let renderer = Renderer::new(&desc.scene);
    let shot = resolved(&desc, o.cost_width, o.cost_height, None);
    let camera = &shot.camera;
    for kind in KINDS {
        let s = Shot {
            camera: camera.clone(),
            render: RenderSettings {
                spp: 16,
                sampler: kind,
                ..shot.render
            },
        };
        let _ = render(&renderer, &s);
        let render_s = median(
            (0..runs)
                .map(|_| renderer.render(&s, &mut |_, _| {}).1.elapsed.as_secs_f64())
                .collect(),
        );
        let generate_s = median((0..runs).map(|_| generation_seconds(&s)).collect());
        println!(
            "CPU {kind}: render {:.1} ms, samples alone {:.2} ms = {:.2} % ({:.2} ns per sample)",
            render_s * 1e3,
            generate_s * 1e3,
            100.0 * generate_s / render_s,
            generate_s * 1e9 / f64::from(camera.width * camera.height * 16)
        );
    }
    let mut gpu = match GpuRenderer::new(&GpuOptions::default()) {
        Ok(gpu) => gpu,
        Err(e) => {
            println!("GPU: skipped ({e})");
            return;
        }
    };
    gpu.load_scene(&desc.scene).expect("load scene");
    for kind in KINDS {
        let s = Shot {
            camera: camera.clone(),
            render: RenderSettings {
                spp: 16,
                sampler: kind,
                ..shot.render
            },
        };
        let _ = gpu.render(&s, &mut |_, _| {}).expect("GPU render");
        let mut trace = Vec::new();
        let mut generate = Vec::new();
        for _ in 0..runs.min(3) {
            let before = gpu.timings().trace_gpu_ms;
            let _ = gpu.render(&s, &mut |_, _| {}).expect("GPU render");
            trace.push(gpu.timings().trace_gpu_ms - before);
            generate.push(gpu.sample_generation_ms(&s).expect("GPU sample cost"));
        }
        let (trace, generate) = (median(trace), median(generate));
        println!(
            "GPU {kind} ({}): trace pass {trace:.1} ms, samples alone {generate:.2} ms = {:.2} %",
            gpu.device_name(),
            100.0 * generate / trace
        );
    }
}
