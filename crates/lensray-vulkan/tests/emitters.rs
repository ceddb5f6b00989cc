//! Emissive triangles as lights on every traversal the device has (ray queries, the software
//! traversal, the ray-tracing pipeline) against the CPU reference, validation on: the Cornell
//! box lit only by its emissive ceiling quad, with one surface a path (the emitters' draw
//! alone) and with three (the emitters' and the BRDF's draws weighed by multiple importance
//! sampling, and the emission a bounce meets weighed against the emitters' draw).
//!
//! Skipping follows tests/renderer.rs (LENSRAY_SKIP_GPU_TESTS=1 on machines without a device).

mod support;

use glam::Vec3;
use lensray_core::camera::{CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{GpuOptions, Traversal};
use support::*;

/// The Cornell box of assets/cornell: its ceiling quad (Ke 30) is the
/// only light.
fn emitter_lit_cornell() -> lensray_core::scene::Scene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/cornell/cornell.obj");
    lensray_core::scene::load_obj(&path)
        .expect("load the Cornell box")
        .scene
}

fn cornell_shot(bounces: u32) -> Shot {
    Shot {
        camera: CameraParams {
            eye: Vec3::new(0.0, 1.0, 3.6),
            target: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            projection: ProjectionParams::Perspective { vfov_degrees: 40.0 },
            lens: LensParams::Pinhole,
            near: 0.05,
            far: 7.0,
            width: 64,
            height: 48,
            movements: Movements::NONE,
        }
        .build()
        .expect("valid camera"),
        render: RenderSettings {
            bounces,
            ..settings(Shading::Lit, 4)
        },
    }
}

#[test]
fn emitters_light_alike_on_every_traversal() {
    let test = "emitters_light_alike_on_every_traversal";
    let Some((mut rayquery, rayquery_log)) = renderer(test) else {
        return;
    };
    let mut pipeline = if rayquery.device_report().rt_pipeline {
        let options = GpuOptions {
            traversal: Some(Traversal::RtPipeline),
            ..Default::default()
        };
        renderer_with(test, &options)
    } else {
        record_skip(
            test,
            "the device has no ray-tracing pipeline: rtpipeline not checked",
        );
        None
    };
    let scene = emitter_lit_cornell();
    let cpu = CpuRenderer::new(&scene);
    rayquery.load_scene(&scene).expect("load scene");
    if let Some((gpu, _)) = &mut pipeline {
        gpu.load_scene(&scene).expect("load scene");
    }
    for bounces in [1, 3] {
        let shot = cornell_shot(bounces);
        let (reference, _) = cpu.render(&shot, &mut |_, _| {});
        // Test set-up: the emitter lights the room (the walls are not black).
        let mean =
            reference.pixels.iter().map(|p| p.x).sum::<f32>() / reference.pixels.len() as f32;
        assert!(mean > 0.05, "bounces {bounces}: the room is dark ({mean})");
        for traversal in [
            Traversal::RayQuery,
            Traversal::Software,
            Traversal::RtPipeline,
        ] {
            let gpu = match (traversal, &mut pipeline) {
                (Traversal::RtPipeline, Some((gpu, _))) => gpu,
                (Traversal::RtPipeline, None) => continue,
                _ => {
                    rayquery.set_traversal(traversal).expect("set traversal");
                    &mut rayquery
                }
            };
            let image = gpu.render(&shot, &mut |_, _| {}).expect("GPU render");
            let diff = compare(&image, &reference, 1.0 / 255.0);
            let label = format!("emitters-{bounces}-{traversal:?}").to_lowercase();
            println!("{label}: {diff:?}");
            if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
                let files = write_comparison(&image, &reference, &label);
                panic!("{label}: GPU and CPU differ: {diff:?}; wrote {files}");
            }
        }
    }
    if let Some((gpu, log)) = pipeline {
        finish(gpu, log);
    }
    finish(rayquery, rayquery_log);
}
