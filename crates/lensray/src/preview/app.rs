//! The preview window: a winit application whose frames the GPU viewer draws. Input (real or
//! scripted) moves the camera rig; every change restarts the accumulation; once the target
//! sample count is reached the event loop waits for input and uses no CPU.

mod actions;
mod flare;
mod frame;
mod open;
mod replay;
mod shot_frames;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result};
use glam::Vec2;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, ModifiersState};
use winit::window::{Window, WindowId};

use super::bindings::{action_for_key, Action, PointerButton, WheelModifier};
use super::cpu_feed::CpuFeed;
use super::frame_log::FrameLog;
use super::input::InputState;
use super::panel::Panel;
use super::playback::Playback;
use super::player::ScriptPlayer;
use super::rig::CameraRig;
use super::view::ViewMode;
use lensray_core::scene::file::SceneDescription;
use lensray_core::settings::Shot;
use lensray_vulkan::{Viewer, ViewerOptions};
use open::GpuPaths;

/// How often the window looks for the CPU path's samples while it waits for them.
const CPU_PATH_POLL: std::time::Duration = std::time::Duration::from_millis(30);

/// Everything the preview starts from.
pub struct PreviewConfig {
    pub description: SceneDescription,
    /// The scene file's settings with the command line's on top (with keyframes, the first
    /// keyed frame's).
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
    /// The scene's keyframed shot, where it has keyframes: the frame shown and its settings.
    pub playback: Option<Playback>,
}

/// What the exit line reports.
#[derive(Clone, Debug)]
pub struct PreviewSummary {
    pub frames: u64,
    pub median_frame_ms: f64,
    pub median_gbuffer_ms: f64,
    pub spp: u32,
    pub target_spp: u32,
    /// Sampling adaptively: the pixels still taking samples (`FrameResult::adaptive_active`).
    pub adaptive_active: Option<usize>,
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
        match self.adaptive_active {
            Some(0) => write!(f, ", adaptive: every pixel converged or at the cap")?,
            Some(n) => write!(f, ", adaptive: {n} pixels still sampling")?,
            None => {}
        }
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
    /// The CPU path's samples are all added, and its adaptive rounds' active pixels
    /// (`cpu_feed::Snapshot`).
    cpu_converged: bool,
    cpu_active: Option<usize>,
    gui: Option<Gui>,
    window: Option<Arc<Window>>,
    panel: Panel,
    input: InputState,
    log: FrameLog,
    /// What the last frame rendered: a change restarts the accumulation.
    last: Option<Shot>,
    /// An animated file's scene posed at the frame shown (`None`: at rest).
    posed: Option<lensray_core::scene::Scene>,
    /// Whether the window said that its path does not blur moving meshes (it says so once).
    said_meshes_stand: bool,
    /// The lens's own light the final view adds (`app/flare.rs`), and whether the window
    /// said why it cannot draw one (it says so once).
    flare: Option<flare::ShownFlare>,
    said_flare: bool,
    pending_pick: Option<Vec2>,
    /// Whether the pending pick is a point of the plane of focus (Shift+click).
    plane_pick: bool,
    /// The world points Shift+clicks picked so far (three lay the plane of focus).
    plane_points: Vec<glam::DVec3>,
    /// A scripted resize not yet seen in a drawn frame (size, when asked): `wait converged`
    /// waits for it, or for 2 s if the window manager refuses it.
    awaiting_size: Option<([u32; 2], Instant)>,
    /// The view of the last frame drawn.
    shown_view: Option<ViewMode>,
    /// The exposure and tone map of the last frame drawn.
    shown_display: Option<lensray_core::film::tonemap::Display>,
    /// The window has no area: nothing to draw until it comes back.
    minimised: bool,
    spp: u32,
    converged: bool,
    /// `FrameResult::adaptive_active` of the last frame drawn.
    adaptive_active: Option<usize>,
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
            cpu_converged: false,
            cpu_active: None,
            gui: None,
            window: None,
            panel,
            input: InputState::default(),
            log: FrameLog::default(),
            last: None,
            posed: None,
            said_meshes_stand: false,
            flare: None,
            said_flare: false,
            pending_pick: None,
            plane_pick: false,
            plane_points: Vec::new(),
            awaiting_size: None,
            shown_view: None,
            shown_display: None,
            minimised: false,
            spp: 0,
            converged: false,
            adaptive_active: None,
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
            || self.playing()
    }

    /// A keyframed shot plays: every frame may show the next of its frames.
    fn playing(&self) -> bool {
        self.config
            .playback
            .as_ref()
            .is_some_and(|p| p.clock.is_playing())
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
            && !self.playing()
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
            adaptive_active: self.adaptive_active,
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
