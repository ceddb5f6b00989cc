//! The preview window: a winit application whose frames the GPU viewer draws. Input (real or
//! scripted) moves the camera rig; every change restarts the accumulation; once the target
//! sample count is reached the event loop waits for input and uses no CPU.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result};
use glam::Vec2;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, ModifiersState};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use super::bindings::{
    action_for_key, wheel_action, Action, PointerButton, WheelAction, WheelModifier,
};
use super::cpu_feed::CpuFeed;
use super::frame_log::FrameLog;
use super::input::{Gesture, InputState};
use super::panel::{Panel, PanelStats};
use super::player::ScriptPlayer;
use super::rig::{CameraRig, LensChoice};
use super::script::ScriptEvent;
use super::view::ViewMode;
use crate::output::PendingOutput;
use crate::paths;
use crate::paths::PathKind;
use lensray_core::camera::Camera;
use lensray_core::scene::file::SceneDescription;
use lensray_core::settings::RenderSettings;
use lensray_vulkan::{Estimator, FrameRequest, HostSamples, OverlayFrame, Viewer, ViewerOptions};

/// How often the window looks for the CPU path's samples while it waits for them.
const CPU_PATH_POLL: std::time::Duration = std::time::Duration::from_millis(30);

/// The GPU paths the window draws with: the one for thin lenses (asked for, or `auto`'s pick)
/// and the traversal path that traces real lenses where that one cannot (the hybrid, whose
/// shortcuts bound thin-lens rays only, and `auto`'s raster path, which would show a real
/// lens's first-order model). The panel may switch lenses at any frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct GpuPaths {
    thin: PathKind,
    /// The renderer's traversal, as a path.
    traced: PathKind,
    /// `--path raster` asked for: a real lens keeps it and shows its first-order model (with
    /// a notice, as `lensray render` does).
    raster_asked: bool,
    in_use: PathKind,
    /// The raster path's notice for a real lens was given.
    first_order_noticed: bool,
}

impl GpuPaths {
    /// The path for a camera with (`real`) or without a real lens.
    fn for_lens(&self, real: bool) -> PathKind {
        match self.thin {
            PathKind::Hybrid if real => self.traced,
            PathKind::Raster if real && !self.raster_asked => self.traced,
            thin => thin,
        }
    }
}

/// Everything the preview starts from.
pub struct PreviewConfig {
    pub description: SceneDescription,
    /// The scene file's settings with the command line's on top.
    pub rig: CameraRig,
    /// The scene file given on the command line (for the `C` key's render command).
    pub scene_path: Option<PathBuf>,
    pub viewer: ViewerOptions,
    /// Trace the samples on the CPU (the CPU path) instead of the GPU's trace pass.
    pub cpu_path: bool,
    pub view: ViewMode,
    /// Stop after this many frames.
    pub frames: Option<u64>,
    /// Save the accumulation here on exit.
    pub screenshot: Option<PathBuf>,
    pub script: ScriptPlayer,
}

/// What the exit line reports.
#[derive(Clone, Debug)]
pub struct PreviewSummary {
    pub frames: u64,
    pub median_frame_ms: f64,
    pub median_gbuffer_ms: f64,
    pub spp: u32,
    pub target_spp: u32,
    pub median_input_to_frame_ms: Option<f64>,
    /// Samples per pixel traced per second while accumulating (first frames excluded).
    pub samples_per_pixel_per_second: Option<f64>,
    /// Median GPU time of the hybrid's plans, in the frames that made one.
    pub median_plan_ms: Option<f64>,
    /// What the frames asked of the device (the screenshot's readback excluded).
    pub counters: Option<lensray_vulkan::Counters>,
}

impl std::fmt::Display for PreviewSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "preview: {} frames drawn, median frame time {:.1} ms, median G-buffer pass {:.2} ms, \
             {} of {} samples per pixel reached",
            self.frames, self.median_frame_ms, self.median_gbuffer_ms, self.spp, self.target_spp
        )?;
        if let Some(ms) = self.median_input_to_frame_ms {
            write!(f, ", median input to frame {ms:.1} ms")?;
        }
        if let Some(ms) = self.median_plan_ms {
            write!(f, ", median hybrid plan {ms:.2} ms")?;
        }
        if let Some(rate) = self.samples_per_pixel_per_second.filter(|r| *r > 0.0) {
            write!(f, ", {rate:.3} samples per pixel per second")?;
        }
        if let Some(c) = self.counters.filter(|_| self.frames > 0) {
            let per_frame = |n: u64| n as f64 / self.frames as f64;
            write!(
                f,
                "; per frame {:.2} submits, {:.2} host waits, {:.0} bytes read back",
                per_frame(c.submits),
                per_frame(c.cpu_waits),
                per_frame(c.readback_bytes)
            )?;
        }
        Ok(())
    }
}

/// Opens the window and runs until it is closed, Escape, `--frames` or the script's `quit`.
pub fn run(config: PreviewConfig) -> Result<PreviewSummary> {
    let event_loop = EventLoop::new().map_err(|e| {
        anyhow::anyhow!(
            "cannot open a window (is a display available?): {}",
            without_source_location(&e.to_string())
        )
    })?;
    let mut app = App::new(config);
    event_loop
        .run_app(&mut app)
        .context("the window's event loop failed")?;
    app.finish()
}

/// winit's OS errors start with the winit source line that raised them ("os error at
/// <file>:<line>: <reason>"); the user needs the reason only.
fn without_source_location(message: &str) -> &str {
    message
        .strip_prefix("os error at ")
        .and_then(|rest| rest.split_once(": "))
        .map_or(message, |(_, reason)| reason)
}

struct Gui {
    ctx: egui::Context,
    state: egui_winit::State,
}

struct App {
    config: PreviewConfig,
    // Drop order: the viewer (device, surface) before the window it draws into.
    viewer: Option<Viewer>,
    /// The CPU path's worker, when it traces the samples.
    cpu_feed: Option<CpuFeed>,
    /// The GPU paths (`None` while the CPU path traces, or before the window opened).
    paths: Option<GpuPaths>,
    /// The device's counters when the frames began (after opening, the scene and `auto`).
    counters_at_start: lensray_vulkan::Counters,
    /// Samples of the current shot the CPU path delivered.
    cpu_spp: u32,
    gui: Option<Gui>,
    window: Option<Arc<Window>>,
    panel: Panel,
    input: InputState,
    log: FrameLog,
    /// What the last frame rendered: a change restarts the accumulation.
    last: Option<(Camera, RenderSettings)>,
    pending_pick: Option<Vec2>,
    /// A scripted resize not yet seen in a drawn frame (size, when asked): `wait converged`
    /// waits for it, or for 2 s if the window manager refuses it.
    awaiting_size: Option<([u32; 2], Instant)>,
    /// The view of the last frame drawn.
    shown_view: Option<ViewMode>,
    /// The window has no area: nothing to draw until it comes back.
    minimised: bool,
    spp: u32,
    converged: bool,
    last_fly: Instant,
    error: Option<anyhow::Error>,
    closed: bool,
}

impl App {
    fn new(config: PreviewConfig) -> Self {
        let panel = Panel::new(config.view, config.rig.settings().image.spp.unwrap_or(16));
        Self {
            config,
            viewer: None,
            cpu_feed: None,
            paths: None,
            counters_at_start: lensray_vulkan::Counters::default(),
            cpu_spp: 0,
            gui: None,
            window: None,
            panel,
            input: InputState::default(),
            log: FrameLog::default(),
            last: None,
            pending_pick: None,
            awaiting_size: None,
            shown_view: None,
            minimised: false,
            spp: 0,
            converged: false,
            last_fly: Instant::now(),
            error: None,
            closed: false,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        self.exit(event_loop);
    }

    fn exit(&mut self, event_loop: &ActiveEventLoop) {
        self.closed = true;
        event_loop.exit();
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let settings = self.config.rig.settings();
        let (width, height) = (
            settings
                .image
                .width
                .unwrap_or(lensray_core::settings::DEFAULT_WIDTH),
            settings
                .image
                .height
                .unwrap_or(lensray_core::settings::DEFAULT_HEIGHT),
        );
        let attributes = Window::default_attributes()
            .with_title(format!(
                "lensray preview: {}",
                self.config.description.source
            ))
            .with_inner_size(PhysicalSize::new(width, height));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot create the window")?,
        );
        let display = window.display_handle().context("window display handle")?;
        let handle = window.window_handle().context("window handle")?;
        let viewer = Viewer::new(
            &self.config.viewer,
            display.as_raw(),
            handle.as_raw(),
            &self.config.description.scene,
        )
        .context("preview")?;
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        self.gui = Some(Gui { ctx, state });
        let mut viewer = viewer;
        let path = if self.config.cpu_path {
            self.cpu_feed = Some(CpuFeed::new(&self.config.description.scene));
            "path cpu (samples traced on the CPU, shown by the GPU)".to_string()
        } else {
            let shot = self
                .config
                .rig
                .shot(&self.config.description.scene)
                .context("camera")?;
            let real_lens = shot.camera.real_lens.clone();
            let asked = self.config.viewer.estimator;
            if let (Some(real), Estimator::Hybrid) = (&real_lens, asked) {
                anyhow::bail!(
                    "--path hybrid does not trace real lenses (--lens {}): use cpu, rayquery, software or auto",
                    real.name()
                );
            }
            let renderer = viewer.renderer_mut();
            let shot = (&shot.camera, &shot.render);
            let (kind, why) = if self.config.viewer.gpu.traversal.is_some() {
                let traversal = renderer.traversal();
                (traversal.to_string(), "asked for".to_string())
            } else if asked != Estimator::Traced || real_lens.is_some() {
                // auto with a real lens: only the traversal paths trace its rays (as `render`).
                let (kind, why) = paths::pick_traversal(renderer, shot)?;
                (kind.to_string(), why)
            } else {
                // auto: any GPU path, the hybrid and raster paths included.
                let (kind, why) = paths::pick_path(renderer, shot)?;
                viewer.use_estimator(kind.estimator());
                self.config.viewer.estimator = kind.estimator();
                (kind.to_string(), why)
            };
            let traced = PathKind::of_traversal(viewer.renderer_mut().traversal());
            let thin = match self.config.viewer.estimator {
                Estimator::Hybrid => PathKind::Hybrid,
                Estimator::Raster => PathKind::Raster,
                Estimator::Traced => traced,
            };
            let raster_asked = asked == Estimator::Raster;
            self.paths = Some(GpuPaths {
                thin,
                traced,
                raster_asked,
                in_use: thin,
                first_order_noticed: false,
            });
            match asked {
                Estimator::Hybrid => {
                    format!("path hybrid (traces with {kind}: {why}; plan made on the device)")
                }
                Estimator::Raster => format!("path raster (shadow rays with {kind}: {why})"),
                Estimator::Traced => format!("path {kind} ({why})"),
            }
        };
        eprintln!("preview: {path} on {}", viewer.device_name());
        self.counters_at_start = viewer.renderer_mut().counters();
        self.viewer = Some(viewer);
        self.window = Some(window);
        Ok(())
    }

    /// Draws the lens of `real` (a real lens or not) with the path for it from now on; says so
    /// when the path changes. Called before `prepare` (which makes the path's passes), and
    /// after the panel where only a traversal path is asked for (which needs no pass of its
    /// own).
    fn follow_lens(&mut self, real: Option<&str>) {
        let (Some(paths), Some(viewer)) = (self.paths.as_mut(), self.viewer.as_mut()) else {
            return;
        };
        let want = paths.for_lens(real.is_some());
        if want == paths.in_use {
            return;
        }
        viewer.use_estimator(want.estimator());
        paths.in_use = want;
        self.converged = false;
        match real {
            Some(name) => eprintln!(
                "preview: path {want} (path {} does not trace real lenses: lens {name})",
                paths.thin
            ),
            None => eprintln!("preview: path {want} again (a thin lens)"),
        }
    }

    /// Applies a discrete action (a key, the panel's buttons or the script).
    fn act(&mut self, event_loop: &ActiveEventLoop, action: Action) -> Result<()> {
        self.log.input(Instant::now());
        let rig = &mut self.config.rig;
        match action {
            Action::FocusUnderCursor => self.pending_pick = Some(self.input.cursor),
            Action::FocusNearer => rig.step_focus(-1.0),
            Action::FocusFarther => rig.step_focus(1.0),
            Action::ApertureWider => rig.step_aperture(1),
            Action::ApertureNarrower => rig.step_aperture(-1),
            Action::ToggleProjection => rig.toggle_projection(),
            Action::SetView(view) => self.panel.view = view,
            Action::NextView => self.panel.view = self.panel.view.next(),
            Action::Screenshot => {
                let path = self.panel.screenshot_path();
                self.save_screenshot(&path)?;
            }
            Action::PrintCamera => self.print_camera()?,
            Action::ResetCamera => rig.reset(),
            Action::ToggleHelp => self.panel.show_help = !self.panel.show_help,
            Action::Quit => self.exit(event_loop),
            // Held keys move the camera every frame while down.
            Action::Fly(direction) => self.input.hold(direction, true),
        }
        Ok(())
    }

    fn gesture(&mut self, gesture: Gesture) {
        self.log.input(Instant::now());
        match gesture {
            Gesture::Orbit(d) => self.config.rig.orbit(f64::from(d.x), f64::from(d.y)),
            Gesture::Pan(d) => self.config.rig.pan(f64::from(d.x), f64::from(d.y)),
            Gesture::Click(at) => self.pending_pick = Some(at),
        }
    }

    fn scroll(&mut self, steps: f64, modifier: Option<WheelModifier>) {
        self.log.input(Instant::now());
        let rig = &mut self.config.rig;
        match wheel_action(modifier) {
            WheelAction::Dolly => rig.dolly(steps),
            WheelAction::Focus => rig.step_focus(steps),
            WheelAction::Aperture => rig.step_aperture(steps.round() as i32),
        }
    }

    fn save_screenshot(&mut self, path: &std::path::Path) -> Result<()> {
        let output = PendingOutput::create(path)?;
        let viewer = self.viewer.as_mut().context("no window yet")?;
        let image = viewer
            .read_accumulation()?
            .context("nothing rendered yet to save")?;
        let shading = match &self.last {
            Some((_, settings)) => settings.shading,
            None => {
                self.config
                    .rig
                    .shot(&self.config.description.scene)?
                    .render
                    .shading
            }
        };
        output.finish(&image, shading)?;
        eprintln!(
            "screenshot: {} ({} samples per pixel)",
            path.display(),
            self.spp
        );
        Ok(())
    }

    fn print_camera(&self) -> Result<()> {
        let resolved = self
            .config
            .rig
            .shot(&self.config.description.scene)
            .context("camera")?;
        let snippet = super::snippet::camera_snippet(
            self.config.rig.settings(),
            &resolved,
            self.config.scene_path.as_deref(),
        );
        println!("{snippet}");
        Ok(())
    }

    fn replay_script(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        if self
            .awaiting_size
            .is_some_and(|(_, asked)| asked.elapsed() > std::time::Duration::from_secs(2))
        {
            self.awaiting_size = None;
        }
        loop {
            let settled = self.converged && self.awaiting_size.is_none();
            let Some(event) = self.config.script.next_due(settled) else {
                break;
            };
            // An input is seen in a frame drawn after it: a `wait converged` that follows in
            // the same batch waits for that frame (the flag was the last frame's).
            let input = !matches!(
                event,
                ScriptEvent::WaitConverged | ScriptEvent::Screenshot(_) | ScriptEvent::Quit
            );
            if input {
                self.converged = false;
            }
            match event {
                ScriptEvent::Key(name) => {
                    let action = action_for_key(&name)
                        .with_context(|| format!("script: no action on key {name}"))?;
                    match action {
                        // A scripted press of a fly key moves the camera as one frame's hold.
                        Action::Fly(direction) => self.config.rig.fly(direction.vector(), 0.1),
                        action => self.act(event_loop, action)?,
                    }
                }
                ScriptEvent::Click { x, y } => {
                    let at = Vec2::new(x as f32, y as f32);
                    self.input.cursor = at;
                    self.pending_pick = Some(at);
                }
                ScriptEvent::Drag { button, from, to } => {
                    let [from, to] = [from, to].map(|p| Vec2::new(p[0] as f32, p[1] as f32));
                    self.input.move_to(from);
                    self.input.press(button);
                    if let Some(g) = self.input.move_to(to) {
                        self.gesture(g);
                    }
                    self.input.release(button);
                }
                ScriptEvent::Scroll { steps, modifier } => self.scroll(steps, modifier),
                ScriptEvent::Resize { width, height } => {
                    let window = self.window.as_ref().context("no window")?;
                    if width == 0 || height == 0 {
                        window.set_minimized(true);
                    } else {
                        window.set_minimized(false);
                        let _ = window.request_inner_size(PhysicalSize::new(width, height));
                        self.awaiting_size = Some(([width, height], Instant::now()));
                    }
                }
                ScriptEvent::Lens(name) => {
                    let choice = if name == "thin" {
                        LensChoice::Thin
                    } else {
                        LensChoice::Real(name)
                    };
                    let rig = &mut self.config.rig;
                    if !rig.lens_choices().contains(&choice) {
                        anyhow::bail!(
                            "script: no lens {} in the panel's picker (thin or {})",
                            choice.label(),
                            lensray_core::optics::builtin::names().join(", ")
                        );
                    }
                    self.log.input(Instant::now());
                    rig.set_lens(&choice);
                }
                ScriptEvent::WaitConverged => {}
                ScriptEvent::Screenshot(path) => self.save_screenshot(&path)?,
                ScriptEvent::Quit => self.exit(event_loop),
            }
        }
        Ok(())
    }

    fn frame(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        // A lens changed since the last frame: its path, before `prepare` makes its passes.
        let real_name = self.config.rig.readout().real.map(|r| r.name);
        self.follow_lens(real_name.as_deref());
        let (Some(window), Some(viewer)) = (self.window.clone(), self.viewer.as_mut()) else {
            return Ok(());
        };
        let size = window.inner_size();
        let Some([width, height]) = viewer.prepare([size.width, size.height])? else {
            self.minimised = true;
            return Ok(());
        };
        self.minimised = false;
        let now = Instant::now();
        let fly = self.input.fly_direction();
        if fly != glam::Vec3::ZERO {
            let seconds = (now - self.last_fly).as_secs_f64().min(0.1);
            self.config.rig.fly(fly, seconds);
        }
        self.last_fly = now;

        // The panel first: it may change the lens before this frame's camera is built.
        let gui = self.gui.as_mut().context("no GUI")?;
        let raw_input = gui.state.take_egui_input(&window);
        let stats = PanelStats {
            spp: self.spp,
            device: viewer.device_name(),
            times: self.log.last_times(),
            frame_ms: self.log.last_frame_ms(),
            lens_summary: self
                .last
                .as_ref()
                .and_then(|(camera, _)| camera.real_lens.as_ref())
                .map(|real| real.summary()),
        };
        let rig = &mut self.config.rig;
        let panel = &mut self.panel;
        let output = gui
            .ctx
            .run_ui(raw_input, |ui| panel.ui(ui.ctx(), rig, &stats));
        gui.state
            .handle_platform_output(&window, output.platform_output);
        let overlay = OverlayFrame {
            primitives: gui.ctx.tessellate(output.shapes, output.pixels_per_point),
            textures: output.textures_delta,
            pixels_per_point: output.pixels_per_point,
        };
        for action in self.panel.take_actions() {
            self.act(event_loop, action)?;
        }

        self.config.rig.set_image_size(width, height);
        let resolved = self
            .config
            .rig
            .shot(&self.config.description.scene)
            .context("camera")?;
        if let Some(real) = &resolved.camera.real_lens {
            // A real lens picked in this frame: a traversal path traces it (no pass to make).
            if self.paths.is_some_and(|p| p.for_lens(true) != p.in_use) {
                self.follow_lens(Some(real.name()));
            }
            if let Some(paths) = self
                .paths
                .as_mut()
                .filter(|p| p.in_use == PathKind::Raster && !p.first_order_noticed)
            {
                paths.first_order_noticed = true;
                eprintln!("{}", first_order_notice(real.name()));
            }
        }
        let current = (resolved.camera.clone(), resolved.render);
        let restart = self.last.as_ref() != Some(&current);
        let changed = restart || Some(self.panel.view) != self.shown_view;
        let pick = self.pending_pick.take().and_then(|at| {
            let (x, y) = (at.x.floor(), at.y.floor());
            (x >= 0.0 && y >= 0.0 && (x as u32) < width && (y as u32) < height)
                .then_some([x as u32, y as u32])
        });
        let snapshot = self.cpu_feed.as_mut().and_then(|feed| {
            feed.request(&resolved.camera, &resolved.render, self.panel.target_spp);
            feed.take_latest()
        });
        if restart {
            self.cpu_spp = 0;
        }
        if let Some(snapshot) = &snapshot {
            self.cpu_spp = snapshot.spp;
        }
        let host = self.cpu_feed.as_ref().map(|_| HostSamples {
            sums: snapshot.as_ref().map(|s| s.sums.as_slice()),
            spp: self.cpu_spp,
            converged: self.cpu_spp >= self.panel.target_spp,
        });
        let viewer = self.viewer.as_mut().context("no viewer")?;
        let result = viewer.draw(FrameRequest {
            camera: &resolved.camera,
            settings: &resolved.render,
            view: self.panel.view.code(),
            restart,
            target_spp: self.panel.target_spp,
            pick,
            overlay: Some(overlay),
            host,
        })?;
        if result.drawn {
            if changed {
                self.log.shown(Instant::now());
            }
            self.shown_view = Some(self.panel.view);
            if self
                .awaiting_size
                .is_some_and(|(size, _)| size == [width, height])
            {
                self.awaiting_size = None;
            }
            self.last = Some(current);
            self.log
                .record(now, result.times, u64::from(width) * u64::from(height));
            self.spp = result.spp;
            self.converged = result.converged;
        }
        if let Some(depth) = result.picked_depth {
            // The new focus shows from the next frame on.
            self.converged = false;
            match depth {
                Some(d) => match self.config.rig.set_focus_distance(f64::from(d)) {
                    Some(focus) if focus > f64::from(d) => eprintln!(
                        "focus: {focus:.4} (the nearest the lens focuses; the view depth under \
                         the cursor is {d:.4})"
                    ),
                    _ => eprintln!("focus: {d:.4} (view depth under the cursor)"),
                },
                None => eprintln!("focus: nothing under the cursor to focus on"),
            }
        }
        if self
            .config
            .frames
            .is_some_and(|limit| self.log.frames() >= limit)
        {
            self.exit(event_loop);
        }
        Ok(())
    }

    /// Whether more frames are needed now: accumulating, moving, a pick or a script waiting.
    fn busy(&self) -> bool {
        let converging = self.panel.view == ViewMode::Final && !self.converged;
        converging
            || self.pending_pick.is_some()
            || self.input.fly_direction() != glam::Vec3::ZERO
            || self.config.script.pending()
            || self.awaiting_size.is_some()
            || self.config.frames.is_some()
            || self.last.is_none()
    }

    /// Busy only because the CPU path has not reached the target yet.
    fn waiting_for_cpu_only(&self) -> bool {
        self.cpu_feed.is_some()
            && self.busy()
            && self.pending_pick.is_none()
            && self.input.fly_direction() == glam::Vec3::ZERO
            && !self.config.script.pending()
            && self.awaiting_size.is_none()
            && self.config.frames.is_none()
            && self.last.is_some()
    }

    fn finish(mut self) -> Result<PreviewSummary> {
        if let Some(error) = self.error.take() {
            return Err(error);
        }
        let start = self.counters_at_start;
        let counters = self
            .viewer
            .as_mut()
            .map(|v| v.renderer_mut().counters().since(&start));
        if let Some(path) = self.config.screenshot.clone() {
            self.save_screenshot(&path)?;
        }
        let summary = PreviewSummary {
            frames: self.log.frames(),
            median_frame_ms: self.log.median_frame_ms(),
            median_gbuffer_ms: self.log.median_gbuffer_ms(),
            spp: self.spp,
            target_spp: self.panel.target_spp,
            median_input_to_frame_ms: self.log.median_input_to_frame_ms(),
            samples_per_pixel_per_second: self.log.samples_per_pixel_per_second(),
            median_plan_ms: self.log.median_plan_ms(),
            counters,
        };
        self.gui = None;
        self.cpu_feed = None;
        if let Some(viewer) = self.viewer.take() {
            viewer.close().context("preview")?;
        }
        drop(self.window.take());
        Ok(summary)
    }
}

/// What `lensray render --path raster` says of a real lens (`paths::open`).
fn first_order_notice(lens: &str) -> String {
    format!(
        "notice: --path raster renders lens {lens} by its first-order model (a thin lens at its entrance pupil): no aberrations, distortion or vignetting"
    )
}

fn pointer_button(button: MouseButton) -> Option<PointerButton> {
    match button {
        MouseButton::Left => Some(PointerButton::Left),
        MouseButton::Right => Some(PointerButton::Right),
        MouseButton::Middle => Some(PointerButton::Middle),
        _ => None,
    }
}

/// winit's key as the bindings name it: named keys by their `NamedKey` name, characters
/// upper-case.
fn key_name(key: &Key) -> Option<String> {
    match key {
        Key::Named(named) => Some(format!("{named:?}")),
        Key::Character(c) => Some(c.to_uppercase()),
        _ => None,
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() && !self.closed {
            if let Err(e) = self.open(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(window) = self.window.clone() else {
            return;
        };
        let consumed = match self.gui.as_mut() {
            Some(gui) => gui.state.on_window_event(&window, &event).consumed,
            None => false,
        };
        let result = match event {
            WindowEvent::CloseRequested => {
                self.exit(event_loop);
                Ok(())
            }
            WindowEvent::RedrawRequested => self.frame(event_loop),
            WindowEvent::ModifiersChanged(m) => {
                let state: ModifiersState = m.state();
                self.input.ctrl = state.control_key();
                self.input.shift = state.shift_key();
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                let at = Vec2::new(position.x as f32, position.y as f32);
                if let Some(g) = self.input.move_to(at).filter(|_| !consumed) {
                    self.gesture(g);
                }
                Ok(())
            }
            WindowEvent::MouseInput { state, button, .. } if !consumed => {
                if let Some(button) = pointer_button(button) {
                    match state {
                        ElementState::Pressed => self.input.press(button),
                        ElementState::Released => {
                            if let Some(g) = self.input.release(button) {
                                self.gesture(g);
                            }
                        }
                    }
                }
                Ok(())
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                let modifier = if self.input.ctrl {
                    Some(WheelModifier::Ctrl)
                } else if self.input.shift {
                    Some(WheelModifier::Shift)
                } else {
                    None
                };
                self.scroll(steps, modifier);
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } if !consumed => {
                let down = event.state == ElementState::Pressed;
                match key_name(&event.logical_key).and_then(|k| action_for_key(&k)) {
                    Some(Action::Fly(direction)) => {
                        self.input.hold(direction, down);
                        Ok(())
                    }
                    Some(action) if down && !event.repeat => self.act(event_loop, action),
                    _ => Ok(()),
                }
            }
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.fail(event_loop, e);
            return;
        }
        // Any input shows in the next frame.
        window.request_redraw();
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.closed {
            return;
        }
        if let Err(e) = self.replay_script(event_loop) {
            self.fail(event_loop, e);
            return;
        }
        if self.minimised {
            // Nothing to draw: wake for the script's next event, or when the window returns
            // (its resize event asks for a frame).
            self.log.pause();
            let wake = self.config.script.pending().then(|| {
                self.config
                    .script
                    .next_wake()
                    .unwrap_or_else(|| Instant::now() + std::time::Duration::from_millis(50))
            });
            event_loop.set_control_flow(match wake {
                Some(at) => ControlFlow::WaitUntil(at),
                None => ControlFlow::Wait,
            });
            return;
        }
        if self.waiting_for_cpu_only() {
            // The CPU path traces on its worker: look for its samples now and then instead of
            // drawing frames that would take the cores it needs.
            let at = Instant::now() + CPU_PATH_POLL;
            event_loop.set_control_flow(ControlFlow::WaitUntil(at));
            if let Some(window) = &self.window {
                window.request_redraw();
            }
        } else if self.busy() {
            event_loop.set_control_flow(ControlFlow::Poll);
            if let Some(window) = &self.window {
                window.request_redraw();
            }
        } else if let Some(at) = self.config.script.next_wake() {
            event_loop.set_control_flow(ControlFlow::WaitUntil(at));
        } else {
            // Converged and idle: sleep until the next input.
            self.log.pause();
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::without_source_location;

    #[test]
    fn winit_errors_lose_their_source_location() {
        assert_eq!(
            without_source_location(
                "os error at /home/u/.cargo/registry/src/winit-0.30.13/src/platform_impl/linux/mod.rs:765: neither WAYLAND_DISPLAY nor WAYLAND_SOCKET nor DISPLAY is set."
            ),
            "neither WAYLAND_DISPLAY nor WAYLAND_SOCKET nor DISPLAY is set."
        );
        assert_eq!(without_source_location("no display"), "no display");
    }
}
