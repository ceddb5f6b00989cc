//! Which paths a bench runs: those named, checked against what the machine can run before any
//! work starts, or by default every path it can run (the GPU paths the device supports, then
//! the CPU).

use anyhow::{bail, Context, Result};

use super::options::BenchOptions;
use super::scenes::BenchScene;
use crate::paths::PathKind;
use crate::paths::{self, Choice, DeviceKind, PathOptions};
use lensray_core::settings::Shot;
use lensray_vulkan::{GpuOptions, GpuRenderer};

/// How to open `kind` for the bench: GPU paths on the Vulkan device the options name; the CPU
/// path without the Vulkan options (which concern only the GPU paths here).
pub fn path_options(kind: PathKind, options: &BenchOptions) -> PathOptions {
    PathOptions {
        path: kind.into(),
        device: kind.device().into(),
        gpu: if kind.is_gpu() {
            options.gpu
        } else {
            GpuOptions::default()
        },
    }
}

/// The paths to run, in order, without repeats. `auto` becomes the path `--path auto` would
/// take (measured by `paths::open`), said in the log with why.
pub fn paths_to_run(
    options: &BenchOptions,
    scene: &BenchScene,
    shot: &Shot,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<PathKind>> {
    let device = options.device;
    // The Vulkan options against --device; each path against --device (the Vulkan options
    // concern only the GPU paths of a list, so the CPU path takes them).
    let asked = PathOptions {
        path: Choice::Auto,
        device,
        gpu: options.gpu,
    };
    asked.device_to_use("--paths")?;
    for &path in &options.paths {
        PathOptions {
            path,
            device,
            gpu: GpuOptions::default(),
        }
        .device_to_use("--paths")?;
    }
    // A named path that cannot sample adaptively is refused before a device is opened.
    refuse_named_unadaptive(options, shot)?;
    let cpu = Choice::Only(PathKind::Cpu);
    let wants_gpu = device != Choice::Only(DeviceKind::Cpu)
        && (options.paths.is_empty() || options.paths.iter().any(|p| *p != cpu));
    let supported = if wants_gpu {
        // Under --device auto with nothing asked of Vulkan, no device means the CPU alone.
        let may_fall_back = device == Choice::Auto
            && asked.gpu_option().is_none()
            && options
                .paths
                .iter()
                .all(|p| *p == cpu || *p == Choice::Auto);
        gpu_paths(options.gpu, may_fall_back, log)?
    } else {
        None
    };

    let mut kinds = Vec::new();
    if options.paths.is_empty() {
        if let Some((_, gpu_kinds)) = &supported {
            // The ray-tracing pipeline where ray queries serve only when asked for: the
            // device's paths are those it opens for (`DeviceReport::opened_traversals`).
            let asked_only = |k: &&PathKind| {
                **k == PathKind::RtPipeline && gpu_kinds.contains(&PathKind::RayQuery)
            };
            kinds.extend(gpu_kinds.iter().filter(|k| !asked_only(k)));
        }
        if device != Choice::Only(DeviceKind::Gpu) {
            kinds.push(PathKind::Cpu);
        }
    }
    for &choice in &options.paths {
        let kind = match choice.only() {
            Some(PathKind::Cpu) => PathKind::Cpu,
            Some(kind) => {
                let (name, gpu_kinds) = supported.as_ref().context("no Vulkan device")?;
                if !gpu_kinds.contains(&kind) {
                    let runs: Vec<&str> = gpu_kinds.iter().map(|k| k.name()).collect();
                    bail!(
                        "--paths {kind}: the Vulkan device {name} cannot run it (it runs: {})",
                        if runs.is_empty() {
                            "none".into()
                        } else {
                            runs.join(", ")
                        }
                    );
                }
                kind
            }
            None => auto_path(options, scene, shot, log)?,
        };
        kinds.push(kind);
    }
    adaptive_only(&mut kinds, shot, log)?;
    let mut seen = Vec::new();
    kinds.retain(|k| {
        let new = !seen.contains(k);
        seen.push(*k);
        new
    });
    if kinds.is_empty() {
        bail!("no path to run: the Vulkan device supports none of lensray's GPU paths");
    }
    Ok(kinds)
}

/// With adaptive sampling (`shot`'s noise threshold), a path named in `--paths` that cannot is
/// an error.
fn refuse_named_unadaptive(options: &BenchOptions, shot: &Shot) -> Result<()> {
    if shot.render.noise_threshold.is_none() || shot.render.shading.is_aov() {
        return Ok(());
    }
    let named = options.paths.iter().filter_map(|p| p.only());
    if let Some((kind, why)) = named
        .filter_map(|k| Some((k, k.adaptive_refusal()?)))
        .next()
    {
        bail!("--paths {kind} does not sample adaptively (--noise-threshold): {why}");
    }
    Ok(())
}

/// With adaptive sampling (`shot`'s noise threshold), the paths that sample adaptively: those
/// that cannot are left out with a notice (one named is refused before, by
/// `refuse_named_unadaptive`).
fn adaptive_only(kinds: &mut Vec<PathKind>, shot: &Shot, log: &mut dyn FnMut(&str)) -> Result<()> {
    if shot.render.noise_threshold.is_none() || shot.render.shading.is_aov() {
        return Ok(());
    }
    let refused: Vec<&str> = kinds
        .iter()
        .filter(|k| k.adaptive_refusal().is_some())
        .map(|k| k.name())
        .collect();
    if !refused.is_empty() {
        log(&format!(
            "notice: --noise-threshold: leaving out {}, which do not sample adaptively (docs/adaptive.md)",
            refused.join(" and ")
        ));
        kinds.retain(|k| k.adaptive_refusal().is_none());
    }
    Ok(())
}

/// The Vulkan device's name and the GPU paths it supports; `None` when there is no usable
/// device and falling back to the CPU is allowed (with a notice).
fn gpu_paths(
    gpu: GpuOptions,
    may_fall_back: bool,
    log: &mut dyn FnMut(&str),
) -> Result<Option<(String, Vec<PathKind>)>> {
    let renderer = match GpuRenderer::new(&GpuOptions {
        traversal: None,
        ..gpu
    }) {
        Ok(renderer) => renderer,
        Err(error) if may_fall_back => {
            log(&format!(
                "notice: benchmarking the CPU path only: no usable GPU ({:#})",
                anyhow::Error::from(error)
            ));
            return Ok(None);
        }
        Err(error) => return Err(anyhow::Error::from(error).context("the Vulkan device")),
    };
    // Every traversal the device can run: the ray-tracing pipeline's too where ray queries
    // serve (benchmarked when asked for).
    let traversals = renderer.device_report().traversals();
    let mut kinds: Vec<PathKind> = [PathKind::RayQuery, PathKind::RtPipeline, PathKind::Software]
        .into_iter()
        .filter(|&k| k.traversal().is_some_and(|t| traversals.contains(&t)))
        .collect();
    // The hybrid and raster paths trace with whichever traversal the device has (the
    // fastest).
    if !kinds.is_empty() {
        kinds.extend([PathKind::Hybrid, PathKind::Raster]);
    }
    let name = renderer.device_name();
    renderer.close()?;
    Ok(Some((name, kinds)))
}

/// The path `--path auto` takes for this shot and device.
fn auto_path(
    options: &BenchOptions,
    scene: &BenchScene,
    shot: &Shot,
    log: &mut dyn FnMut(&str),
) -> Result<PathKind> {
    let path_options = PathOptions {
        path: Choice::Auto,
        device: options.device,
        gpu: options.gpu,
    };
    let opened = paths::open(&path_options, &scene.description.scene, shot)?;
    let kind = opened.path.kind();
    log(&format!("--paths auto: {kind} ({})", opened.why));
    opened.path.close()?;
    Ok(kind)
}
