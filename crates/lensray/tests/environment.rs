//! Light from the environment: the white furnace (a metal under a uniform white sky reflects
//! its directional albedo, what single scattering keeps, and loses the rest), and the raster
//! path drawing a metallic-roughness scene under an HDR map and over bounces as the CPU
//! reference does.

mod gpu_support;

use std::f32::consts::PI;
use std::sync::Arc;

use glam::Vec3;
use gpu_support::{
    camera, compare, open_path_with, settings, sphere, test_scene, write_comparison,
};
use lensray::paths::{OpenedPath, PathChoice, PathKind};
use lensray_core::camera::{CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::film::compare::mean_error;
use lensray_core::reference::brdf::{ggx_distribution, Dielectric, MetallicRoughness};
use lensray_core::reference::Renderer;
use lensray_core::scene::environment::studio::studio;
use lensray_core::scene::{EnvironmentLight, Material, Mesh, Scene};
use lensray_core::settings::{RenderSettings, Shading, Shot};

/// A quad through the origin whose normal is tilted `degrees` from +Z towards +Y, long enough
/// along its tilted side to fill a view 1 high seen along -Z.
fn tilted_quad(degrees: f32) -> Mesh {
    let (s, c) = degrees.to_radians().sin_cos();
    // The quad's own axes: x, and y turned about x.
    let (x, y) = (Vec3::X * 2.0, Vec3::new(0.0, c, -s) * (1.0 + 1.0 / c));
    Mesh {
        name: "quad".into(),
        positions: vec![-x - y, x - y, x + y, -x + y],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![0; 2],
        ..Default::default()
    }
}

/// The directional albedo of `brdf` seen at n.v = `mu`: the integral of f cos over the
/// hemisphere, written over the half vector h (dl = 4 v.h dh) and integrated on a 512 x 512
/// grid of GGX's inverse cumulative distribution of h (density D(h) n.h), fine for the
/// narrowest lobe, independently of the renderer's visible-normal draws and their weighing.
fn albedo(brdf: &MetallicRoughness, mu: f32) -> f32 {
    let v = Vec3::new(0.0, (1.0 - mu * mu).sqrt(), mu);
    let alpha = brdf.alpha();
    let steps = 512;
    let mut sum = 0.0f64;
    for i in 0..steps {
        let u1 = (i as f32 + 0.5) / steps as f32;
        let cos_h = ((1.0 - u1) / (1.0 + (alpha * alpha - 1.0) * u1)).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).sqrt();
        for j in 0..steps {
            let phi = (j as f32 + 0.5) / steps as f32 * 2.0 * PI;
            let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
            let l = 2.0 * v.dot(h) * h - v;
            if l.z <= 0.0 || v.dot(h) <= 0.0 {
                continue;
            }
            let density = ggx_distribution(cos_h, alpha) * cos_h;
            let f = brdf.evaluate(Vec3::Z, l, v).x;
            sum += f64::from(f * l.z * 4.0 * v.dot(h) / density);
        }
    }
    (sum / f64::from(steps * steps)) as f32
}

/// The furnaces' camera: 16 x 16 pixels looking down -Z at the unit square, orthographic.
fn furnace_camera() -> lensray_core::camera::Camera {
    CameraParams {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: ProjectionParams::Orthographic { height: 1.0 },
        lens: LensParams::Pinhole,
        near: 0.5,
        far: 50.0,
        width: 16,
        height: 16,
        movements: Movements::NONE,
    }
    .build()
    .expect("furnace camera")
}

/// The white furnace: a white metal (base colour 1, metallic 1) under a uniform sky of
/// radiance 1 reflects its directional albedo E(n.v) at every pixel, which a quadrature of the
/// BRDF gives independently of the renderer's sampling; 1 - E is the energy single scattering
/// loses (no multiple-scattering compensation, as glTF's Appendix B). The loss per roughness
/// is printed and lies in docs/environment.md.
#[test]
fn a_white_metal_in_a_white_furnace_reflects_its_albedo() {
    let camera = furnace_camera();
    let render = RenderSettings {
        environment: Vec3::ONE,
        ..settings(Shading::Lit, 64)
    };
    for roughness in [0.1f32, 0.25, 0.5, 0.75, 1.0] {
        let brdf = MetallicRoughness {
            base_colour: Vec3::ONE,
            metallic: 1.0,
            roughness,
            specular: 1.0,
            dielectric: Dielectric::OPAQUE,
        };
        let mut losses = Vec::new();
        for (degrees, mu) in [(0.0f32, 1.0f32), (60.0, 0.5), (80.0, 0.173_648_18)] {
            let scene = Scene {
                meshes: vec![tilted_quad(degrees)],
                materials: vec![Material {
                    name: "white metal".into(),
                    diffuse: Vec3::ONE,
                    metallic: 1.0,
                    roughness,
                    specular: 1.0,
                    ..Default::default()
                }],
                ..Default::default()
            };
            let shot = Shot {
                camera: camera.clone(),
                render,
            };
            let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
            let values: Vec<f32> = image.pixels.iter().map(|p| p[0]).collect();
            let n = values.len() as f32;
            let mean = values.iter().sum::<f32>() / n;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / (n - 1.0);
            let standard_error = (variance / n).sqrt();
            let want = albedo(&brdf, mu);
            println!(
                "roughness {roughness}, n.v {mu:.3}: reflected {mean:.4} (+- {standard_error:.4}), \
                 albedo {want:.4}, loss {:.1} %",
                100.0 * (1.0 - want)
            );
            assert!(
                (mean - want).abs() <= 4.0 * standard_error + 2e-3,
                "roughness {roughness}, n.v {mu}: the furnace reflects {mean}, the BRDF's \
                 albedo is {want} (standard error {standard_error})"
            );
            assert!(want <= 1.0 + 1e-3, "albedo above 1: {want}");
            losses.push(1.0 - want);
        }
        // Single scattering loses more the rougher the metal.
        if roughness <= 0.1 {
            assert!(losses[0] < 0.01, "roughness 0.1 loses {losses:?}");
        }
    }
}

/// The white furnace with shading normals tilted from the surface's (what a normal map does):
/// the quad faces the viewer, its vertex normals lean `tilt` degrees towards +Y, so that for
/// tilts past 45 degrees the mirror reflection of the view about them points into the surface.
/// Shaded about that normal as it is, a smooth metal reflects nothing there (every draw falls
/// below the surface); the reflection-safe normal (docs/shading-normals.md) keeps the lobe above
/// the surface. The metal reflects at most its untilted albedo (plus noise: nothing is
/// created) and at least half of it (the lobe turned to graze the surface loses its lower
/// half at most).
#[test]
fn a_tilted_shading_normal_in_the_white_furnace_keeps_its_light() {
    let camera = furnace_camera();
    let render = RenderSettings {
        environment: Vec3::ONE,
        ..settings(Shading::Lit, 64)
    };
    for roughness in [0.1f32, 0.5] {
        let brdf = MetallicRoughness {
            base_colour: Vec3::ONE,
            metallic: 1.0,
            roughness,
            specular: 1.0,
            dielectric: Dielectric::OPAQUE,
        };
        let untilted = albedo(&brdf, 1.0);
        for tilt in [30.0f32, 60.0, 80.0] {
            let mut quad = tilted_quad(0.0);
            let (s, c) = tilt.to_radians().sin_cos();
            quad.normals = vec![Vec3::new(0.0, s, c); 4];
            let scene = Scene {
                meshes: vec![quad],
                materials: vec![Material {
                    name: "white metal".into(),
                    diffuse: Vec3::ONE,
                    metallic: 1.0,
                    roughness,
                    specular: 1.0,
                    ..Default::default()
                }],
                ..Default::default()
            };
            let shot = Shot {
                camera: camera.clone(),
                render,
            };
            let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
            let values: Vec<f32> = image.pixels.iter().map(|p| p[0]).collect();
            let n = values.len() as f32;
            let mean = values.iter().sum::<f32>() / n;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / (n - 1.0);
            let standard_error = (variance / n).sqrt();
            println!(
                "roughness {roughness}, tilt {tilt}: reflected {mean:.4} (+- {standard_error:.4}), \
                 untilted albedo {untilted:.4}"
            );
            assert!(
                mean <= untilted + 4.0 * standard_error + 2e-3,
                "roughness {roughness}, tilt {tilt}: {mean} is more than the albedo {untilted}"
            );
            assert!(
                mean >= 0.5 * untilted,
                "roughness {roughness}, tilt {tilt}: {mean} is less than half the albedo {untilted}"
            );
        }
    }
}

/// The test scene with a gold sphere and a glossy red one, under the studio map.
fn map_lit_scene() -> Scene {
    let mut scene = test_scene();
    let pbr = |name: &str, base: Vec3, metallic: f32, roughness: f32| Material {
        name: name.into(),
        diffuse: base,
        metallic,
        roughness,
        specular: 1.0,
        ..Default::default()
    };
    scene
        .materials
        .push(pbr("gold", Vec3::new(1.0, 0.78, 0.34), 1.0, 0.2));
    scene
        .materials
        .push(pbr("glossy red", Vec3::new(0.8, 0.1, 0.1), 0.0, 0.3));
    scene
        .meshes
        .push(sphere(Vec3::new(-0.9, 0.4, 1.4), 0.4, 12, 16, 4));
    scene
        .meshes
        .push(sphere(Vec3::new(0.2, 0.3, 1.8), 0.3, 12, 16, 5));
    scene.environment = Some(Arc::new(EnvironmentLight::new(
        studio(64).turned(-40.0, 0.7),
    )));
    scene
}

/// The raster path (one lens point per pass, shared by every pixel) draws metallic-roughness
/// spheres under the studio map, over paths of two surfaces, as the CPU reference does with
/// the same shared samples.
#[test]
fn the_raster_path_draws_a_map_lit_scene_as_the_cpu_does() {
    let test = "the_raster_path_draws_a_map_lit_scene_as_the_cpu_does";
    let scene = map_lit_scene();
    let lens = LensParams::ThinLens {
        aperture_radius: 0.1,
        focus_distance: 5.0,
    };
    let shot = Shot {
        camera: camera(false, lens, 64, 48),
        render: RenderSettings {
            environment_seen: true,
            bounces: 2,
            shared_samples: true,
            ..settings(Shading::Lit, 8)
        },
    };
    let Some(OpenedPath { path: mut cpu, .. }) =
        open_path_with(test, PathChoice::Only(PathKind::Cpu), &scene, &shot)
    else {
        return;
    };
    let reference = cpu.render(&shot, &mut |_, _| {}).expect("cpu render");
    cpu.close().expect("close");
    let Some(OpenedPath { mut path, .. }) =
        open_path_with(test, PathChoice::Only(PathKind::Raster), &scene, &shot)
    else {
        return;
    };
    let image = path.render(&shot, &mut |_, _| {}).expect("raster render");
    let diff = compare(&image, &reference, 1.0 / 255.0);
    println!("raster under the map: {diff:?}");
    if diff.within < 0.995 || diff.mean_abs >= 1e-3 {
        let files = write_comparison(&image, &reference, "raster-map-vs-cpu");
        panic!("raster: differs from the CPU reference under the map: {diff:?}; wrote {files}");
    }
    path.close().expect("close: validation messages or leaks");
}

/// The hybrid path (shortcuts where the blur is under half a pixel, checked by traced
/// samples) under the studio map with two bounces: its image mean is the CPU reference's
/// within noise (4 standard errors of a reference of 16x the samples and another seed).
#[test]
fn the_hybrid_path_converges_under_a_map() {
    let test = "the_hybrid_path_converges_under_a_map";
    let scene = map_lit_scene();
    let lens = LensParams::ThinLens {
        aperture_radius: 0.1,
        focus_distance: 5.0,
    };
    let shot = Shot {
        camera: camera(false, lens, 64, 48),
        render: RenderSettings {
            environment_seen: true,
            bounces: 2,
            ..settings(Shading::Lit, 16)
        },
    };
    let reference_shot = Shot {
        camera: shot.camera.clone(),
        render: RenderSettings {
            spp: 256,
            seed: shot.render.seed ^ 0x5bd1_e995,
            ..shot.render
        },
    };
    let Some(OpenedPath { path: mut cpu, .. }) = open_path_with(
        test,
        PathChoice::Only(PathKind::Cpu),
        &scene,
        &reference_shot,
    ) else {
        return;
    };
    let reference = cpu
        .render(&reference_shot, &mut |_, _| {})
        .expect("cpu render");
    cpu.close().expect("close");
    let Some(OpenedPath { mut path, .. }) =
        open_path_with(test, PathChoice::Only(PathKind::Hybrid), &scene, &shot)
    else {
        return;
    };
    let image = path.render(&shot, &mut |_, _| {}).expect("hybrid render");
    path.close().expect("close: validation messages or leaks");
    let error = mean_error(&image, &reference);
    println!("hybrid under the map: image-mean error {error:?}");
    if error.mean.abs() > 4.0 * error.standard_error {
        let files = write_comparison(&image, &reference, "hybrid-map-vs-cpu");
        panic!("hybrid: its image mean is off by {error:?} under the map; wrote {files}");
    }
}
