//! Scripted input: the script's events that are due, played as real input would be.

use std::time::Instant;

use anyhow::{Context as _, Result};
use glam::Vec2;
use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;

use super::App;
use crate::preview::bindings::{action_for_key, Action};
use crate::preview::rig::LensChoice;
use crate::preview::script::ScriptEvent;

impl App {
    /// Plays the script's events that are due (a `wait converged` once the frames settled).
    pub(super) fn replay_script(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
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
                ScriptEvent::Click { x, y, shift } => {
                    let at = Vec2::new(x as f32, y as f32);
                    self.input.cursor = at;
                    self.plane_pick = shift;
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
                ScriptEvent::Frame(frame) => {
                    self.log.input(Instant::now());
                    self.set_frame(frame, Instant::now())?;
                }
                ScriptEvent::WaitConverged => {}
                ScriptEvent::Screenshot(path) => self.save_screenshot(&path)?,
                ScriptEvent::Quit => self.exit(event_loop),
            }
        }
        Ok(())
    }
}
