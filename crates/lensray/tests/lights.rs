//! Lights on every path: point, spot and directional lights with hard shadows (through an alpha
//! mask too) and the uniform environment render on the GPU as on the CPU reference, and the
//! CPU reference's lighting matches the formulas (a directional light's Lambert term, a spot's
//! cone, the environment's open half-space).

mod gpu_support;

use glam::Vec3;
use gpu_support::{assert_gpu_paths_match_cpu, camera, floor, settings, test_scene};
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::interface::SHADOW_ORIGIN_OFFSET;
use lensray_core::reference::Renderer;
use lensray_core::scene::test_card::test_card;
use lensray_core::scene::{Light, LightKind, Material, Mesh, Scene};
use lensray_core::settings::{RenderSettings, Shading, Shot};

fn spot(position: Vec3, target: Vec3, intensity: Vec3, inner: f32, outer: f32) -> Light {
    Light {
        kind: LightKind::Spot {
            cos_inner: inner.to_radians().cos(),
            cos_outer: outer.to_radians().cos(),
        },
        direction: (target - position).normalize(),
        range: 0.0,
        ..Light::point(position, intensity)
    }
}

fn sun(direction: Vec3, irradiance: Vec3) -> Light {
    Light {
        kind: LightKind::Directional,
        direction: direction.normalize(),
        ..Light::point(Vec3::ZERO, irradiance)
    }
}

/// The test scene under a point light with a range, a spot and a sun at a slant.
fn lit_scene() -> Scene {
    let mut scene = test_scene();
    scene.lights = vec![
        Light {
            range: 9.0,
            ..Light::point(Vec3::new(-2.5, 3.0, 2.0), Vec3::new(12.0, 10.0, 8.0))
        },
        spot(
            Vec3::new(1.5, 3.5, 1.5),
            Vec3::new(0.8, 0.0, 0.3),
            Vec3::new(20.0, 25.0, 30.0),
            15.0,
            30.0,
        ),
        sun(Vec3::new(0.4, -1.0, -0.3), Vec3::new(0.6, 0.55, 0.5)),
    ];
    scene
}

fn shot(environment: Vec3, spp: u32) -> Shot {
    let lens = LensParams::ThinLens {
        aperture_radius: 0.08,
        focus_distance: 6.0,
    };
    Shot {
        camera: camera(false, lens, 80, 60),
        render: RenderSettings {
            environment,
            ..settings(Shading::Lit, spp)
        },
    }
}

/// Point (with a range), spot and directional lights, each with its shadow, and the environment.
#[test]
fn gpu_paths_light_as_the_cpu_does() {
    let test = "gpu_paths_light_as_the_cpu_does";
    let shot = shot(Vec3::new(0.3, 0.35, 0.45), 8);
    assert_gpu_paths_match_cpu(test, &lit_scene(), &[(test.into(), shot)]);
}

/// The textured card's masked leaf casts its shadow through the mask under a spot and the sky.
#[test]
fn gpu_paths_cast_masked_shadows_from_every_light() {
    let test = "gpu_paths_cast_masked_shadows_from_every_light";
    let scene = Scene {
        lights: vec![
            spot(
                Vec3::new(0.5, 3.0, 3.5),
                Vec3::new(0.0, 0.8, 0.0),
                Vec3::splat(30.0),
                20.0,
                40.0,
            ),
            sun(Vec3::new(-0.3, -0.6, -1.0), Vec3::splat(0.5)),
        ],
        ..test_card()
    };
    let camera = CameraParams {
        eye: Vec3::new(0.0, 1.2, 4.0),
        target: Vec3::new(0.0, 0.8, 0.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 50.0 },
        lens: LensParams::ThinLens {
            aperture_radius: 0.06,
            focus_distance: 4.3,
        },
        near: 0.1,
        far: 100.0,
        width: 80,
        height: 60,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera");
    let shot = Shot {
        camera,
        render: RenderSettings {
            environment: Vec3::splat(0.2),
            ..settings(Shading::Lit, 8)
        },
    };
    assert_gpu_paths_match_cpu(test, &scene, &[(test.into(), shot)]);
}

/// A square of `half` metres at height 0 facing up (+y), of colour `kd`.
fn ground(half: f32, kd: Vec3) -> Scene {
    Scene {
        meshes: vec![floor(half, 0.0, 0)],
        materials: vec![Material::new("ground", kd, Vec3::ZERO)],
        ..Default::default()
    }
}

/// Looking straight down at the ground from `height`, a pinhole of 20 degrees.
fn top_down(height: f32, size: u32) -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, height, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        projection: ProjectionParams::Perspective { vfov_degrees: 20.0 },
        lens: LensParams::Pinhole,
        near: 0.01,
        far: 100.0,
        width: size,
        height: size,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera")
}

/// A directional light gives Kd / pi * E * cos(theta) everywhere, unshadowed on open ground.
#[test]
fn a_directional_light_is_lambert_with_its_irradiance() {
    let kd = Vec3::new(0.5, 0.6, 0.7);
    let e = Vec3::new(2.0, 3.0, 4.0);
    let direction = Vec3::new(0.3, -1.0, 0.2).normalize();
    let scene = Scene {
        lights: vec![sun(direction, e)],
        ..ground(50.0, kd)
    };
    let shot = Shot {
        camera: top_down(5.0, 8),
        render: settings(Shading::Lit, 1),
    };
    let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    let expected = kd / std::f32::consts::PI * e * -direction.y;
    for p in &image.pixels {
        let error = ((*p - expected) / expected).abs().max_element();
        assert!(error < 1e-5, "{p} against {expected}: relative {error}");
    }
}

/// A spot light straight down: full intensity inside its inner cone, none outside its outer
/// cone, and glTF's squared ramp between.
#[test]
fn a_spot_light_falls_off_across_its_cone() {
    let scene = Scene {
        lights: vec![spot(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::ZERO,
            Vec3::ONE,
            10.0,
            20.0,
        )],
        ..ground(50.0, Vec3::ONE)
    };
    let size = 65;
    let camera = top_down(3.0, size);
    let shot = Shot {
        camera: camera.clone(),
        render: RenderSettings {
            background: Vec3::ZERO,
            ..settings(Shading::Lit, 1)
        },
    };
    let (image, _) = Renderer::new(&scene).render(&shot, &mut |_, _| {});
    let mut checked = [0; 3];
    for row in 0..size {
        for column in 0..size {
            let sample = lensray_core::sampler::camera_sample(
                shot.render.sampler,
                shot.render.seed,
                glam::UVec2::new(column, row),
                size,
                0,
            );
            let ray = camera.first_order_ray(sample);
            let p = ray.at(-ray.origin.y / ray.direction.y);
            let angle = p.x.hypot(p.z).atan().to_degrees();
            // From the shadow ray's origin (reference/surface.rs), just above the ground.
            let o = p + Vec3::Y * SHADOW_ORIGIN_OFFSET * (1.0 + p.abs().max_element());
            let to_light = Vec3::Y - o;
            let d = to_light.length();
            // The angle's cosine at the spot and the light's at the ground are both to_light.y / d.
            let cos = to_light.y / d;
            let lambert = cos / (d * d) / std::f32::consts::PI;
            let got = image.get(column, row).x;
            let (expected, case) = if angle < 9.9 {
                (lambert, 0)
            } else if angle > 20.1 {
                (0.0, 2)
            } else if (10.1..19.9).contains(&angle) {
                let (inner, outer) = (10f32.to_radians().cos(), 20f32.to_radians().cos());
                let t = (cos - outer) / (inner - outer);
                (lambert * t * t, 1)
            } else {
                continue;
            };
            assert!(
                (got - expected).abs() < 1e-5 * lambert.max(1e-3),
                "pixel ({column}, {row}) at {angle:.2} degrees: {got} against {expected}"
            );
            checked[case] += 1;
        }
    }
    assert!(
        checked.iter().all(|&n| n > 50),
        "pixels per case: {checked:?}"
    );
}

/// Under the environment alone, open ground reflects exactly Kd * L in every sample; in front
/// of a tall wall half of the cosine-weighted sky is hidden, so the image converges to
/// Kd * L / 2 there.
#[test]
fn the_environment_lights_open_ground_fully_and_a_wall_s_foot_by_half() {
    let kd = Vec3::new(0.8, 0.6, 0.4);
    let sky = Vec3::new(0.5, 0.7, 1.0);
    let lit = |scene: &Scene, spp| {
        let shot = Shot {
            camera: top_down(0.5, 16),
            render: RenderSettings {
                environment: sky,
                ..settings(Shading::Lit, spp)
            },
        };
        Renderer::new(scene).render(&shot, &mut |_, _| {}).0
    };
    let open = lit(&ground(50.0, kd), 4);
    for p in &open.pixels {
        assert!((*p - kd * sky).abs().max_element() < 1e-6, "{p}");
    }
    // A wall 100 m high and wide through x = 0.2, beside the patch the camera sees
    // (x within +-0.09): every direction towards +x hits it.
    let mut walled = ground(50.0, kd);
    walled.meshes.push(Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "wall".into(),
        positions: vec![
            Vec3::new(0.2, 0.0, -50.0),
            Vec3::new(0.2, 0.0, 50.0),
            Vec3::new(0.2, 100.0, 50.0),
            Vec3::new(0.2, 100.0, -50.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![0, 0],
        ..Default::default()
    });
    let image = lit(&walled, 1024);
    let mean = image.pixels.iter().copied().sum::<Vec3>() / image.pixels.len() as f32;
    let expected = 0.5 * kd * sky;
    let error = ((mean - expected) / expected).abs().max_element();
    assert!(
        error < 0.01,
        "mean {mean} against {expected}: relative {error}"
    );
}
