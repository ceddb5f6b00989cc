//! `lensray preview`: the window to frame a shot and pick the focus (see `crate::preview`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use super::args::{PathArgs, ViewArgs};
use super::named::by_name;
use super::render::load_scene;
use crate::focus::focus_depth_at;
use crate::frame_settings::{command_line_over, FrameSettings};
use crate::paths::{self, OpenedPath, PathOptions};
use crate::preview::app::{run as run_window, PreviewConfig};
use crate::preview::playback::{Playback, PlaybackClock};
use crate::preview::player::ScriptPlayer;
use crate::preview::{CameraRig, ViewMode};
use lensray_core::scene::file::SceneDescription;
use lensray_vulkan::{PresentMode, ViewerOptions};

#[derive(Args, Debug)]
pub struct PreviewArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    /// What the window shows first (V cycles, 1-5 pick).
    #[arg(long = "view", value_enum, default_value_t = ViewMode::Final)]
    pub initial_view: ViewMode,
    /// How frames wait for the display.
    #[arg(long, value_parser = by_name::<PresentMode>(), default_value = PresentMode::Fifo.name())]
    pub present_mode: PresentMode,
    /// Draw this many frames, then exit.
    #[arg(long, value_name = "N")]
    pub frames: Option<u64>,
    /// On exit, save the accumulation here (.png or .exr), as `render --out` would.
    #[arg(long, value_name = "FILE")]
    pub screenshot: Option<PathBuf>,
    /// Replay timed input events from this file (keys, clicks, drags, scrolls, resizes,
    /// `lens NAME|thin`, `frame N`, `wait converged`, `screenshot FILE`, `quit`; one per line
    /// after a delay in seconds).
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    #[command(flatten)]
    pub path: PathArgs,
}

pub fn run(args: &PreviewArgs) -> Result<()> {
    if args.frames == Some(0) {
        anyhow::bail!("--frames must be at least 1");
    }
    if let Some(path) = &args.screenshot {
        crate::output::format_of(path)?;
    }
    let script = match &args.script {
        Some(path) => crate::preview::script::load(path)?,
        None => Vec::new(),
    };
    let choice = crate::paths::preview_options(&args.path.options())?;
    let mut description = load_scene(&args.view)?;
    let (settings, playback) = keyed_start(&mut description, args)?;
    // The CPU and the traced GPU paths sample adaptively in the preview too (docs/adaptive.md);
    // the raster and hybrid paths give every pixel the same samples.
    let uniform = args
        .path
        .options()
        .path
        .only()
        .and_then(|kind| Some(format!("--path {kind} ({})", kind.adaptive_refusal()?)));
    if let (Some(threshold), Some(who)) = (settings.render.noise_threshold, uniform) {
        eprintln!("notice: {who} gives every pixel the same samples; the noise threshold ({threshold}) applies to `lensray render`");
    }
    let rig = CameraRig::new(settings, &description.scene)
        .with_context(|| format!("scene {}", description.source))?;
    // Bad exposure options fail here, in one line, before the window opens.
    rig.shot(&description.scene)
        .and_then(|shot| rig.exposure(&shot.camera))
        .with_context(|| format!("scene {}", description.source))?;
    // The rig's lights are pinned: they light the scene wherever the camera goes.
    let warnings = lensray_core::settings::light_scene(rig.settings(), &mut description.scene)
        .with_context(|| format!("scene {}", description.source))?;
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    let config = PreviewConfig {
        scene_path: args.view.scene.clone(),
        description,
        rig,
        viewer: ViewerOptions {
            gpu: choice.gpu,
            present_mode: args.present_mode,
            estimator: choice.estimator,
        },
        cpu_path: choice.cpu,
        view: args.initial_view,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        script: ScriptPlayer::new(script),
        playback,
    };
    let summary = run_window(config)?;
    println!("{summary}");
    Ok(())
}

/// The settings the window opens with and, for a scene with keyframes, its shot: the first
/// keyed frame, exactly as `render --frames` makes it (its focus points and pixels resolved,
/// a pixel's through the path the options open, as `render` resolves them).
fn keyed_start(
    description: &mut SceneDescription,
    args: &PreviewArgs,
) -> Result<(lensray_core::settings::Settings, Option<Playback>)> {
    let command_line = args.view.to_settings().scaled(description.units.metres());
    let keyframes = std::mem::take(&mut description.keyframes);
    let merged = command_line_over(&description.settings, &command_line);
    // The camera's glTF animation plays in the window as in `render --frames`.
    let keyframes = super::camera_animation::play(keyframes, description, &merged)?;
    let mut frames = FrameSettings::new(description.settings.clone(), command_line, keyframes)
        .with_moving_objects(description.motion.is_some());
    let context = || format!("scene {}", description.source);
    // The frames an animated file's meshes and lights move over play too.
    let moving = match &description.motion {
        Some(motion) => {
            let fps = lensray_core::settings::fps(&merged).with_context(context)?;
            let (start, end) = motion.time_range();
            let frame = |t: f64| t.clamp(0.0, f64::from(u32::MAX)) as u32;
            Some((frame((start * fps).floor()), frame((end * fps).ceil())))
        }
        None => None,
    };
    let range = match (frames.keyframes().range(), moving) {
        (Some(keyed), Some(moving)) => Some((keyed.0.min(moving.0), keyed.1.max(moving.1))),
        (keyed, moving) => keyed.or(moving),
    };
    let Some((first, last)) = range else {
        return Ok((frames.unkeyed(), None));
    };
    let fps = lensray_core::settings::fps(&frames.at(first)).with_context(context)?;
    resolve_focus(&mut frames, description, &args.path.options())?;
    let what = if frames.keyframes().range().is_some() {
        "keyframes from frame"
    } else {
        "frames"
    };
    eprintln!(
        "preview: {what} {first} to {last} at {fps} fps (the panel's slider picks a frame, Enter plays)"
    );
    let clock = PlaybackClock::new((first, last), fps);
    // An animated file's first frame is posed when the window shows it.
    let shown = description.motion.is_none().then_some(first);
    Ok((frames.at(first), Some(Playback::new(frames, clock, shown))))
}

/// The keyframes' focus points and pixels as distances; a path opens at the first pixel key.
fn resolve_focus(
    frames: &mut FrameSettings,
    description: &SceneDescription,
    options: &PathOptions,
) -> Result<()> {
    let (scene, source) = (&description.scene, description.source.as_str());
    let (first, _) = frames.keyframes().range().unwrap_or_default();
    let first_shot = frames.shot(first, scene, source)?;
    let mut opened: Option<OpenedPath> = None;
    frames.resolve_focus(scene, source, &mut |camera, pixel, what| {
        let opened = match &mut opened {
            Some(opened) => opened,
            None => opened.insert(paths::open(options, scene, &first_shot)?),
        };
        focus_depth_at(opened.path.as_mut(), camera, pixel, what)
    })?;
    if let Some(opened) = opened {
        opened.path.close()?;
    }
    Ok(())
}
