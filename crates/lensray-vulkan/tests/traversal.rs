//! The trace pass's closest-hit implementations (ray queries; the ray-tracing pipeline; the
//! software traversal of the project's own BVH) on the device present (lavapipe on CI),
//! validation on: the ray-tracing pipeline and the software traversal find the surfaces ray
//! queries find, the software traversal shades like the CPU reference and runs on a device whose
//! ray queries are hidden; every traversal shades the metallic-roughness BRDF like the CPU.
//!
//! Skipping follows tests/renderer.rs (LENSRAY_SKIP_GPU_TESTS=1 on machines without a device).

mod support;

use std::sync::Arc;

use glam::Vec3;
use lensray_core::camera::LensParams;
use lensray_core::film::{Accumulation, Image};
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::scene::environment::studio::studio;
use lensray_core::scene::texture::{Encoding, Texture, TextureRef};
use lensray_core::scene::{EnvironmentLight, Light, Material, Scene};
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{Estimator, GpuError, GpuOptions, GpuRenderer, Traversal, ValidationLog};
use support::*;

/// The project's scenes (built-in default, Cornell box) as the CLI resolves them, small.
fn project_scenes(
    width: u32,
    height: u32,
    spp: u32,
    shading: Shading,
) -> Vec<(&'static str, Scene, Shot)> {
    use lensray_core::settings::{ImageSettings, RenderStyle, Settings};
    let cornell =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/cornell/cornell.toml");
    let scenes = [
        ("default", lensray_core::scene::builtin::default_scene()),
        (
            "cornell",
            lensray_core::scene::file::load(&cornell).expect("load the Cornell box"),
        ),
    ];
    scenes
        .into_iter()
        .map(|(name, mut desc)| {
            let settings = desc.settings.clone();
            lensray_core::settings::light_scene(&settings, &mut desc.scene).expect("its lights");
            let over = Settings {
                image: ImageSettings {
                    width: Some(width),
                    height: Some(height),
                    spp: Some(spp),
                    seed: Some(3),
                    sampler: None,
                    fps: None,
                },
                render: RenderStyle {
                    shading: Some(shading),
                    background: None,
                    environment: None,
                    environment_rotation: None,
                    environment_intensity: None,
                    bounces: None,
                    noise_threshold: None,
                },
                ..Default::default()
            };
            let resolved = lensray_core::settings::shot(
                &desc.settings.clone().overridden_by(&over),
                &desc.scene,
            )
            .expect("resolve settings");
            (name, desc.scene, resolved)
        })
        .collect()
}

/// Pixels whose values differ at all.
fn differing_pixels(a: &Image, b: &Image) -> usize {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| p != q)
        .count()
}

/// Unlit, both traversals find the same surfaces: identical images but for samples through a
/// shared edge, where either triangle may win the tie.
#[test]
fn software_equals_rayquery_unlit() {
    let Some((mut gpu, log)) = renderer("software_equals_rayquery_unlit") else {
        return;
    };
    let traversals = gpu.traversals();
    if !traversals.contains(&Traversal::RayQuery) {
        record_skip(
            "software_equals_rayquery_unlit",
            "the device has no ray queries to compare with",
        );
        return;
    }
    assert_eq!(traversals, vec![Traversal::RayQuery, Traversal::Software]);
    assert_eq!(gpu.traversal(), Traversal::RayQuery, "ray queries first");
    for (name, scene, shot) in project_scenes(160, 120, 2, Shading::Unlit) {
        gpu.load_scene(&scene).expect("load scene");
        gpu.set_traversal(Traversal::RayQuery).unwrap();
        let rayquery = gpu.render(&shot, &mut |_, _| {}).expect("ray-query render");
        gpu.set_traversal(Traversal::Software).unwrap();
        assert_eq!(gpu.traversal(), Traversal::Software);
        let software = gpu.render(&shot, &mut |_, _| {}).expect("software render");
        let differing = differing_pixels(&software, &rayquery);
        let pixels = software.pixels.len();
        println!("{name}: {differing} of {pixels} pixels differ (shared-edge ties)");
        // Under 0.1% of the pixels.
        if differing * 1000 >= pixels {
            let files = write_comparison(&software, &rayquery, &format!("software-rq-{name}"));
            panic!("{name}: {differing} of {pixels} pixels differ; wrote {files}");
        }
        let t = gpu.timings();
        assert!(t.accel_bytes > 0 && t.bvh_bytes > 0, "{t:?}");
    }
    finish(gpu, log);
}

/// Two renderers on the device, one opened for ray queries and one for the ray-tracing
/// pipeline alone; `None` (recorded as a skip) where the device has either missing.
fn rayquery_and_rtpipeline(
    test: &str,
) -> Option<((GpuRenderer, ValidationLog), (GpuRenderer, ValidationLog))> {
    let open = |traversal| {
        let options = GpuOptions {
            traversal: Some(traversal),
            ..Default::default()
        };
        renderer_with(test, &options)
    };
    let rayquery = open(Traversal::RayQuery)?;
    if !rayquery.0.device_report().rt_pipeline {
        record_skip(test, "the device has no ray-tracing pipeline");
        return None;
    }
    Some((rayquery, open(Traversal::RtPipeline)?))
}

/// The ray-tracing pipeline traces through the acceleration structures ray queries use, with
/// the same alpha test and shading: unlit and lit (its shadow rays), the project's scenes, the
/// same images as ray queries but for shared-edge ties.
#[test]
fn rtpipeline_equals_rayquery() {
    let test = "rtpipeline_equals_rayquery";
    let Some(((mut rayquery, rayquery_log), (mut pipeline, pipeline_log))) =
        rayquery_and_rtpipeline(test)
    else {
        return;
    };
    assert_eq!(pipeline.traversals(), vec![Traversal::RtPipeline]);
    for shading in [Shading::Unlit, Shading::Lit] {
        for (name, scene, shot) in project_scenes(96, 72, 2, shading) {
            rayquery.load_scene(&scene).expect("load scene");
            pipeline.load_scene(&scene).expect("load scene");
            let expected = rayquery.render(&shot, &mut |_, _| {}).expect("ray queries");
            let image = pipeline.render(&shot, &mut |_, _| {}).expect("rt pipeline");
            let differing = differing_pixels(&image, &expected);
            let pixels = image.pixels.len();
            println!("{name} {shading:?}: {differing} of {pixels} pixels differ");
            if differing * 1000 >= pixels {
                let files = write_comparison(&image, &expected, &format!("rtp-rq-{name}"));
                panic!("{name} {shading:?}: {differing} of {pixels} pixels differ; wrote {files}");
            }
            let t = pipeline.timings();
            assert!(t.accel_bytes > 0 && t.bvh_bytes == 0, "{t:?}");
        }
    }
    finish(pipeline, pipeline_log);
    finish(rayquery, rayquery_log);
}

/// On a device opened for the ray-tracing pipeline alone (as one without ray queries), the
/// hybrid and raster estimators trace their rays with it: lit, the same sums as with ray
/// queries but for shared-edge ties.
#[test]
fn rtpipeline_traces_the_hybrid_and_raster_estimators() {
    let test = "rtpipeline_traces_the_hybrid_and_raster_estimators";
    let Some(((mut rayquery, rayquery_log), (mut pipeline, pipeline_log))) =
        rayquery_and_rtpipeline(test)
    else {
        return;
    };
    let (name, scene, shot) = project_scenes(96, 72, 4, Shading::Lit).remove(0);
    rayquery.load_scene(&scene).expect("load scene");
    pipeline.load_scene(&scene).expect("load scene");
    for estimator in [Estimator::Hybrid, Estimator::Raster] {
        let image = |gpu: &mut GpuRenderer| {
            let cam = &shot.camera;
            let mut sums = Accumulation::new(cam.width, cam.height);
            gpu.add_samples(
                &shot,
                estimator,
                0..shot.render.spp,
                &mut sums,
                &mut |_, _| {},
            )
            .expect("add samples");
            gpu.read_sums(&mut sums).expect("read sums");
            sums.image().expect("on the host")
        };
        let expected = image(&mut rayquery);
        let traced = image(&mut pipeline);
        let differing = differing_pixels(&traced, &expected);
        let pixels = traced.pixels.len();
        println!("{name} {estimator:?}: {differing} of {pixels} pixels differ");
        if differing * 1000 >= pixels {
            let files = write_comparison(&traced, &expected, &format!("rtp-rq-{estimator:?}"));
            panic!("{estimator:?}: {differing} of {pixels} pixels differ; wrote {files}");
        }
    }
    finish(pipeline, pipeline_log);
    finish(rayquery, rayquery_log);
}

/// Lit, the software traversal against the CPU reference with the statistics of
/// tests/renderer/renders.rs (`gpu_matches_cpu`): the test scene through a thin lens, and the project's scenes.
#[test]
fn software_matches_cpu_lit() {
    let Some((mut gpu, log)) = renderer("software_matches_cpu_lit") else {
        return;
    };
    gpu.set_traversal(Traversal::Software).unwrap();
    let lens = LensParams::ThinLens {
        aperture_radius: 0.12,
        focus_distance: 5.0,
    };
    let mut cases = vec![(
        "test-scene",
        test_scene(),
        Shot {
            camera: camera(false, lens, 96, 72),
            render: settings(Shading::Lit, 8),
        },
    )];
    cases.extend(project_scenes(96, 72, 4, Shading::Lit));
    for (name, scene, shot) in cases {
        gpu.load_scene(&scene).expect("load scene");
        let image = gpu.render(&shot, &mut |_, _| {}).expect("software render");
        let (reference, _) = CpuRenderer::new(&scene).render(&shot, &mut |_, _| {});
        let diff = compare(&image, &reference, 1.0 / 255.0);
        let label = format!("software-vs-cpu-{name}");
        println!("{label}: {diff:?}");
        if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
            let files = write_comparison(&image, &reference, &label);
            panic!("{label}: software and CPU differ: {diff:?}; wrote {files}");
        }
    }
    finish(gpu, log);
}

/// With ray queries hidden the device opens for the software traversal only, builds no
/// acceleration structures, renders, and refuses ray queries with a clear error.
#[test]
fn hidden_ray_queries_leave_the_software_traversal() {
    let options = GpuOptions {
        hide_ray_query: true,
        ..Default::default()
    };
    let Some((mut gpu, log)) =
        renderer_with("hidden_ray_queries_leave_the_software_traversal", &options)
    else {
        return;
    };
    assert_eq!(gpu.traversals(), vec![Traversal::Software]);
    assert_eq!(gpu.traversal(), Traversal::Software);
    assert!(!gpu.device_report().ray_query && gpu.device_report().software);
    let err = gpu
        .set_traversal(Traversal::RayQuery)
        .expect_err("ray queries are hidden");
    let text = err.to_string();
    assert!(
        matches!(err, GpuError::TraversalUnavailable { .. })
            && text.contains("rayquery")
            && text.contains("not available")
            && !text.contains('\n'),
        "unclear: {text}"
    );

    let scene = test_scene();
    gpu.load_scene(&scene).expect("load scene");
    let t = gpu.timings();
    assert_eq!(t.accel_bytes, 0, "no acceleration structures: {t:?}");
    assert!(t.bvh_bytes > 0, "{t:?}");
    let shot = Shot {
        camera: camera(false, LensParams::Pinhole, 48, 36),
        render: settings(Shading::Unlit, 1),
    };
    let image = gpu.render(&shot, &mut |_, _| {}).expect("render");
    let (reference, _) = CpuRenderer::new(&scene).render(&shot, &mut |_, _| {});
    let diff = compare(&image, &reference, 1.0 / 255.0);
    assert!(diff.within >= 0.995, "{diff:?}");
    finish(gpu, log);
}

/// Asking for the software traversal alone opens no ray-tracing extension even where the device
/// has them, and asking for ray queries alone builds no BVH.
#[test]
fn a_requested_traversal_builds_only_its_structures() {
    for traversal in Traversal::ALL {
        let options = GpuOptions {
            traversal: Some(traversal),
            ..Default::default()
        };
        let Some((mut gpu, log)) =
            renderer_with("a_requested_traversal_builds_only_its_structures", &options)
        else {
            return;
        };
        assert_eq!(gpu.traversals(), vec![traversal]);
        gpu.load_scene(&test_scene()).expect("load scene");
        let t = gpu.timings();
        assert_eq!(
            (t.accel_bytes > 0, t.bvh_bytes > 0),
            (
                traversal != Traversal::Software,
                traversal == Traversal::Software
            ),
            "{traversal}: {t:?}"
        );
        finish(gpu, log);
    }
}

/// Metallic-roughness spheres (red dielectric and gold metal, roughness 0.2 and 0.6, a fifth
/// whose metallic, roughness and occlusion come from 8 x 8 checkers, a sixth of red plastic
/// under a clear coat whose weight and roughness come from the same checkers, a seventh of
/// velvet: dark red under a bright sheen whose colour (sRGB) and roughness (alpha) come from a
/// checker, a glass volume whose transmission comes from the first checkers and a thin glass
/// wall) on a Lambert floor under a point light.
fn metallic_rough_scene() -> Scene {
    let pbr = |name: &str, base: Vec3, metallic: f32, roughness: f32| Material {
        metallic,
        roughness,
        specular: 1.0,
        ..material(name, base, Vec3::ZERO)
    };
    let (red, gold) = (Vec3::new(0.8, 0.1, 0.1), Vec3::new(1.0, 0.78, 0.34));
    let ball = |x: f32, z: f32, material: u32| {
        let mut mesh = sphere(Vec3::new(x, 0.45, z), 0.45, 16, 24, material);
        // Planar texture coordinates: 3 checker cells across the sphere.
        mesh.texcoords = mesh
            .positions
            .iter()
            .map(|p| glam::Vec2::new(p.x, p.y) * 0.8)
            .collect();
        mesh
    };
    // Metal (B) and rough (G) in alternate cells; occlusion (R) 1 and 1/4.
    let checker = |cell: [u8; 4], other: [u8; 4]| -> Vec<u8> {
        (0..64)
            .flat_map(|i| {
                if (i % 8 + i / 8) % 2 == 0 {
                    cell
                } else {
                    other
                }
            })
            .collect()
    };
    let metallic_roughness = checker([0, 51, 255, 255], [0, 204, 0, 255]);
    let occlusion = checker([255, 0, 0, 255], [64, 0, 0, 255]);
    // Sheen colours warm and cold (sRGB), roughness 0.3 and 0.9 (alpha).
    let sheen = checker([255, 240, 220, 77], [180, 220, 255, 230]);
    let textures = vec![
        Texture::from_rgba8(
            "metallic-roughness",
            8,
            8,
            &metallic_roughness,
            Encoding::Linear,
        ),
        Texture::from_rgba8("occlusion", 8, 8, &occlusion, Encoding::Linear),
        Texture::from_rgba8("sheen", 8, 8, &sheen, Encoding::Srgb),
    ];
    Scene {
        meshes: vec![
            floor(6.0, 0.0, 0),
            ball(-1.5, 0.0, 1),
            ball(-0.5, 0.0, 2),
            ball(0.5, 0.0, 3),
            ball(1.5, 0.0, 4),
            ball(0.0, 1.2, 5),
            ball(1.2, 1.2, 6),
            ball(-1.2, 1.2, 7),
            ball(0.6, 2.2, 8),
            ball(-0.8, 2.4, 9),
        ],
        materials: vec![
            material("floor", Vec3::splat(0.6), Vec3::ZERO),
            pbr("plastic 0.2", red, 0.0, 0.2),
            pbr("plastic 0.6", red, 0.0, 0.6),
            pbr("gold 0.2", gold, 1.0, 0.2),
            pbr("gold 0.6", gold, 1.0, 0.6),
            Material {
                metallic_roughness_texture: Some(TextureRef::new(0)),
                occlusion_texture: Some(TextureRef::new(1)),
                occlusion_strength: 0.8,
                ..pbr("checkered", gold, 1.0, 1.0)
            },
            // Coat weight 1 and 1/4 (R), roughness 0.3 x 0.8 and 0.3 x 0.2 (G).
            Material {
                clearcoat: 1.0,
                clearcoat_texture: Some(TextureRef::new(1)),
                clearcoat_roughness: 0.3,
                clearcoat_roughness_texture: Some(TextureRef::new(0)),
                ..pbr("coated", red, 0.0, 0.6)
            },
            Material {
                sheen_colour: Vec3::new(1.0, 0.9, 0.8),
                sheen_colour_texture: Some(TextureRef::new(2)),
                sheen_roughness: 1.0,
                sheen_roughness_texture: Some(TextureRef::new(2)),
                ..pbr("velvet", Vec3::new(0.3, 0.02, 0.04), 0.0, 0.8)
            },
            // A glass volume (a purple attenuation) that transmits 1 and 1/4 (R), and a
            // rough thin wall of a lower index.
            Material {
                transmission: 1.0,
                transmission_texture: Some(TextureRef::new(1)),
                thin: false,
                attenuation: Vec3::new(0.3, 2.0, 0.3),
                ..pbr("glass", Vec3::ONE, 0.0, 0.1)
            },
            Material {
                transmission: 1.0,
                ior: 1.3,
                ..pbr("thin", Vec3::new(0.6, 0.8, 1.0), 0.0, 0.3)
            },
        ],
        textures,
        lights: vec![Light::point(Vec3::new(1.0, 4.0, 4.0), Vec3::splat(40.0))],
        environment: None,
    }
}

/// The metallic-roughness BRDF on each traversal the device has (ray queries, the software
/// traversal, the ray-tracing pipeline) against the CPU reference, with the statistics of
/// `gpu_matches_cpu`: lit by the point light; by the light and the uniform sky; by the light and
/// the studio map (drawn by power and by the BRDF, multiple importance sampling), seen behind;
/// and by those over paths of three surfaces (`bounces`).
#[test]
fn metallic_rough_spheres_match_cpu_on_every_traversal() {
    let test = "metallic_rough_spheres_match_cpu_on_every_traversal";
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
    let plain = metallic_rough_scene();
    let map = Arc::new(EnvironmentLight::new(studio(64).turned(30.0, 0.5)));
    let mapped = Scene {
        environment: Some(map),
        ..plain.clone()
    };
    // (label, scene, uniform sky, a miss sees the map, bounces)
    let cases = [
        ("light", &plain, Vec3::ZERO, false, 1),
        ("sky", &plain, Vec3::splat(0.3), false, 1),
        ("map", &mapped, Vec3::ZERO, true, 1),
        ("map-bounces", &mapped, Vec3::ZERO, true, 3),
    ];
    let mut loaded: Option<&Scene> = None;
    let mut cpu = CpuRenderer::new(&plain);
    for (sky, scene, environment, environment_seen, bounces) in cases {
        if loaded != Some(scene) {
            cpu = CpuRenderer::new(scene);
            rayquery.load_scene(scene).expect("load scene");
            if let Some((gpu, _)) = &mut pipeline {
                gpu.load_scene(scene).expect("load scene");
            }
            loaded = Some(scene);
        }
        let shot = Shot {
            camera: camera(false, LensParams::Pinhole, 96, 72),
            render: RenderSettings {
                environment,
                environment_seen,
                bounces,
                ..settings(Shading::Lit, 4)
            },
        };
        let (reference, _) = cpu.render(&shot, &mut |_, _| {});
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
            let label = format!("pbr-{sky}-{traversal:?}").to_lowercase();
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
