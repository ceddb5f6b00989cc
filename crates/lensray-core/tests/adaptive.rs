//! Adaptive sampling (`film::adaptive`) on the CPU reference: the same settings give the same
//! sums; every pixel holds exactly the uniform render's sums at its own sample count; an image
//! with flat regions takes far fewer samples than `spp` everywhere; the error against a
//! converged reference stays within a stated bound.
//!
//! Run with `cargo test -p lensray-core --test adaptive`.

use lensray_core::film::adaptive::{min_samples, round_ends};
use lensray_core::film::compare::rmse;
use lensray_core::film::Sums;
use lensray_core::reference::Renderer;
use lensray_core::scene::builtin::default_scene;
use lensray_core::settings::{shot, ImageSettings, RenderStyle, Settings, Shot};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

/// The default scene (lit: a point light, hard shadows, sky) at 64x48.
fn default_shot(spp: u32, noise_threshold: Option<f64>, seed: u32) -> (Renderer, Shot) {
    let description = default_scene();
    let settings = description.settings.clone().overridden_by(&Settings {
        image: ImageSettings {
            width: Some(WIDTH),
            height: Some(HEIGHT),
            spp: Some(spp),
            seed: Some(seed),
            ..Default::default()
        },
        render: RenderStyle {
            noise_threshold,
            ..Default::default()
        },
        ..Default::default()
    });
    let shot = shot(&settings, &description.scene).expect("the default shot");
    (Renderer::new(&description.scene), shot)
}

fn adaptive_sums(renderer: &Renderer, shot: &Shot) -> (Sums, u64) {
    let mut sums = Sums::new(WIDTH, HEIGHT);
    let threshold = shot.render.noise_threshold.expect("a threshold");
    let (_, report) = renderer.render_adaptive(shot, threshold, &mut sums, &mut |_, _| {});
    (sums, report.samples)
}

#[test]
fn the_same_settings_give_the_same_sums() {
    let (renderer, shot) = default_shot(128, Some(0.05), 0);
    let (a, samples_a) = adaptive_sums(&renderer, &shot);
    let (b, samples_b) = adaptive_sums(&renderer, &shot);
    assert_eq!(samples_a, samples_b);
    let bits =
        |s: &Sums| -> Vec<[u32; 4]> { s.pixels.iter().map(|p| p.map(f32::to_bits)).collect() };
    assert!(bits(&a) == bits(&b), "two adaptive renders differ");
}

/// A pixel that stopped at n samples holds, bit for bit, the uniform render's sums at n spp:
/// a uniform accumulation is advanced round end by round end (a split of the range gives the
/// same sums) and every pixel that stopped there is compared.
#[test]
fn each_pixel_equals_the_uniform_render_at_its_sample_count() {
    let (spp, threshold) = (128, 0.05);
    let (renderer, shot) = default_shot(spp, Some(threshold), 3);
    let (adaptive, _) = adaptive_sums(&renderer, &shot);
    let mut uniform = Sums::new(WIDTH, HEIGHT);
    let mut done = 0;
    let mut compared = 0;
    let mut counts_seen = 0;
    for end in round_ends(threshold as f32, spp) {
        renderer.accumulate(&shot, done..end, &mut uniform, &mut |_, _| {});
        done = end;
        let mut here = 0;
        for (i, (a, u)) in adaptive.pixels.iter().zip(&uniform.pixels).enumerate() {
            if a[3] as u32 == end {
                assert_eq!(
                    a.map(f32::to_bits),
                    u.map(f32::to_bits),
                    "pixel {i} at {end} samples: adaptive {a:?}, uniform {u:?}"
                );
                here += 1;
            }
        }
        compared += here;
        counts_seen += (here > 0) as u32;
    }
    assert_eq!(
        compared,
        (WIDTH * HEIGHT) as usize,
        "a pixel's count is no round's end"
    );
    // The test means something only if pixels stopped at different counts.
    assert!(
        counts_seen >= 3,
        "pixels stopped at {counts_seen} counts only"
    );
}

/// The default scene's sky, ground and sphere interiors are flat: they stop at the minimum,
/// while the edges and shadows go on to the cap.
#[test]
fn flat_regions_take_fewer_samples() {
    let (spp, threshold) = (256, 0.05);
    let (renderer, shot) = default_shot(spp, Some(threshold), 0);
    let (sums, samples) = adaptive_sums(&renderer, &shot);
    let uniform = (WIDTH * HEIGHT * spp) as u64;
    let counts: Vec<u32> = sums.pixels.iter().map(|p| p[3] as u32).collect();
    let at_min = counts
        .iter()
        .filter(|&&n| n == min_samples(threshold as f32, spp))
        .count();
    let at_cap = counts.iter().filter(|&&n| n == spp).count();
    assert!(
        samples * 3 < uniform,
        "{samples} samples, uniform takes {uniform}"
    );
    assert!(at_min * 2 > counts.len(), "{at_min} pixels at the minimum");
    assert!(at_cap > 0, "no pixel reached the cap");
    assert_eq!(samples, counts.iter().map(|&n| n as u64).sum::<u64>());
}

/// Against a 2048-spp reference, the adaptive render (threshold 0.02, cap 256) is within 10 %
/// of the uniform render's error at the cap while taking at most half its samples.
#[test]
fn error_stays_near_the_uniform_render_at_the_cap() {
    let (renderer, reference_shot) = default_shot(2048, None, 101);
    let (reference, _) = renderer.render(&reference_shot, &mut |_, _| {});
    let (_, uniform_shot) = default_shot(256, None, 0);
    let (uniform, _) = renderer.render(&uniform_shot, &mut |_, _| {});
    let (_, adaptive_shot) = default_shot(256, Some(0.02), 0);
    let (sums, samples) = adaptive_sums(&renderer, &adaptive_shot);
    let (e_uniform, e_adaptive) = (rmse(&uniform, &reference), rmse(&sums.image(), &reference));
    assert!(
        e_adaptive <= 1.1 * e_uniform,
        "adaptive RMSE {e_adaptive:.5}, uniform {e_uniform:.5}"
    );
    let uniform_samples = (WIDTH * HEIGHT * 256) as u64;
    assert!(
        samples * 2 <= uniform_samples,
        "{samples} samples, uniform {uniform_samples}"
    );
}
