//! Textures and alpha on every path: the GPU paths render the textured test card as the CPU
//! reference does (texture filtering, wrap modes, transforms, masks, blended cuts and shadows
//! through masks), and a texture at the focal plane stays as sharp as through a pinhole.

mod gpu_support;

use glam::{Vec2, Vec3};
use gpu_support::{assert_gpu_paths_match_cpu, render_scene, settings, write_png};
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::scene::test_card::test_card;
use lensray_core::scene::{Light, Scene};
use lensray_core::settings::{Shading, Shot};

fn card_camera(lens: LensParams, width: u32, height: u32) -> Camera {
    camera_towards(Vec3::new(0.0, 0.8, 0.0), lens, width, height)
}

fn camera_towards(target: Vec3, lens: LensParams, width: u32, height: u32) -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, 1.2, 4.0),
        target,
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 50.0 },
        lens,
        near: 0.1,
        far: 100.0,
        width,
        height,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera")
}

fn shot(shading: Shading, spp: u32) -> Shot {
    let lens = LensParams::ThinLens {
        aperture_radius: 0.06,
        focus_distance: 4.3,
    };
    Shot {
        camera: card_camera(lens, 80, 60),
        render: settings(shading, spp),
    }
}

/// The test card under one point light.
fn lit_card() -> Scene {
    Scene {
        lights: vec![Light::point(Vec3::new(1.5, 3.0, 3.0), Vec3::splat(25.0))],
        ..test_card()
    }
}

/// Every traced GPU path and the raster path render the lit, textured, alpha-tested card as the
/// CPU reference does, as do the G-buffer's albedo AOV and the CPU's.
#[test]
fn gpu_paths_render_textures_and_alpha_as_the_cpu_does() {
    let test = "gpu_paths_render_textures_and_alpha_as_the_cpu_does";
    for shading in [Shading::Lit, Shading::Albedo] {
        let name = format!("textures-{shading:?}");
        assert_gpu_paths_match_cpu(test, &name, &lit_card(), &shot(shading, 8));
    }
}

/// The gradient card at the focal plane reads the same texture level through a wide aperture as
/// through a pinhole: its pixels match the pinhole render's (the lens only spreads what is off
/// the focal plane), where a footprint that included the lens would blur it.
#[test]
fn a_texture_in_focus_is_as_sharp_as_through_a_pinhole() {
    let test = "a_texture_in_focus_is_as_sharp_as_through_a_pinhole";
    // The card alone, facing the camera square on at depth 4.5.
    let mut card = test_card();
    card.meshes = vec![card.meshes.swap_remove(1)];
    let (width, height) = (96, 72);
    let level = Vec3::new(0.0, 1.2, 0.0);
    let unlit = |lens| Shot {
        camera: camera_towards(level, lens, width, height),
        render: settings(Shading::Unlit, 64),
    };
    let wide = LensParams::ThinLens {
        aperture_radius: 0.25,
        focus_distance: 4.5,
    };
    let cpu = PathChoice::Only(PathKind::Cpu);
    let (Some(pinhole), Some(blurred)) = (
        render_scene(test, cpu, &card, &unlit(LensParams::Pinhole)),
        render_scene(test, cpu, &card, &unlit(wide)),
    ) else {
        return;
    };
    // The card's pixels, two pixels in from its edges (the only places the lens may spread
    // the background over it).
    let camera = camera_towards(level, LensParams::Pinhole, width, height);
    let corner = camera.project(Vec3::new(-1.6, 1.6, -0.5));
    let far = camera.project(Vec3::new(-0.4, 0.2, -0.5));
    let (lo, hi) = (
        Vec2::new(corner.x, corner.y) + 2.0,
        Vec2::new(far.x, far.y) - 2.0,
    );
    let mut worst = 0.0f32;
    let mut count = 0;
    for y in lo.y.ceil() as u32..hi.y.floor() as u32 {
        for x in lo.x.ceil() as u32..hi.x.floor() as u32 {
            let i = (y * width + x) as usize;
            worst = worst.max((pinhole.pixels[i] - blurred.pixels[i]).abs().max_element());
            count += 1;
        }
    }
    assert!(count > 200, "{count} card pixels");
    if worst > 0.01 {
        write_png(&pinhole, "texture-focus-pinhole.png");
        write_png(&blurred, "texture-focus-wide.png");
        panic!("the in-focus card differs from the pinhole's by {worst} at most");
    }
}
