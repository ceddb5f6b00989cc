//! Discrete actions (keys, the panel's buttons, the script), mouse gestures and the wheel,
//! applied to the camera rig and the panel; the screenshot and the camera printout.

use std::time::Instant;

use anyhow::{Context as _, Result};
use winit::event_loop::ActiveEventLoop;

use super::App;
use crate::output::PendingOutput;
use crate::preview::bindings::{wheel_action, Action, WheelAction, WheelModifier};
use crate::preview::input::Gesture;
use lensray_core::scene::units::SceneUnits;

impl App {
    /// Applies a discrete action (a key, the panel's buttons or the script).
    pub(super) fn act(&mut self, event_loop: &ActiveEventLoop, action: Action) -> Result<()> {
        let now = Instant::now();
        self.log.input(now);
        let rig = &mut self.config.rig;
        match action {
            Action::FocusUnderCursor => self.pending_pick = Some(self.input.cursor),
            Action::FocusNearer => rig.step_focus(-1.0),
            Action::FocusFarther => rig.step_focus(1.0),
            Action::ApertureWider => rig.step_aperture(1),
            Action::ApertureNarrower => rig.step_aperture(-1),
            Action::ToggleProjection => rig.toggle_projection(),
            Action::ToggleMotionBlur => {
                let on = rig.toggle_motion_blur();
                eprintln!("motion blur: {}", if on { "on" } else { "off" });
                // The file's moving meshes go with their steps, or without.
                self.pose_again();
            }
            Action::SetView(view) => self.panel.view = view,
            Action::NextView => self.panel.view = self.panel.view.next(),
            Action::Screenshot => {
                let path = self.panel.screenshot_path();
                self.save_screenshot(&path)?;
            }
            Action::PrintCamera => self.print_camera()?,
            Action::ResetCamera => rig.reset(),
            Action::PlayPause => self.play_pause(now),
            Action::PreviousFrame => self.step_frame(-1, now),
            Action::NextFrame => self.step_frame(1, now),
            Action::ToggleHelp => self.panel.show_help = !self.panel.show_help,
            Action::Quit => self.exit(event_loop),
            // Held keys move the camera every frame while down.
            Action::Fly(direction) => self.input.hold(direction, true),
        }
        Ok(())
    }

    /// Applies a mouse gesture: orbit, pan or a click that focuses there.
    pub(super) fn gesture(&mut self, gesture: Gesture) {
        self.log.input(Instant::now());
        match gesture {
            Gesture::Orbit(d) => self.config.rig.orbit(f64::from(d.x), f64::from(d.y)),
            Gesture::Pan(d) => self.config.rig.pan(f64::from(d.x), f64::from(d.y)),
            Gesture::Click(at) => {
                // Shift+click: a point of the plane of focus (three lay it).
                self.plane_pick = self.input.shift;
                self.pending_pick = Some(at);
            }
        }
    }

    /// Applies wheel steps: dolly, or with a modifier, focus or aperture.
    pub(super) fn scroll(&mut self, steps: f64, modifier: Option<WheelModifier>) {
        self.log.input(Instant::now());
        let rig = &mut self.config.rig;
        match wheel_action(modifier) {
            WheelAction::Dolly => rig.dolly(steps),
            WheelAction::Focus => rig.step_focus(steps),
            WheelAction::Aperture => rig.step_aperture(steps.round() as i32),
        }
    }

    /// Saves the accumulation as an image file at `path`.
    pub(super) fn save_screenshot(&mut self, path: &std::path::Path) -> Result<()> {
        let output = PendingOutput::create(path)?;
        let viewer = self.viewer.as_mut().context("no window yet")?;
        let mut image = viewer
            .read_accumulation()?
            .context("nothing rendered yet to save")?;
        let shot = match &self.last {
            Some(shot) => shot.clone(),
            None => self.config.rig.shot(&self.config.description.scene)?,
        };
        // With the lens's own light the final view adds.
        if let Some(flare) = self.flare.as_ref().filter(|f| f.is_of(&shot)) {
            for (pixel, light) in image.pixels.iter_mut().zip(&flare.light.pixels) {
                *pixel += *light;
            }
        }
        // As the final view shows it (a PNG), or linear (an EXR, unless --expose-exr).
        let exposure = self.config.rig.exposure(&shot.camera)?;
        output.finish(&image, shot.render.shading, &exposure)?;
        eprintln!(
            "screenshot: {} ({} samples per pixel)",
            path.display(),
            self.spp
        );
        Ok(())
    }

    /// Prints the current camera as scene-file tables, a `lensray render` command and a
    /// `[[keyframe]]` at the frame shown (the `C` key).
    fn print_camera(&self) -> Result<()> {
        let resolved = self
            .config
            .rig
            .shot(&self.config.description.scene)
            .context("camera")?;
        let snippet = crate::preview::snippet::camera_snippet(
            self.config.rig.settings(),
            &resolved,
            self.config.scene_path.as_deref(),
            self.config.description.units,
        );
        let frame = self.keyframe_number();
        let units = self.config.description.units;
        let keyframe =
            crate::preview::snippet::keyframe_table(self.config.rig.settings(), frame, units);
        let lengths = match units {
            SceneUnits::M => String::new(),
            units => format!("; lengths in {units}"),
        };
        println!("{snippet}# keyframe (frame {frame}{lengths}):\n{keyframe}");
        Ok(())
    }
}
