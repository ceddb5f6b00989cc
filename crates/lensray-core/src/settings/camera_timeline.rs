//! A sequence's camera moved by the glTF animation of the scene's camera: frame N is at N / fps
//! seconds on the file's timeline (frame 0 at 0 s), and its eye, target and up are the
//! animated node's position, a point along its view direction (-Z) and its +Y axis. The target
//! lies at the frame's focus distance, or where none is given at the distance of the settings'
//! own target (for a glTF camera, the depth of the scene's centre at rest: the focus a single
//! render of the file gets), else 1 m; its distance only sets the default focus.

use glam::DVec3;

use crate::scene::CameraAnimation;
use crate::settings::Settings;

/// A camera animation on a sequence's frames.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraTimeline {
    animation: CameraAnimation,
    fps: f64,
}

impl CameraTimeline {
    /// `animation` at `fps` frames per second (positive, as `settings::fps` checks).
    pub fn new(animation: CameraAnimation, fps: f64) -> Self {
        Self { animation, fps }
    }

    pub fn animation(&self) -> &CameraAnimation {
        &self.animation
    }

    /// Frames per second.
    pub fn fps(&self) -> f64 {
        self.fps
    }

    /// The time of `frame` on the file's timeline, seconds.
    pub fn time(&self, frame: u32) -> f64 {
        f64::from(frame) / self.fps
    }

    /// The frames from the animation's first key to its last (the first at or before it, the
    /// last at or after it).
    pub fn frame_range(&self) -> (u32, u32) {
        let (start, end) = self.animation.time_range();
        let frame = |t: f64| t.clamp(0.0, f64::from(u32::MAX)) as u32;
        (
            frame((start * self.fps).floor()),
            frame((end * self.fps).ceil()),
        )
    }

    /// `settings` with the camera's eye, target and up at `frame`.
    pub fn settings_at(&self, settings: &Settings, frame: u32) -> Settings {
        self.settings_at_time(settings, f64::from(frame))
    }

    /// [`Self::settings_at`] a fractional frame `frame` (a time within a frame's shutter).
    pub fn settings_at_time(&self, settings: &Settings, frame: f64) -> Settings {
        let pose = self.animation.pose_at(frame / self.fps);
        let c = &settings.camera;
        let own_distance = c
            .eye
            .zip(c.target)
            .map(|(e, t)| DVec3::from(t).distance(DVec3::from(e)))
            .filter(|d| d.is_finite() && *d > 0.0);
        let distance = c.focus_distance.or(own_distance).unwrap_or(1.0);
        let mut out = settings.clone();
        out.camera.eye = Some(pose.eye.to_array());
        out.camera.target = Some((pose.eye + pose.forward * distance).to_array());
        out.camera.up = Some(pose.up.to_array());
        out
    }

    /// This timeline in a world scaled by `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            animation: self.animation.scaled(factor),
            fps: self.fps,
        }
    }
}
