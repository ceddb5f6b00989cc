//! A keyframed shot in the window: the frame the clock, the slider, the keys or the script
//! pick, and the camera of that frame, made from the settings `render --frames` renders it
//! with.

use std::time::Instant;

use anyhow::Result;

use super::App;
use crate::preview::rig::CameraRig;
use lensray_core::settings::shot::camera_frame;
use lensray_core::settings::{shutter, Shot};

/// What the play and frame keys say without keyframes.
const NO_KEYFRAMES: &str =
    "the scene has no [[keyframe]]s to play (C prints one for the current view)";

impl App {
    /// Where the frame to show changed (playing, or picked), makes the camera anew from that
    /// frame's settings at the window's size; a change by hand holds until then. The lights
    /// stay where the first frame laid them, as a sequence's do.
    pub(super) fn follow_frame(&mut self, now: Instant) {
        let Some(playback) = self.config.playback.as_mut() else {
            return;
        };
        let Some(frame) = playback.next_frame(now) else {
            return;
        };
        let fps = playback.clock.fps();
        let mut settings = playback.frames().at(frame);
        let current = self.config.rig.settings();
        settings.image.width = current.image.width;
        settings.image.height = current.image.height;
        settings.light = current.light.clone();
        // Motion blur as the window has it (B toggles it).
        settings.camera.shutter = current.camera.shutter.clone();
        match CameraRig::new(settings, &self.config.description.scene) {
            Ok(rig) => self.config.rig = rig,
            Err(e) => eprintln!("frame {frame}: {e} (the camera stays)"),
        }
        self.pose(frame, fps);
    }

    /// Poses what the file's animations move at frame `frame` (at `fps`), as `render --frames`
    /// does, the meshes moving over the frame's shutter where the window's motion blur is on,
    /// and hands the pose to the path tracing the samples; the accumulation restarts. The
    /// camera's framing stays the scene's at rest, as a sequence's does.
    pub(super) fn pose(&mut self, frame: u32, fps: f64) {
        let Some(motion) = &self.config.description.motion else {
            return;
        };
        let time = f64::from(frame) / fps;
        let scene = self
            .posed
            .get_or_insert_with(|| self.config.description.scene.clone());
        motion.pose(scene, time);
        let shutter = shutter(self.config.rig.settings()).ok().flatten();
        let steps = shutter.and_then(|s| s.object_motion(motion, f64::from(frame), fps));
        if let Some(feed) = self.cpu_feed.as_mut() {
            feed.load_scene(scene, steps.as_ref());
        } else if let Some(viewer) = self.viewer.as_mut() {
            if let Err(e) = viewer.load_scene(scene, steps.as_ref()) {
                if !std::mem::replace(&mut self.said_meshes_stand, true) {
                    eprintln!("motion blur: {e}; the meshes stand at each frame's time (--path software blurs them)");
                }
                if let Err(e) = viewer.load_scene(scene, None) {
                    eprintln!("the pose at {time:.3} s: {e} (the scene stays)");
                }
            }
        }
        self.last = None;
    }

    /// Poses the frame shown again (motion blur turned on or off).
    pub(super) fn pose_again(&mut self) {
        if let Some(playback) = self.config.playback.as_ref() {
            let (frame, fps) = (playback.clock.frame(), playback.clock.fps());
            self.pose(frame, fps);
        }
    }

    /// Plays the shot from the frame shown, or pauses on the frame it reached.
    pub(super) fn play_pause(&mut self, now: Instant) {
        let Some(playback) = self.config.playback.as_mut() else {
            eprintln!("playback: {NO_KEYFRAMES}");
            return;
        };
        let clock = &mut playback.clock;
        clock.toggle(now);
        if clock.is_playing() {
            eprintln!(
                "playback: playing from frame {} at {} fps",
                clock.frame(),
                clock.fps()
            );
        } else {
            eprintln!("playback: paused at frame {}", clock.frame());
        }
    }

    /// The frame `by` frames on (back where negative), within the keyframes' range.
    pub(super) fn step_frame(&mut self, by: i64, now: Instant) {
        match self.config.playback.as_mut() {
            Some(playback) => playback.clock.step(by, now),
            None => eprintln!("frames: {NO_KEYFRAMES}"),
        }
    }

    /// The script's `frame N`: the slider set to `frame`; outside the keyframes' range, the
    /// nearest frame of it, with a warning.
    pub(super) fn set_frame(&mut self, frame: u32, now: Instant) -> Result<()> {
        let Some(playback) = self.config.playback.as_mut() else {
            anyhow::bail!("script: frame {frame}: {NO_KEYFRAMES}");
        };
        let (first, last) = playback.clock.range();
        if !(first..=last).contains(&frame) {
            eprintln!(
                "warning: script: frame {frame} is outside the keyframes' frames {first} to {last}: the nearest is shown"
            );
        }
        playback.clock.set_frame(frame, now);
        Ok(())
    }

    /// `shot` moving over its frame's shutter as `render --frames` renders it (motion blur, a
    /// rolling shutter: `FrameSettings::moving`), while the camera is the frame's keyed one; a
    /// camera moved by hand, or a shot without keyframes, holds still.
    pub(super) fn moving(&self, shot: Shot) -> Result<Shot> {
        let Some(playback) = self.config.playback.as_ref() else {
            return Ok(shot);
        };
        let frame = playback.clock.frame();
        let description = &self.config.description;
        let Ok(keyed) = camera_frame(&playback.frames().at(frame), &description.scene) else {
            return Ok(shot);
        };
        let shown = &shot.camera.frame;
        let moved = [
            keyed.eye - shown.eye,
            keyed.forward - shown.forward,
            keyed.true_up - shown.true_up,
        ];
        if moved
            .iter()
            .any(|d| d.length() > 1e-5 * (1.0 + shown.eye.length()))
        {
            return Ok(shot);
        }
        let shutter = shutter(self.config.rig.settings())?;
        playback.frames().moving_through(
            shutter,
            frame,
            shot,
            &description.scene,
            &description.source,
        )
    }

    /// The frame a `[[keyframe]]` printout names: the one shown, or 1 without keyframes (a
    /// shot's start).
    pub(super) fn keyframe_number(&self) -> u32 {
        self.config.playback.as_ref().map_or(1, |p| p.clock.frame())
    }
}
