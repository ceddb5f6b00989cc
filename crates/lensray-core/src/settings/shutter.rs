//! When the shutter is open about a frame's own time (frame N at N / fps seconds): motion blur
//! and a rolling shutter (`camera::motion` states the model).
//!
//! - The exposure: `camera.exposure.shutter` seconds when given (the time the exposure uses,
//!   so that exposure and blur agree), else `angle` degrees of a frame (default 180).
//! - The readout of a rolling shutter: `rolling` seconds from the top row's opening to the
//!   bottom row's (default 0).
//! - The span, from the first row's opening to the last row's closing, is the exposure plus
//!   the readout; `position` puts its start, centre or end at the frame's time.
//!
//! Without motion blur a row is an instant (exposure 0), so a rolling shutter alone skews what
//! moves without blurring it.

use super::{fps, Settings, SettingsError, ShutterPosition, Switch};
use crate::camera::{CameraFrame, CameraMotion};
use crate::interface::MOTION_STEPS;
use crate::scene::motion::{ObjectMotion, SceneMotion};
use crate::scene::Scene;

/// The default shutter angle, degrees: half a frame, as film cameras' 180-degree shutter.
pub const DEFAULT_SHUTTER_ANGLE: f64 = 180.0;

/// A frame's shutter, in frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shutter {
    /// How long each row is open (0 without motion blur).
    pub exposure: f64,
    /// How much later the bottom row opens than the top one.
    pub readout: f64,
    pub position: ShutterPosition,
}

/// The shutter `settings` ask for, or `None` when nothing moves while it is open (motion blur
/// off and no rolling shutter); an error names a value out of range.
pub fn shutter(settings: &Settings) -> Result<Option<Shutter>, SettingsError> {
    let s = &settings.camera.shutter;
    let bad = |what: String| Err(SettingsError::Shutter(what));
    let blur = s.motion_blur == Some(Switch::On);
    let rolling = s.rolling.unwrap_or(0.0);
    if let Some(angle) = s
        .angle
        .filter(|a| !(a.is_finite() && *a > 0.0 && *a <= 360.0))
    {
        return bad(format!(
            "the shutter angle must be above 0 and at most 360 degrees, got {angle}"
        ));
    }
    if !(rolling.is_finite() && (0.0..=60.0).contains(&rolling)) {
        return bad(format!(
            "the rolling shutter's readout must be from 0 to 60 seconds, got {rolling}"
        ));
    }
    if !blur && rolling == 0.0 {
        return Ok(None);
    }
    let rate = fps(settings)?;
    let exposure = match (blur, settings.camera.exposure.shutter) {
        (false, _) => 0.0,
        (true, Some(seconds)) if seconds.is_finite() && seconds > 0.0 => seconds * rate,
        (true, Some(seconds)) => {
            return bad(format!(
                "the shutter time must be a positive number of seconds, got {seconds}"
            ))
        }
        (true, None) => s.angle.unwrap_or(DEFAULT_SHUTTER_ANGLE) / 360.0,
    };
    if !exposure.is_finite() {
        return bad(format!(
            "the shutter is open for {exposure} frames at {rate} fps: too long to take"
        ));
    }
    Ok(Some(Shutter {
        exposure,
        readout: rolling * rate,
        position: s.position.unwrap_or(ShutterPosition::Center),
    }))
}

impl Shutter {
    /// The span's start and end, frames from the frame's own time.
    pub fn span(&self) -> (f64, f64) {
        let length = self.exposure + self.readout;
        match self.position {
            ShutterPosition::Start => (0.0, length),
            ShutterPosition::Center => (-0.5 * length, 0.5 * length),
            ShutterPosition::End => (-length, 0.0),
        }
    }

    /// The exposure's and the readout's shares of the span (`CameraMotion`'s).
    pub fn shares(&self) -> (f32, f32) {
        let length = self.exposure + self.readout;
        (
            (self.exposure / length) as f32,
            (self.readout / length) as f32,
        )
    }

    /// The times (frames) of the camera's poses over frame `frame`'s span: MOTION_STEPS of
    /// them, evenly spaced from its start to its end.
    pub fn step_frames(&self, frame: f64) -> Vec<f64> {
        let (start, end) = self.span();
        let last = f64::from(MOTION_STEPS - 1);
        (0..MOTION_STEPS)
            .map(|k| frame + start + (end - start) * f64::from(k) / last)
            .collect()
    }

    /// The meshes `motion` moves over frame `frame`'s span (frames at `rate` a second, frame
    /// N at N / rate seconds), at its steps: what a path meets at a sample's moment; `None`
    /// when none moves then.
    pub fn object_motion(
        &self,
        motion: &SceneMotion,
        frame: f64,
        rate: f64,
    ) -> Option<ObjectMotion> {
        let times: Vec<f64> = self
            .step_frames(frame)
            .iter()
            .map(|step| step / rate)
            .collect();
        motion.steps(&times, self.frame_moment())
    }

    /// Where the frame's own time lies in its span, in [0, 1].
    pub fn frame_moment(&self) -> f32 {
        let (start, end) = self.span();
        (-start / (end - start)) as f32
    }

    /// The camera's motion over frame `frame`'s span: its pose at each step from the settings
    /// at that time (`settings_at`, of a fractional frame), `None` when it stays put and
    /// nothing else moves (`objects_move`: the samples' moments still place what moves).
    pub fn camera_motion(
        &self,
        frame: f64,
        settings_at: &dyn Fn(f64) -> Settings,
        scene: &Scene,
        objects_move: bool,
    ) -> Result<Option<CameraMotion>, SettingsError> {
        let frames: Vec<CameraFrame> = self
            .step_frames(frame)
            .into_iter()
            .map(|t| super::shot::camera_frame(&settings_at(t), scene))
            .collect::<Result<_, _>>()?;
        let (exposure, readout) = self.shares();
        let motion = CameraMotion::through(&frames, exposure, readout);
        Ok((objects_move || !motion.stands_still()).then_some(motion))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::ShutterSettings;

    fn with(shutter: ShutterSettings, seconds: Option<f64>) -> Settings {
        let mut s = Settings::default();
        s.camera.shutter = shutter;
        s.camera.exposure.shutter = seconds;
        s.image.fps = Some(24.0);
        s
    }

    #[test]
    fn the_span_is_the_angle_or_the_shutter_time_plus_the_readout() {
        let on = ShutterSettings {
            motion_blur: Some(Switch::On),
            ..ShutterSettings::default()
        };
        let half = shutter(&with(on.clone(), None)).unwrap().unwrap();
        assert_eq!(half.exposure, 0.5);
        assert_eq!(half.span(), (-0.25, 0.25));
        let timed = shutter(&with(on.clone(), Some(1.0 / 48.0)))
            .unwrap()
            .unwrap();
        assert!((timed.exposure - 0.5).abs() < 1e-12);
        let rolling = ShutterSettings {
            rolling: Some(1.0 / 24.0),
            position: Some(ShutterPosition::Start),
            angle: Some(90.0),
            ..on
        };
        let r = shutter(&with(rolling, None)).unwrap().unwrap();
        assert_eq!((r.exposure, r.readout), (0.25, 1.0));
        assert_eq!(r.span(), (0.0, 1.25));
        assert_eq!(r.shares(), (0.2, 0.8));
        let steps = r.step_frames(10.0);
        assert_eq!(steps.len(), MOTION_STEPS as usize);
        assert_eq!((steps[0], steps[steps.len() - 1]), (10.0, 11.25));
    }

    #[test]
    fn nothing_moves_without_blur_or_readout_and_bad_values_are_named() {
        assert_eq!(shutter(&with(ShutterSettings::default(), None)), Ok(None));
        let alone = ShutterSettings {
            rolling: Some(0.01),
            ..ShutterSettings::default()
        };
        let r = shutter(&with(alone, None)).unwrap().unwrap();
        assert_eq!((r.exposure, r.shares()), (0.0, (0.0, 1.0)));
        for angle in [0.0, -10.0, 361.0, f64::NAN] {
            let s = ShutterSettings {
                motion_blur: Some(Switch::On),
                angle: Some(angle),
                ..ShutterSettings::default()
            };
            let err = shutter(&with(s, None)).unwrap_err().to_string();
            assert!(err.contains("shutter angle"), "{err}");
        }
        let s = ShutterSettings {
            rolling: Some(-1.0),
            ..ShutterSettings::default()
        };
        assert!(shutter(&with(s, None)).is_err());
        let on = ShutterSettings {
            motion_blur: Some(Switch::On),
            ..ShutterSettings::default()
        };
        let err = shutter(&with(on, Some(1e308))).unwrap_err().to_string();
        assert!(err.contains("too long"), "{err}");
    }
}
