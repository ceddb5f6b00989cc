//! A metal's map draw resampled among `SKY_CANDIDATES` directions (`reference/sky.rs:
//! sky_draw`) estimates the light the map's power alone does: both are unbiased, so their images
//! agree within their noise, over the whole image and block by block; and on glossy metals the
//! resampled draw is the less noisy of the two at the same samples (docs/environment.md).

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use lensray_core::film::compare::rmse;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::scene::environment::EnvironmentMap;
use lensray_core::scene::{default_scene, EnvironmentLight, Scene};
use lensray_core::settings::{
    shot, EnvironmentSetting, ImageSettings, RenderStyle, Settings, Shot,
};

/// The default scene's materials made metals of roughness `roughness` under the studio map
/// (its small bright lamps), with no lights of its own.
fn metals_under_studio(roughness: f32) -> Scene {
    let mut scene = default_scene().scene;
    for m in &mut scene.materials {
        m.specular = 1.0;
        m.metallic = 1.0;
        m.roughness = roughness;
    }
    scene.lights.clear();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/environments/studio.hdr");
    let (map, _) = EnvironmentMap::load(&path).expect("the studio map");
    scene.environment = Some(Arc::new(EnvironmentLight::new(map)));
    scene
}

fn the_shot(scene: &Scene, spp: u32, seed: u32) -> Shot {
    let settings = Settings {
        image: ImageSettings {
            width: Some(32),
            height: Some(24),
            ..ImageSettings::default()
        },
        render: RenderStyle {
            environment: Some(EnvironmentSetting::Map("studio".into())),
            ..RenderStyle::default()
        },
        ..Settings::default()
    };
    let mut shot = shot(&settings, scene).expect("the shot");
    shot.render.spp = spp;
    shot.render.seed = seed;
    shot
}

fn render(renderer: &Renderer, shot: &Shot) -> Image {
    renderer.render(shot, &mut |_, _| {}).0
}

/// The mean of each 8 x 8 block's pixels (their channels summed), row by row.
fn block_means(image: &Image) -> Vec<f64> {
    let mut means = Vec::new();
    for by in (0..image.height).step_by(8) {
        for bx in (0..image.width).step_by(8) {
            let mut sum = 0.0;
            for y in by..by + 8 {
                for x in bx..bx + 8 {
                    let p: Vec3 = image.get(x, y);
                    sum += f64::from(p.x + p.y + p.z);
                }
            }
            means.push(sum / 64.0);
        }
    }
    means
}

#[test]
fn a_maps_resampled_draw_agrees_with_its_power_alone() {
    let scene = metals_under_studio(0.3);
    let shot = the_shot(&scene, 1024, 3);
    let resampled = block_means(&render(&Renderer::new(&scene), &shot));
    let power = block_means(&render(
        &Renderer::new(&scene).with_sky_candidates(1),
        &shot,
    ));
    let whole = |m: &[f64]| m.iter().sum::<f64>() / m.len() as f64;
    let (a, b) = (whole(&resampled), whole(&power));
    println!("image mean: resampled {a:.5}, power alone {b:.5}");
    assert!(
        (a / b - 1.0).abs() < 0.006,
        "the image's mean: resampled {a:.5} against the power alone's {b:.5}"
    );
    for (k, (a, b)) in resampled.iter().zip(&power).enumerate() {
        println!("block {k}: resampled {a:.5}, power alone {b:.5}");
        assert!(
            (a / b - 1.0).abs() < 0.02,
            "block {k}: resampled {a:.5} against the power alone's {b:.5}"
        );
    }
}

/// The image with each channel clamped at 1: what a display shows of it without a tone map,
/// so that the few pixels that see a lamp (in thousands) do not stand for the noise.
fn displayed(mut image: Image) -> Image {
    for p in &mut image.pixels {
        *p = p.min(Vec3::ONE);
    }
    image
}

#[test]
fn a_maps_resampled_draw_is_less_noisy_on_gloss() {
    let scene = metals_under_studio(0.3);
    let reference = displayed(render(&Renderer::new(&scene), &the_shot(&scene, 512, 1000)));
    let shot = the_shot(&scene, 16, 1);
    let resampled = rmse(
        &displayed(render(&Renderer::new(&scene), &shot)),
        &reference,
    );
    let power = rmse(
        &displayed(render(&Renderer::new(&scene).with_sky_candidates(1), &shot)),
        &reference,
    );
    println!("16 spp against 512: RMSE resampled {resampled:.5}, power alone {power:.5}");
    assert!(
        resampled < 0.75 * power,
        "RMSE at 16 spp: resampled {resampled:.5} against the power alone's {power:.5}"
    );
}
