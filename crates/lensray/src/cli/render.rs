//! `lensray render`: its options, the scene they name, and one image, headless (a sequence,
//! `--frames`, is `cli::sequence`'s, which renders a still here).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;

use super::args::{parse_pixel, PathArgs, ViewArgs};
use super::frames::{parse_chunk, parse_frames, Chunk, FrameRange};
use super::progress::{ProgressMode, ProgressReporter};
use crate::focus::{focus_depth_at, lay_focus_plane};
use crate::frame_settings::command_line_over;
use crate::lens_flare;
use crate::output::PendingOutput;
use crate::paths::{self, OpenedPath, PathOptions, Phases, RenderPath};
use lensray_core::scene::file::SceneDescription;
use lensray_core::scene::units::SceneUnits;
use lensray_core::settings::Settings;
use lensray_core::settings::{exposure, light_scene, shot, Exposure, Shot};

pub const DEFAULT_OUTPUT: &str = "lensray.png";

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub path: PathArgs,
    /// Output image: .png (sRGB, exposed and tone mapped) or .exr (linear float, exposed only
    /// with --expose-exr); default lensray.png.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Autofocus: focus on the surface seen at this pixel (column,row).
    #[arg(long, value_parser = parse_pixel, value_name = "X,Y")]
    pub focus_at: Option<[u32; 2]>,
    /// How to show progress: a bar on a terminal, plain lines, or nothing.
    #[arg(long, value_enum, default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// Print where the time went, phase by phase (docs/performance.md, "Phases of a render").
    #[arg(long)]
    pub timings: bool,
    /// Render a sequence: frame N, frames A to B, or every STEP-th of them, the scene's
    /// `[[keyframe]]`s moving the camera; --out names each frame's file with #### or %04d.
    #[arg(long, value_parser = parse_frames, value_name = "N|A-B|A-B:STEP", allow_hyphen_values = true)]
    pub frames: Option<FrameRange>,
    /// Render only the INDEX-th (from 0) of SIZE contiguous parts of --frames (a render farm's
    /// task: a job array's index).
    #[arg(long, value_parser = parse_chunk, value_name = "INDEX/SIZE")]
    pub chunk: Option<Chunk>,
    /// With --frames: skip the frames whose file exists and is complete (decodes at the
    /// shot's size); a partial file is rendered again.
    #[arg(long)]
    pub resume: bool,
    /// With --frames: also encode the frames, in order, into an H.264 MP4 with ffmpeg, at the
    /// sequence's fps, as PNG frames show them; without --out, the video alone.
    #[arg(long, value_name = "FILE.mp4")]
    pub video: Option<PathBuf>,
}

impl RenderArgs {
    /// `--out`, or its default.
    pub fn out_path(&self) -> &Path {
        self.out.as_deref().unwrap_or(Path::new(DEFAULT_OUTPUT))
    }
}

/// The scene the options name (with the camera `--camera` picks), or the built-in default
/// scene, in metres. What the loader ignored or repaired is printed, a warning a line, and so
/// are the scale from the scene's units and the file's camera in use.
pub fn load_scene(view: &ViewArgs) -> Result<SceneDescription> {
    let mut description = match &view.scene {
        Some(path) => lensray_core::scene::file::load_in(path, view.scene_units)?,
        None => {
            let mut description = lensray_core::scene::builtin::default_scene();
            description.set_units(view.scene_units.unwrap_or_default());
            description
        }
    };
    for notice in &description.notices {
        eprintln!("warning: {notice}");
    }
    let units = description.units;
    if units != SceneUnits::M {
        eprintln!(
            "scene units: {units}: the scene and its lengths scaled by {} to metres",
            units.metres()
        );
    }
    if let Some(crease) = view.smooth_normals {
        let meshes = description.scene.smooth_normals(crease);
        if let Some(motion) = &mut description.motion {
            motion.smooth_normals(crease);
        }
        eprintln!("smooth normals: {meshes} meshes without normals, creased at {crease} degrees");
    }
    if let Some(choice) = &view.camera {
        description
            .use_camera(choice)
            .map_err(|e| anyhow::anyhow!("scene {}: {e}", description.source))?;
    }
    if let Some(camera) = description.camera_summary() {
        eprintln!("camera: {camera}");
    }
    if let Some(lights) = lights_summary(&description.scene.lights) {
        eprintln!("lights: {lights} from the file");
    }
    Ok(description)
}

/// "2 point, 1 spot" for the file's lights; `None` for none.
fn lights_summary(lights: &[lensray_core::scene::Light]) -> Option<String> {
    use lensray_core::scene::LightKind;
    let name = |kind: &LightKind| match kind {
        LightKind::Point => "point",
        LightKind::Spot { .. } => "spot",
        LightKind::Directional => "directional",
    };
    let parts: Vec<String> = ["point", "spot", "directional"]
        .into_iter()
        .map(|kind| {
            (
                kind,
                lights.iter().filter(|l| name(&l.kind) == kind).count(),
            )
        })
        .filter(|&(_, n)| n > 0)
        .map(|(kind, n)| format!("{n} {kind}"))
        .collect();
    (!parts.is_empty()).then(|| parts.join(", "))
}

/// The scene file's settings (in metres) with the command line's on top, its world lengths
/// given in the scene's `units`. Lens options replace the file's lens as a group, so a file's
/// aperture radius does not clash with a command-line focal length.
pub fn merged_settings(file: &Settings, units: SceneUnits, view: &ViewArgs) -> Settings {
    command_line_over(file, &view.to_settings().scaled(units.metres()))
}

impl Default for RenderArgs {
    fn default() -> Self {
        Self {
            view: ViewArgs::default(),
            path: PathArgs::default(),
            out: None,
            focus_at: None,
            progress: ProgressMode::Auto,
            timings: false,
            frames: None,
            chunk: None,
            resume: false,
            video: None,
        }
    }
}

/// The driver's shader compilation, apart from the render's time: said where it took a
/// noticeable part of the run (a device's first use), not for the milliseconds of a cached run.
fn compile_note(seconds: f64) -> String {
    if seconds >= 0.5 {
        format!(" ({seconds:.2} s of it compiling shaders)")
    } else {
        String::new()
    }
}

/// The exposure's line of the summary, where one was asked for.
fn print_exposure(settings: &Settings, exposure: &Exposure) {
    if settings.camera.exposure.ev.is_some() || exposure.physical.is_some() {
        let ev = settings.camera.exposure.ev.unwrap_or(0.0);
        println!("  exposure: {}", exposure.summary(ev));
    }
}

/// `--focus-at`: `settings` focused on the surface seen at `pixel`, and their shot.
fn autofocus(
    path: &mut dyn RenderPath,
    settings: &mut Settings,
    description: &SceneDescription,
    resolved: &Shot,
    pixel: [u32; 2],
) -> Result<Shot> {
    let focus = focus_depth_at(path, &resolved.camera, pixel, "--focus-at")?;
    settings.camera.focus_distance = Some(focus as f64);
    let resolved = shot(settings, &description.scene)
        .with_context(|| format!("scene {}", description.source))?;
    // lensray's lengths are metres: a scene in other units says so.
    let unit = match description.units {
        SceneUnits::M => "",
        _ => " m",
    };
    eprintln!(
        "autofocus: pixel {},{} is {focus:.4}{unit} away along the view axis",
        pixel[0], pixel[1]
    );
    Ok(resolved)
}

/// Says that a render of one image leaves the scene's keyframes out.
fn note_keyframes(description: &SceneDescription) {
    if let Some((first, last)) = description.keyframes.range() {
        eprintln!("note: the scene's keyframes (frames {first} to {last}) move the camera in sequences (--frames); this render is the scene without them");
    }
}

/// The path `options` ask for with the scene loaded. Where a still of an animated file blurs
/// (`shutter`), the CPU path with the file's meshes posed as frame 0 of a sequence at the
/// settings' fps, those that move over the open shutter with their steps: the still is that
/// frame, its camera standing still.
fn open_still(
    options: &PathOptions,
    description: &SceneDescription,
    (settings, resolved): (&Settings, &Shot),
    shutter: Option<&lensray_core::settings::Shutter>,
) -> Result<OpenedPath> {
    let (Some(shutter), Some(motion)) = (shutter, &description.motion) else {
        return paths::open(options, &description.scene, resolved);
    };
    let mut opened = paths::open_moving_objects(options, &description.scene, resolved)?;
    let rate = lensray_core::settings::fps(settings)
        .with_context(|| format!("scene {}", description.source))?;
    let mut scene = description.scene.clone();
    let (path, frame) = (opened.path.as_mut(), (0.0, rate));
    super::posed::load_frame(path, motion, &mut scene, frame, Some(shutter))?;
    Ok(opened)
}

/// `resolved` focused as the arguments ask (`--focus-plane`, `--focus-at`) on `path`, its
/// camera taking its samples' moments where a still's `shutter` blurs the file's meshes.
fn focused_shot(
    args: &RenderArgs,
    path: &mut dyn RenderPath,
    (settings, mut resolved): (&mut Settings, Shot),
    description: &SceneDescription,
    shutter: Option<&lensray_core::settings::Shutter>,
) -> Result<Shot> {
    let context = || format!("scene {}", description.source);
    if settings.camera.focus_plane.is_some() {
        if args.focus_at.is_some() {
            anyhow::bail!("give either --focus-at or --focus-plane, not both");
        }
        resolved = lay_focus_plane(path, settings, &resolved, &|settings| {
            shot(settings, &description.scene).with_context(context)
        })?;
    }
    if let Some(pixel) = args.focus_at {
        resolved = autofocus(path, settings, description, &resolved, pixel)?;
    }
    if let Some(shutter) = shutter {
        // The camera stands still; its samples take their moments, where the meshes are met.
        let motion = shutter
            .camera_motion(0.0, &|_| settings.clone(), &description.scene, true)
            .with_context(context)?;
        resolved.camera = resolved.camera.with_motion(motion);
    }
    Ok(resolved)
}

/// Closes `path`'s device while `image` encodes into `output` (on NVIDIA's driver closing
/// takes ~60 ms); the file reaches its name only once the device closed cleanly. The seconds
/// the encoding took.
fn close_and_write(
    path: Box<dyn RenderPath>,
    output: PendingOutput,
    image: &lensray_core::film::Image,
    shading: lensray_core::settings::Shading,
    exposure: &Exposure,
) -> Result<f64> {
    let (closed, (encoded, write_seconds)) = std::thread::scope(|s| {
        let closing = s.spawn(move || path.close());
        let write_start = Instant::now();
        let encoded = output.encode(image, shading, exposure);
        let write_seconds = write_start.elapsed().as_secs_f64();
        let closed = closing
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (closed, (encoded, write_seconds))
    });
    closed?;
    encoded?.commit()?;
    Ok(write_seconds)
}

/// One image (`render` without `--frames`; `cli::sequence::run` decides).
pub fn render_one(args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    // Fail on a bad output path before spending time on the render.
    let output = PendingOutput::create(args.out_path())?;
    let mut description = load_scene(&args.view)?;
    note_keyframes(&description);
    super::camera_animation::note_still(&description);
    super::camera_animation::note_motion(&description, None);
    let mut settings = merged_settings(&description.settings, description.units, &args.view);
    let context = || format!("scene {}", description.source);
    let resolved = shot(&settings, &description.scene).with_context(context)?;
    let open_shutter = lensray_core::settings::shutter(&settings).with_context(context)?;
    super::camera_animation::note_shutter(&description, open_shutter.is_some(), false);
    // A still of an animated file blurs its meshes over the shutter (`load_still_pose`).
    let still_blur = open_shutter.filter(|_| description.motion.is_some());
    // The f-number is the lens's, which focusing below leaves as it is.
    let exposure = exposure(&settings, &resolved.camera).with_context(context)?;
    for warning in light_scene(&settings, &mut description.scene).with_context(context)? {
        eprintln!("warning: {warning}");
    }
    let load_seconds = start.elapsed().as_secs_f64();

    let mut options = args.path.options();
    options.gpu.first_use_notice = args.progress != ProgressMode::None;
    let OpenedPath {
        mut path,
        why,
        startup,
    } = open_still(
        &options,
        &description,
        (&settings, &resolved),
        still_blur.as_ref(),
    )?;
    let resolved = focused_shot(
        args,
        path.as_mut(),
        (&mut settings, resolved),
        &description,
        still_blur.as_ref(),
    )?;

    let flare = lens_flare::flare_for(&settings, &resolved).with_context(context)?;
    let mut progress = ProgressReporter::new("rendering", args.progress);
    let before = path.report();
    let render_start = Instant::now();
    let mut image = path.render(&resolved, &mut |d, t| progress.update(d, t))?;
    let render_seconds = render_start.elapsed().as_secs_f64();
    let mut flare_seconds = 0.0;
    if let Some(flare) = &flare {
        let flare_start = Instant::now();
        let (lights, scale) = (&description.scene.lights, exposure.display.exposure);
        lens_flare::add(flare, (&mut image, scale), &resolved, lights, path.as_mut())?;
        flare_seconds = flare_start.elapsed().as_secs_f64();
    }
    progress.finish();
    let report = path.report().since(&before);
    // Pipelines may be made while the path opens (auto's choice) or in the render.
    let compile_seconds = path.report().compile_seconds;
    let (kind, device) = (path.kind(), path.device_name());
    let Shot { camera, render } = &resolved;
    let write_seconds = close_and_write(path, output, &image, render.shading, &exposure)?;
    let aov = render.shading.is_aov();
    let phases = Phases {
        load_seconds,
        write_seconds,
        flare_seconds,
        ..Phases::of_render(
            render_seconds,
            &report,
            if aov { 1 } else { render.spp },
            aov,
        )
    }
    .with_startup(startup);
    println!(
        "{}: {}x{} px, {} spp ({} sampler), {:?} shading, {} triangles, path {kind} ({why}) on {}: {:.2} s total{}, {:.2} Mrays/s",
        args.out_path().display(),
        camera.width,
        camera.height,
        render.spp,
        render.sampler,
        render.shading,
        description.scene.triangle_count(),
        device,
        start.elapsed().as_secs_f64(),
        compile_note(compile_seconds),
        report.rays_per_second() / 1e6
    );
    if !aov {
        print_adaptive(render, camera, report.adaptive_samples);
    }
    print_exposure(&settings, &exposure);
    if let Some(real) = camera.lens.real() {
        println!("  {}", real.summary());
        if let Some(notice) = real.params.prescription.dispersion_notice() {
            eprintln!("warning: {notice}");
        }
    }
    if args.timings {
        for line in phases.closed(start.elapsed().as_secs_f64()).lines() {
            println!("{line}");
        }
    }
    Ok(())
}

/// The summary's line of an adaptive render (`--noise-threshold`): its samples and their
/// average per pixel.
fn print_adaptive(
    render: &lensray_core::settings::RenderSettings,
    camera: &lensray_core::camera::Camera,
    samples: u64,
) {
    if let Some(threshold) = render.noise_threshold {
        let pixels = camera.width as f64 * camera.height as f64;
        println!(
            "  adaptive: noise threshold {threshold}, {samples} samples, {:.2} spp on average (cap {})",
            samples as f64 / pixels,
            render.spp
        );
    }
}
