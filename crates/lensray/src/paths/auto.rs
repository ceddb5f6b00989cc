//! `--path auto`: which path renders a shot on an open Vulkan device. The traversal paths it
//! was opened for (`rayquery`, `software`, and `rtpipeline` where ray queries are absent) are
//! timed on a small render of the shot, the fastest is the one the
//! hybrid and raster paths trace with, and then the fastest of that traversal, the hybrid and
//! the raster path (where its ghost copies would not show) is kept.

use std::time::Instant;

use anyhow::{bail, Result};

use super::calibration;
use crate::paths::PathKind;
use lensray_core::camera::Camera;
use lensray_core::film::Accumulation;
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{Estimator, GpuRenderer};

/// `auto` on an open Vulkan device with a scene loaded: the only traversal it runs, the fastest
/// of the device's cached calibration (`calibration`), or else the fastest on a small render of
/// `shot`. Sets it, and says which and why.
pub fn pick_traversal(renderer: &mut GpuRenderer, shot: &Shot) -> Result<(PathKind, String)> {
    let kinds = traversal_kinds(renderer);
    let (kind, why) = match (kinds.as_slice(), cached_fastest(renderer, &kinds, shot)) {
        ([], _) => bail!(
            "the Vulkan device {} runs no lensray path",
            renderer.device_name()
        ),
        (_, Some(kind)) => (
            kind,
            "auto: the fastest traversal of this device's calibration (cached)".to_string(),
        ),
        ([only], None) => (
            *only,
            "auto: the only path this device supports".to_string(),
        ),
        (_, None) => fastest(renderer, &kinds, shot)?,
    };
    renderer.set_traversal(kind.traversal().expect("a GPU path"))?;
    Ok((kind, why))
}

/// Sets the traversal the device's cached calibration picks for `shot`, if one is cached:
/// before a scene is loaded, so that only that traversal's pipeline is built for it.
pub(super) fn preset_cached_traversal(renderer: &mut GpuRenderer, shot: &Shot) -> Result<()> {
    let kinds = traversal_kinds(renderer);
    if let Some(kind) = cached_fastest(renderer, &kinds, shot) {
        renderer.set_traversal(kind.traversal().expect("a GPU path"))?;
    }
    Ok(())
}

fn traversal_kinds(renderer: &GpuRenderer) -> Vec<PathKind> {
    renderer
        .traversals()
        .into_iter()
        .map(PathKind::of_traversal)
        .collect()
}

/// The fastest of `kinds` for `shot` by the device's cached calibration, if one is cached.
fn cached_fastest(renderer: &GpuRenderer, kinds: &[PathKind], shot: &Shot) -> Option<PathKind> {
    calibration::load(&calibration::key(&renderer.device_report()))
        .and_then(|c| c.fastest(kinds.iter().copied(), pixel_samples(shot)))
        .map(|(kind, _)| kind)
}

/// The pixel-samples of `shot` (an AOV: one per pixel).
pub(super) fn pixel_samples(shot: &Shot) -> u64 {
    let spp = if shot.render.shading.is_aov() {
        1
    } else {
        shot.render.spp
    };
    u64::from(shot.camera.width) * u64::from(shot.camera.height) * u64::from(spp)
}

/// Width of the calibration render of `auto` (its height keeps the shot's aspect).
const CALIBRATION_WIDTH: u32 = 96;
/// Samples per pixel of each timed calibration render.
const CALIBRATION_SPP: u32 = 2;

/// Times each path on a small render of the shot (lit, as the most work; after a warm-up that
/// compiles the pipeline) and returns the fastest, with the measured ratio.
fn fastest(
    renderer: &mut GpuRenderer,
    kinds: &[PathKind],
    shot: &Shot,
) -> Result<(PathKind, String)> {
    let calibration = calibration_shot(shot);
    let small = &calibration.camera;
    let mut times = Vec::new();
    for &kind in kinds {
        renderer.set_traversal(kind.traversal().expect("a GPU path"))?;
        let mut seconds = f64::INFINITY;
        for round in 0..3 {
            let before = renderer.timings();
            let mut accumulation = Accumulation::new(small.width, small.height);
            renderer.add_samples(
                &calibration,
                Estimator::Traced,
                0..calibration.render.spp,
                &mut accumulation,
                &mut |_, _| {},
            )?;
            let after = renderer.timings();
            // Round 0 compiles the pipeline (its first dispatch is timed apart).
            if round > 0 {
                seconds = seconds.min((after.trace_gpu_ms - before.trace_gpu_ms) * 1e-3);
            }
        }
        times.push((kind, seconds));
    }
    times.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (best, best_s) = times[0];
    let (next, next_s) = times[1];
    let why = format!(
        "auto: {best} traced a {}x{} calibration {:.2}x faster than {next}",
        small.width,
        small.height,
        next_s / best_s.max(1e-12)
    );
    Ok((best, why))
}

/// The calibration shot of `auto` for `shot`: `CALIBRATION_WIDTH` pixels wide (the shot's
/// aspect), lit, `CALIBRATION_SPP` samples.
fn calibration_shot(shot: &Shot) -> Shot {
    let (camera, settings) = (&shot.camera, &shot.render);
    let height = ((u64::from(CALIBRATION_WIDTH) * u64::from(camera.height))
        / u64::from(camera.width.max(1)))
    .max(1) as u32;
    let small = camera.with_resolution(CALIBRATION_WIDTH, height);
    let lit = RenderSettings {
        shading: if settings.shading.is_aov() {
            Shading::Lit
        } else {
            settings.shading
        },
        spp: CALIBRATION_SPP,
        ..*settings
    };
    Shot {
        camera: small,
        render: lit,
    }
}

/// The largest circle of confusion (radius, pixels of the shot) of the surfaces the shot sees,
/// from the G-buffer of the calibration camera.
fn largest_coc_pixels(renderer: &mut GpuRenderer, camera: &Camera, small: &Camera) -> Result<f32> {
    let gbuffer = renderer.render_gbuffer(&small.for_rasterizing_rays(), glam::Vec3::ZERO)?;
    // A pixel of the small camera covers `scale` of the shot's, the same screen window.
    let scale = camera.width as f32 / small.width as f32;
    let coc = lensray_core::camera::CocLens::of(camera);
    let mut largest = 0f32;
    for (i, (&z, &covered)) in gbuffer.view_depth.iter().zip(&gbuffer.coverage).enumerate() {
        if covered {
            let (x, y) = (i as u32 % small.width, i as u32 / small.width);
            let centre = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5) * scale;
            largest = largest.max(coc.radius_pixels(centre, z));
        }
    }
    Ok(largest)
}

/// `auto` with every GPU path: the device's fastest traversal path (`pick_traversal`), the
/// hybrid and the raster path, timed by the wall clock on the calibration shot (their plans
/// and raster passes included), the fastest kept. The raster path is left out where the shot's
/// circles of confusion reach `sqrt(spp) / 2` pixels: there its samples, shared by every
/// pixel, show as ghost copies instead of noise (docs/raster.md). Leaves the renderer on the
/// traversal the hybrid and raster paths trace with; says which path and why.
pub fn pick_path(renderer: &mut GpuRenderer, shot: &Shot) -> Result<(PathKind, String)> {
    let (traced, traced_why) = pick_traversal(renderer, shot)?;
    let calibration = calibration_shot(shot);
    let small = &calibration.camera;
    // The hybrid's error at equal spp is the traced paths' (unlit and lit, docs/hybrid.md), so
    // its time at equal spp is the measure.
    let mut candidates = vec![traced, PathKind::Hybrid];
    let coc = largest_coc_pixels(renderer, &shot.camera, small)?;
    let ghost_free = (shot.render.spp as f32).sqrt() / 2.0;
    let raster_note = if coc <= ghost_free {
        candidates.push(PathKind::Raster);
        String::new()
    } else {
        format!(
            "; raster left out: circles of confusion up to {coc:.1} px would show as ghost \
             copies at {} spp",
            shot.render.spp
        )
    };
    let mut times = Vec::new();
    for &kind in &candidates {
        let mut seconds = f64::INFINITY;
        // Round 0 compiles pipelines and makes the passes' images.
        for round in 0..3 {
            let mut accumulation = Accumulation::new(small.width, small.height);
            let start = Instant::now();
            renderer.add_samples(
                &calibration,
                kind.estimator(),
                0..calibration.render.spp,
                &mut accumulation,
                &mut |_, _| {},
            )?;
            renderer.read_sums(&mut accumulation)?;
            if round > 0 {
                seconds = seconds.min(start.elapsed().as_secs_f64());
            }
        }
        times.push((kind, seconds));
    }
    times.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (best, best_s) = times[0];
    let (next, next_s) = times[1];
    let traversal = traced.traversal().expect("a traversal path");
    let why = format!(
        "auto: {best} rendered a {}x{} calibration {:.2}x faster than {next}{}; {} \
         {traversal} ({})",
        small.width,
        small.height,
        next_s / best_s.max(1e-12),
        raster_note,
        if best == traced {
            "traversal"
        } else {
            "traces with"
        },
        traced_why.trim_start_matches("auto: "),
    );
    Ok((best, why))
}
