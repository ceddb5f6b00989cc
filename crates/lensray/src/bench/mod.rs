//! `lensray bench`: the render paths compared on equal terms. Each path renders the same shot
//! after a warm-up, N times; the report gives its time (median and spread), rays, memory, and
//! its error against a converged reference, so paths can be compared at equal error as well
//! as at equal samples. A sweep (spp, resolution, triangles) repeats this over a range of work.
//!
//! Files: `options` (what to measure), `choose` (which paths), `scenes`, `sweep` (the points),
//! `reference` (the cached converged image), `focus` (how much of the shot is in focus), `lens`
//! (the lens sweep's pass shares and costs per camera ray), `movements` (the movements sweep's
//! shots), `runs` (timing the paths at one point), `report` (the results, also the JSON file),
//! `camera` (the shot's camera in it), `table`, `plot`; the machine it ran on is
//! `crate::machine`.

pub mod camera;
pub mod choose;
pub mod focus;
pub mod lens;
pub mod movements;
pub mod options;
pub mod plot;
pub mod reference;
pub mod report;
pub mod runs;
pub mod scenes;
pub mod sweep;
pub mod table;

use std::rc::Rc;

use anyhow::{bail, ensure, Context, Result};

use crate::lens_flare;
use crate::paths::{self, OpenedPath};
use crate::paths::{PathKind, RenderPath};
use focus::FocusInfo;
use lens::LensPoint;
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::settings::exposure;
use lensray_core::settings::Shot;
use movements::MovementsPoint;
use options::{BenchOptions, SceneChoice, SweepKind};
use reference::Reference;
use report::{BenchReport, PathInfo, PointReport, SceneInfo, SettingsInfo};
use runs::Measurement;
use scenes::BenchScene;
use sweep::{BenchLens, SweepValue};

/// Runs the bench `options` describe; `log` receives progress and notices (stderr on the
/// command line).
pub fn run(options: &BenchOptions, log: &mut dyn FnMut(&str)) -> Result<BenchReport> {
    ensure!(options.repeat >= 1, "--repeat must be at least 1");
    ensure!(
        options.reference_spp >= 2,
        "--reference-spp must be at least 2"
    );
    let values = sweep::values(options.sweep, options.sweep_points.as_deref(), options.spp)?;
    let flared = options.flare.ghosts || options.flare.starburst;
    if flared && options.sweep.is_some() {
        bail!("--flare and --starburst time one point against its render: they take no --sweep or --plot");
    }
    if options.sweep == Some(SweepKind::Triangles) && options.scene != SceneChoice::default_scene()
    {
        bail!("--sweep triangles renders generated scenes: it takes no --scene or --scene-file");
    }
    if options.sweep == Some(SweepKind::Lens) && options.aperture_radius.is_some() {
        bail!("--sweep lens: the lenses set the aperture (--f-number stops them down); it takes no --aperture-radius");
    }
    let max_spp = values
        .iter()
        .map(|v| spp_of(*v, options))
        .max()
        .unwrap_or(options.spp);
    if options.reference_spp < 4 * max_spp {
        log(&format!(
            "notice: --reference-spp {} is less than 4x the {max_spp} spp measured: errors near the reference's own are not meaningful",
            options.reference_spp
        ));
    }

    let base = scenes::load(&options.scene, options.dense_triangles, options.scene_units)?;
    let units = base.description.units;
    if units != lensray_core::scene::units::SceneUnits::M {
        log(&format!(
            "scene units: {units}: the scene and its lengths scaled by {} to metres",
            units.metres()
        ));
    }
    let base_shot = bench_shot(&base, options, base_value(options, &values))?;
    lens_flare::flare_of(options.flare, &base_shot)?;
    let mut kinds = choose::paths_to_run(options, &base, &base_shot, log)?;
    if options.sweep == Some(SweepKind::Lens) {
        kinds = lens_paths(options, kinds, log)?;
    }
    let mut report = BenchReport {
        schema: report::SCHEMA,
        lensray_version: env!("CARGO_PKG_VERSION"),
        machine: crate::machine::describe(),
        scene: SceneInfo {
            name: base.name.clone(),
            triangles: base.triangles,
            load: report::SceneLoad::of(&base.description),
        },
        settings: SettingsInfo {
            width: options.width,
            height: options.height,
            spp: options.spp,
            noise_threshold: base_shot.render.noise_threshold,
            shading: base_shot.render.shading,
            sampler: base_shot.render.sampler,
            seed: base_shot.render.seed,
            aperture_radius: base_shot.camera.lens.first_order().aperture_radius,
            focus_distance: base_shot.camera.lens.first_order().focus_distance,
            repeat: options.repeat,
            reference_spp: options.reference_spp,
        },
        camera: camera::CameraInfo::of(&base_shot.camera),
        sweep: options.sweep,
        paths: Vec::new(),
        points: Vec::new(),
    };

    // A triangle sweep renders one scene per point; the other sweeps share the base scene,
    // and each path is opened once for all of its points.
    let groups: Vec<Vec<SweepValue>> = if options.sweep == Some(SweepKind::Triangles) {
        values.iter().map(|v| vec![*v]).collect()
    } else {
        vec![values]
    };
    let mut base = Some(base);
    for group in groups {
        let scene = match (group[0], base.take()) {
            (SweepValue::Triangles(n), _) => {
                log(&format!("generating a scene of at least {n} triangles"));
                scenes::dense(n, options.scene_units)?
            }
            (_, Some(base)) => base,
            (_, None) => unreachable!("one group unless the sweep is of triangles"),
        };
        let points = measure_group(options, &kinds, &scene, &group, &mut report.paths, log)?;
        report.points.extend(points);
    }
    if let Some(first) = report.points.first() {
        report.camera = first.camera.clone();
    }
    if options.sweep == Some(SweepKind::Triangles) {
        report.scene = SceneInfo {
            name: "generated dense".into(),
            triangles: report.points.first().map_or(0, |p| p.triangles),
            load: None,
        };
    }
    Ok(report)
}

/// The point whose shot the paths are chosen for (and `auto` picks on): the shot as asked for.
fn base_value(options: &BenchOptions, values: &[SweepValue]) -> SweepValue {
    match options.sweep {
        // A real lens (`auto` picks among the paths that trace one).
        Some(SweepKind::Lens) => values
            .iter()
            .copied()
            .find(|v| matches!(v, SweepValue::Lens(l) if l.real))
            .unwrap_or(values[0]),
        // The plain shot (the options' movements are the moved points').
        Some(SweepKind::Movements) => values[0],
        _ => SweepValue::Spp(options.spp),
    }
}

/// The shot at one point: the scene's settings with the options' and the point's on top.
fn bench_shot(scene: &BenchScene, options: &BenchOptions, value: SweepValue) -> Result<Shot> {
    let mut settings = scene.description.settings.clone();
    let (width, height) = match value {
        SweepValue::Resolution { width, height } => (width, height),
        _ => (options.width, options.height),
    };
    settings.image.width = Some(width);
    settings.image.height = Some(height);
    settings.image.spp = Some(spp_of(value, options));
    settings.render.noise_threshold = options.noise_threshold.or(settings.render.noise_threshold);
    settings.image.sampler = options.sampler.or(settings.image.sampler);
    settings.image.seed = options.seed.or(settings.image.seed);
    settings.render.shading = Some(options.shading);
    // The options' lengths are in the scene's units, its settings already in metres.
    let metres_per_unit = scene.description.units.metres();
    if let Some(radius) = options.aperture_radius.map(|r| r * metres_per_unit) {
        // As `render --aperture-radius`: the radius replaces a physical lens's.
        settings.camera.aperture_radius = Some(radius);
        settings.camera.focal_length_mm = None;
        settings.camera.f_number = None;
        settings.camera.sensor_height_mm = None;
    }
    settings.camera.focus_distance = options
        .focus_distance
        .map(|d| d * metres_per_unit)
        .or(settings.camera.focus_distance);
    settings.camera.f_number = options.f_number.or(settings.camera.f_number);
    movements::set(&mut settings.camera, options, value);
    if let SweepValue::Lens(lens) = value {
        // As `render --lens NAME`: the real lens replaces the scene's lens; the field of view
        // follows from it.
        settings.camera.lens.prescription = Some(lens.name().to_string());
        settings.camera.aperture_radius = None;
        settings.camera.focal_length_mm = None;
        settings.camera.f_number = options.f_number;
    }
    let mut shot = lensray_core::settings::shot(&settings, &scene.description.scene)
        .with_context(|| format!("scene {}", scene.description.source))?;
    if let SweepValue::Aperture(aperture) = value {
        // The shape replaces the scene's; the radius stays.
        let aperture = aperture.shape().build()?;
        shot.camera = shot.camera.with_aperture(aperture)?;
    }
    if let SweepValue::Lens(BenchLens { real: false, .. }) = value {
        // The first-order model the camera holds (same framing, pupil and focus), untraced.
        shot.camera.lens = shot.camera.lens.first_order_only();
    }
    Ok(shot)
}

fn spp_of(value: SweepValue, options: &BenchOptions) -> u32 {
    match value {
        SweepValue::Spp(spp) => spp,
        _ => options.spp,
    }
}

/// The points of one scene: their references, then every path opened once and, point by point,
/// measured in turns.
fn measure_group(
    options: &BenchOptions,
    kinds: &[PathKind],
    scene: &BenchScene,
    values: &[SweepValue],
    paths_seen: &mut Vec<PathInfo>,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<PointReport>> {
    let shots: Vec<Shot> = values
        .iter()
        .map(|v| bench_shot(scene, options, *v))
        .collect::<Result<_>>()?;
    let references = group_references(options, scene, &shots, log)?;
    let mut opened = open_paths(options, kinds, scene, &shots[0], paths_seen)?;
    let group = Group {
        options,
        kinds,
        scene,
        values,
        shots: &shots,
        references: &references,
    };
    let in_turns = matches!(
        options.sweep,
        Some(SweepKind::Aperture) | Some(SweepKind::Lens) | Some(SweepKind::Movements)
    );
    let mut results = if in_turns {
        measure_in_turns(&group, &mut opened, log)?
    } else {
        measure_point_by_point(&group, &mut opened, log)?
    };
    for (path, kind) in opened.into_iter().zip(kinds) {
        path.close().with_context(|| format!("--paths {kind}"))?;
    }
    let lenses = if options.sweep == Some(SweepKind::Lens) {
        lens_points(values, &shots, &mut results, log)
    } else {
        vec![None; values.len()]
    };

    let cpu = CpuRenderer::new(&scene.description.scene);
    Ok(shots
        .iter()
        .zip(references)
        .zip(results)
        .zip(values)
        .zip(lenses)
        .map(|((((s, reference), mut results), value), lens)| {
            set_speedups(&mut results);
            let focus = FocusInfo::of(&cpu, s);
            let mut point = point_report(scene, s, &reference, focus, results);
            match *value {
                SweepValue::Aperture(a) => point.aperture = Some(a),
                SweepValue::Movements(m) => {
                    point.movements = Some(MovementsPoint::of(m, options, &s.camera));
                }
                _ => {}
            }
            point.lens = lens;
            point
        })
        .collect())
}

/// One scene's points as they are measured: what with, and against which references.
struct Group<'a> {
    options: &'a BenchOptions,
    kinds: &'a [PathKind],
    scene: &'a BenchScene,
    values: &'a [SweepValue],
    shots: &'a [Shot],
    references: &'a [Rc<Reference>],
}

/// Each shot's converged reference; points that differ only in spp share one.
fn group_references(
    options: &BenchOptions,
    scene: &BenchScene,
    shots: &[Shot],
    log: &mut dyn FnMut(&str),
) -> Result<Vec<Rc<Reference>>> {
    let mut references: Vec<Rc<Reference>> = Vec::new();
    for (i, s) in shots.iter().enumerate() {
        let same = (0..i).find(|&j| shots[j].camera == s.camera);
        let reference = match same {
            Some(j) => Rc::clone(&references[j]),
            None => Rc::new(reference::obtain(
                options.cache_dir.as_deref(),
                scene,
                s,
                options.reference_spp,
                log,
            )?),
        };
        references.push(reference);
    }
    Ok(references)
}

/// Every path open at once, so that each point's repeats can take turns between them; each
/// path's device is recorded the first time it is seen.
fn open_paths(
    options: &BenchOptions,
    kinds: &[PathKind],
    scene: &BenchScene,
    first: &Shot,
    paths_seen: &mut Vec<PathInfo>,
) -> Result<Vec<Box<dyn RenderPath>>> {
    let mut opened: Vec<Box<dyn RenderPath>> = Vec::with_capacity(kinds.len());
    for &kind in kinds {
        let OpenedPath { path, startup, .. } = paths::open(
            &choose::path_options(kind, options),
            &scene.description.scene,
            first,
        )
        .with_context(|| format!("--paths {kind}"))?;
        if !paths_seen.iter().any(|p| p.path == kind) {
            paths_seen.push(PathInfo {
                path: kind,
                device: path.device_name(),
                startup,
            });
        }
        opened.push(path);
    }
    Ok(opened)
}

/// The aperture, lens and movements sweeps: every point measured in turns (the paths' repeats go
/// round the points), then each aperture's cost against the round one, each moved shot's
/// against the plain one.
fn measure_in_turns(
    group: &Group,
    opened: &mut [Box<dyn RenderPath>],
    log: &mut dyn FnMut(&str),
) -> Result<Vec<Vec<Measurement>>> {
    let Group {
        options,
        kinds,
        scene,
        values,
        shots,
        references,
    } = *group;
    log(&format!(
        "measuring {}: {} ({} triangles), {}x{}, {} spp, {} {} in turns",
        kinds_list(kinds),
        scene.name,
        scene.triangles,
        options.width,
        options.height,
        options.spp,
        match options.sweep {
            Some(SweepKind::Lens) => "lenses",
            Some(SweepKind::Movements) => "shots",
            _ => "apertures",
        },
        values
            .iter()
            .map(|v| match v {
                SweepValue::Aperture(a) => a.name().to_string(),
                SweepValue::Lens(l) => l.label(),
                SweepValue::Movements(m) => m.name().to_string(),
                _ => "?".into(),
            })
            .collect::<Vec<_>>()
            .join(", ")
    ));
    let points: Vec<_> = shots
        .iter()
        .zip(references)
        .map(|(s, r)| (s, &r.image))
        .collect();
    let mut results = runs::measure_points_interleaved(opened, &points, options.repeat)?;
    match options.sweep {
        Some(SweepKind::Aperture) => {
            runs::set_costs_vs_first(&mut results, |m, c| m.cost_vs_round = Some(c));
        }
        Some(SweepKind::Movements) => {
            runs::set_costs_vs_first(&mut results, |m, c| m.time_per_sample_vs_plain = Some(c));
        }
        _ => {}
    }
    Ok(results)
}

/// The other sweeps: point by point, the paths' repeats interleaved at each.
fn measure_point_by_point(
    group: &Group,
    opened: &mut [Box<dyn RenderPath>],
    log: &mut dyn FnMut(&str),
) -> Result<Vec<Vec<Measurement>>> {
    let Group {
        options,
        kinds,
        scene,
        shots,
        references,
        ..
    } = *group;
    let mut results: Vec<Vec<Measurement>> = Vec::with_capacity(shots.len());
    for (s, reference) in shots.iter().zip(references) {
        log(&format!(
            "measuring {}: {} ({} triangles), {}x{}, {} spp",
            kinds_list(kinds),
            scene.name,
            scene.triangles,
            s.camera.width,
            s.camera.height,
            s.render.spp
        ));
        let Some(flare) = lens_flare::flare_of(options.flare, s)? else {
            results.push(runs::measure_interleaved(
                opened,
                s,
                options.repeat,
                (&reference.image, None),
            )?);
            continue;
        };
        // The reference, flared on the CPU as the paths' images are on their devices.
        let exposure = exposure(&scene.description.settings, &s.camera)?
            .display
            .exposure;
        let lights = &scene.description.scene.lights;
        let mut flared = reference.image.clone();
        let points = lens_flare::point_sources(lights, &s.camera);
        flare.apply(&mut flared, exposure, &points);
        let bench_flare = runs::BenchFlare {
            flare: &flare,
            exposure,
            lights,
        };
        results.push(runs::measure_interleaved(
            opened,
            s,
            options.repeat,
            (&flared, Some(&bench_flare)),
        )?);
    }
    Ok(results)
}

/// The lens sweep: each point's pass shares, then each real lens against its thin model (the
/// paths' `results` get their costs against it).
fn lens_points(
    values: &[SweepValue],
    shots: &[Shot],
    results: &mut [Vec<Measurement>],
    log: &mut dyn FnMut(&str),
) -> Vec<Option<LensPoint>> {
    log("counting the camera rays each lens lets through (CPU)");
    let lens_values: Vec<BenchLens> = values
        .iter()
        .map(|v| match v {
            SweepValue::Lens(l) => *l,
            _ => unreachable!("the lens sweep's points are lenses"),
        })
        .collect();
    let measured: Vec<LensPoint> = lens_values
        .iter()
        .zip(shots)
        .map(|(&l, s)| {
            let real = lens_values
                .iter()
                .position(|&m| m == BenchLens { real: true, ..l })
                .map_or(&s.camera, |i| &shots[i].camera);
            LensPoint::measure(l, s, real)
        })
        .collect();
    lens::set_costs_vs_thin(&lens_values, &measured, results);
    measured.into_iter().map(Some).collect()
}

/// The lens sweep's paths: those that trace real lenses (cpu, rayquery, rtpipeline,
/// software). The hybrid
/// refuses them and raster renders their first-order model: asked for, an error; in the
/// default list, left out with a notice.
fn lens_paths(
    options: &BenchOptions,
    kinds: Vec<PathKind>,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<PathKind>> {
    let untraced = |k: &PathKind| matches!(k, PathKind::Hybrid | PathKind::Raster);
    if let Some(kind) = options.paths.iter().filter_map(|p| p.only()).find(untraced) {
        bail!("--sweep lens: --paths {kind} does not trace real lenses (hybrid refuses them, raster renders their first-order model); use cpu, rayquery, rtpipeline or software");
    }
    let (left, kept): (Vec<PathKind>, Vec<PathKind>) = kinds.into_iter().partition(untraced);
    if !left.is_empty() {
        log(&format!(
            "notice: --sweep lens leaves out {}: they do not trace real lenses",
            kinds_list(&left)
        ));
    }
    ensure!(
        !kept.is_empty(),
        "--sweep lens: no path that traces real lenses (cpu, rayquery, rtpipeline, software) to run"
    );
    Ok(kept)
}

fn kinds_list(kinds: &[PathKind]) -> String {
    kinds
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Each path's speed against the CPU path's at the same point (CPU median / path median).
fn set_speedups(results: &mut [Measurement]) {
    let cpu = results
        .iter()
        .find(|m| m.path == PathKind::Cpu)
        .map(|m| m.trace_seconds.median);
    if let Some(cpu) = cpu {
        for m in results {
            m.speedup_vs_cpu = Some(cpu / m.trace_seconds.median.max(1e-12));
        }
    }
}

/// The report of the point of `scene` rendering `shot`.
fn point_report(
    scene: &BenchScene,
    shot: &Shot,
    reference: &Reference,
    focus: FocusInfo,
    results: Vec<Measurement>,
) -> PointReport {
    PointReport {
        width: shot.camera.width,
        height: shot.camera.height,
        spp: shot.render.spp,
        triangles: scene.triangles,
        camera: camera::CameraInfo::of(&shot.camera),
        aperture: None,
        lens: None,
        movements: None,
        reference: reference.info.clone(),
        focus,
        results,
    }
}
