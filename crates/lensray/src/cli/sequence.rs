//! `lensray render`: the sequence `--frames` asks for, else one image (`render::render_one`).
//! A sequence renders in one process: the scene loads, and the device, its pipelines and the
//! acceleration structures are made, once; each frame is a new shot (its camera from the
//! scene's keyframes, or its glTF camera animation; what the file's animations move posed at
//! its time) rendered on the same path, with its own seed (`settings::frame_seed`), written to
//! a temporary file and renamed when complete.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};

use super::frames::{is_complete, FramePattern};
use super::progress::{ProgressMode, ProgressReporter};
use super::render::{load_scene, RenderArgs};
use super::video::{VideoEncoder, VideoPlan};
use crate::focus::focus_depth_at;
use crate::frame_settings::{command_line_over, FrameSettings};
use crate::lens_flare;
use crate::output::PendingOutput;
use crate::paths::{self, OpenedPath, RenderPath, Startup};
use lensray_core::scene::file::SceneDescription;
use lensray_core::settings::{exposure, fps, light_scene, shot, shutter, Shot};

/// Where a sequence's time went, seconds.
#[derive(Default)]
struct SequenceTimes {
    rendered: usize,
    skipped: usize,
    /// The paths' renders alone.
    render: f64,
    /// Everything else of the frames: their shots, autofocus, exposure, encoding and writing.
    other: f64,
}

/// `lensray render`: the frames `--frames` asks for, else one image (`render::render_one`).
pub fn run(args: &RenderArgs) -> Result<()> {
    match sequence_of(args)? {
        Some((frames, pattern)) => run_frames(args, &frames, pattern.as_ref()),
        None => super::render::render_one(args),
    }
}

/// A sequence's frames and file names (none for a video alone), where `--frames` asks for one;
/// `--chunk`, `--resume` and `--video` without it, or a frame number's place in `--out` without
/// it, are refused.
fn sequence_of(args: &RenderArgs) -> Result<Option<(Vec<u32>, Option<FramePattern>)>> {
    let out = args.out_path();
    let pattern = FramePattern::of(out);
    let Some(range) = args.frames else {
        let option = [
            (args.resume, "--resume"),
            (args.chunk.is_some(), "--chunk"),
            (args.video.is_some(), "--video"),
        ];
        if let Some((_, option)) = option.into_iter().find(|(given, _)| *given) {
            anyhow::bail!("{option} is for sequences: give --frames too");
        }
        if pattern.is_some() {
            anyhow::bail!(
                "--out {} names a frame number: give --frames (like --frames 1-240)",
                out.display()
            );
        }
        return Ok(None);
    };
    if args.video.is_some() && args.chunk.is_some() {
        anyhow::bail!("--video encodes a whole sequence, not a --chunk: once the chunks' frames are rendered, one run over the range with --resume --video encodes them");
    }
    let frames = range.frames();
    let frames = args.chunk.map_or(frames.clone(), |chunk| chunk.of(&frames));
    if args.video.is_some() && args.out.is_none() {
        if args.resume {
            anyhow::bail!("--resume skips the frames' complete files: give --out with the frame number's place too");
        }
        return Ok(Some((frames, None)));
    }
    let Some(pattern) = pattern else {
        anyhow::bail!(
            "--out {}: a sequence's file name needs the frame number's place, like shot.####.exr or shot.%04d.exr",
            out.display()
        );
    };
    Ok(Some((frames, Some(pattern))))
}

/// Renders `frames` to the files `pattern` names and to `--video`'s.
fn run_frames(args: &RenderArgs, frames: &[u32], pattern: Option<&FramePattern>) -> Result<()> {
    let start = Instant::now();
    if args.view.focus_plane.is_some() {
        anyhow::bail!("--focus-plane is for one frame: key focus_distance, tilt and tilt_direction in [[keyframe]]s for a sequence");
    }
    let Some(&first) = frames.first() else {
        println!("{}: no frames in this chunk", args.out_path().display());
        return Ok(());
    };
    // A missing ffmpeg or a bad output path fails before any rendering.
    let video = args.video.as_deref().map(VideoPlan::check).transpose()?;
    if let Some(pattern) = pattern {
        PendingOutput::create(&pattern.path(first))?;
    }
    let mut description = load_scene(&args.view)?;
    let command_line = args.view.to_settings().scaled(description.units.metres());
    let keyframes = std::mem::take(&mut description.keyframes);
    let merged = command_line_over(&description.settings, &command_line);
    let keyframes = super::camera_animation::play(keyframes, &description, &merged)?;
    let context = format!("scene {}", description.source);
    let moving_shutter = shutter(&merged).with_context(|| context.clone())?.is_some();
    // The file's meshes blur where they move while the shutter is open.
    let objects_blur = moving_shutter && description.motion.is_some();
    let mut settings = FrameSettings::new(description.settings.clone(), command_line, keyframes)
        .with_moving_objects(objects_blur);
    // The scene's lights are those of the first frame's settings: the scene stays.
    let rate = fps(&merged).map_err(|e| match args.view.fps {
        Some(_) => anyhow::anyhow!("--fps: {e}"),
        None => anyhow::anyhow!("{context}: [image] {e}"),
    })?;
    let video = video.map(|video| (video, rate));
    for warning in
        light_scene(&settings.at(first), &mut description.scene).context(context.clone())?
    {
        eprintln!("warning: {warning}");
    }
    let (scene, source) = (&description.scene, description.source.as_str());
    let first_shot = settings.shot(first, scene, source)?;
    let mut options = args.path.options();
    options.gpu.first_use_notice = args.progress != ProgressMode::None;
    let load_seconds = start.elapsed().as_secs_f64();
    let OpenedPath {
        mut path,
        why,
        startup,
    } = match objects_blur {
        true => paths::open_moving_objects(&options, scene, &first_shot)?,
        false => paths::open(&options, scene, &first_shot)?,
    };
    let focus_start = Instant::now();
    settings.resolve_focus(scene, source, &mut |camera, pixel, what| {
        focus_depth_at(path.as_mut(), camera, pixel, what)
    })?;
    let focus_seconds = focus_start.elapsed().as_secs_f64();
    let startup_seconds = start.elapsed().as_secs_f64();

    let loop_start = Instant::now();
    let (width, height) = (first_shot.camera.width, first_shot.camera.height);
    let mut video = video
        .map(|(video, fps)| video.start(width, height, fps))
        .transpose()?;
    super::camera_animation::note_motion(&description, Some(rate));
    super::camera_animation::note_shutter(&description, moving_shutter, true);
    let times = render_frames(
        args,
        frames,
        pattern,
        &settings,
        &description,
        path.as_mut(),
        video.as_mut(),
    )?;
    let loop_seconds = loop_start.elapsed().as_secs_f64();
    let (kind, device) = (path.kind(), path.device_name());
    path.close()?;
    let video = video.map(VideoEncoder::finish).transpose()?;
    let Shot { camera, render } = &first_shot;
    // Without --out, the video is the sequence's one output.
    let name = args.out.as_deref().or(args.video.as_deref());
    println!(
        "{}: {} frames from {first} to {} ({} rendered, {} complete and skipped), {}x{} px, {} spp, path {kind} ({why}) on {device}: {:.2} s total",
        name.unwrap_or(args.out_path()).display(),
        frames.len(),
        frames[frames.len() - 1],
        times.rendered,
        times.skipped,
        camera.width,
        camera.height,
        render.spp,
        start.elapsed().as_secs_f64(),
    );
    let per_frame = times.other / times.rendered.max(1) as f64;
    println!(
        "  start-up {startup_seconds:.2} s once (scene, device, pipelines, acceleration structures); frames {loop_seconds:.2} s: rendering {:.2} s, beyond it {:.1} ms a frame ({:.3}x rendering alone)",
        times.render,
        per_frame * 1e3,
        loop_seconds / times.render.max(1e-9),
    );
    if let Some(video) = video {
        println!("  video {video}");
    }
    if args.timings {
        let total = start.elapsed().as_secs_f64();
        print_timings(total, &startup, load_seconds, focus_seconds, &times);
    }
    Ok(())
}

/// `--timings`: the sequence's phases, and what they leave of `total`, a line each.
fn print_timings(
    total: f64,
    startup: &Startup,
    load_seconds: f64,
    focus_seconds: f64,
    times: &SequenceTimes,
) {
    let phases = [
        ("load", load_seconds),
        ("device and pipelines", startup.device_seconds),
        (
            "scene upload and acceleration structures",
            startup.scene_seconds,
        ),
        ("focus keys", focus_seconds),
        ("rendering", times.render),
        (
            "beyond rendering (shots, exposure, encode and write)",
            times.other,
        ),
    ];
    let known: f64 = phases.iter().map(|(_, s)| s).sum();
    for (phase, seconds) in phases {
        println!("timings: {phase} {seconds:.4} s");
    }
    println!("timings: other {:.4} s", (total - known).max(0.0));
    println!("timings: total {total:.4} s");
}

/// Renders each frame not yet complete (under `--resume`), with one progress bar over them all;
/// what the file's animations move is posed at each frame's time (frame N at N / fps seconds).
fn render_frames(
    args: &RenderArgs,
    frames: &[u32],
    pattern: Option<&FramePattern>,
    settings: &FrameSettings,
    description: &SceneDescription,
    path: &mut dyn RenderPath,
    mut video: Option<&mut VideoEncoder>,
) -> Result<SequenceTimes> {
    let mut posed = description
        .motion
        .as_ref()
        .map(|motion| (motion, description.scene.clone()));
    let mut times = SequenceTimes::default();
    let mut progress = ProgressReporter::new("rendering", args.progress);
    let lines = args.progress == ProgressMode::Lines;
    let count = frames.len() as u64;
    for (i, &frame) in frames.iter().enumerate() {
        let frame_start = Instant::now();
        let file = pattern.map(|p| p.path(frame));
        let mut resolved = settings.shot(frame, &description.scene, &description.source)?;
        let (width, height) = (resolved.camera.width, resolved.camera.height);
        let complete = |f: &&PathBuf| args.resume && is_complete(f, width, height);
        if let Some(file) = file.as_ref().filter(complete) {
            if let Some(video) = video.as_deref_mut() {
                let exposure = exposure(&settings.at(frame), &resolved.camera)
                    .with_context(|| format!("frame {frame}"))?;
                video.push_file(file, resolved.render.shading, &exposure)?;
            }
            times.skipped += 1;
            if lines {
                eprintln!("frame {frame}: {} is complete, skipped", file.display());
            }
            continue;
        }
        let output = file.as_deref().map(PendingOutput::create).transpose()?;
        if let Some((motion, scene)) = posed.as_mut() {
            let at = settings.at(frame);
            let context = || format!("frame {frame}");
            let rate = fps(&at).with_context(context)?;
            let shutter = shutter(&at).with_context(context)?;
            let frame_time = (f64::from(frame), rate);
            super::posed::load_frame(path, motion, scene, frame_time, shutter.as_ref())
                .with_context(|| format!("frame {frame}: the posed scene"))?;
        }
        if let Some(pixel) = args.focus_at {
            let focus = focus_depth_at(path, &resolved.camera, pixel, "--focus-at")?;
            let mut keyed = settings.at(frame);
            keyed.camera.focus_distance = Some(f64::from(focus));
            let refocused =
                shot(&keyed, &description.scene).with_context(|| format!("frame {frame}"))?;
            resolved =
                settings.moving(frame, refocused, &description.scene, &description.source)?;
        }
        let frame_settings = settings.at(frame);
        let exposure = exposure(&frame_settings, &resolved.camera)
            .with_context(|| format!("frame {frame}"))?;
        let flare = lens_flare::flare_for(&frame_settings, &resolved)
            .with_context(|| format!("frame {frame}"))?;
        let render_start = Instant::now();
        let i = i as u64;
        let mut image = path.render(&resolved, &mut |done, total| {
            progress.update(i * total + done, count * total);
        })?;
        if let Some(flare) = &flare {
            let lights = posed
                .as_ref()
                .map_or(&description.scene.lights, |(_, scene)| &scene.lights);
            let scale = exposure.display.exposure;
            lens_flare::add(flare, (&mut image, scale), &resolved, lights, path)?;
        }
        let render_seconds = render_start.elapsed().as_secs_f64();
        let shading = resolved.render.shading;
        VideoEncoder::write_frame(video.as_deref_mut(), output, &image, shading, &exposure)?;
        let frame_seconds = frame_start.elapsed().as_secs_f64();
        times.rendered += 1;
        times.render += render_seconds;
        times.other += frame_seconds - render_seconds;
        if lines {
            let name = file.map_or("the video".into(), |f| f.display().to_string());
            eprintln!(
                "frame {frame} ({} of {count}): {name} in {frame_seconds:.3} s (rendering {render_seconds:.3} s)",
                i + 1
            );
        }
    }
    progress.finish();
    Ok(times)
}
