//! The preview's frame of a keyframed shot and its playback clock. Playing, the frame follows
//! the wall clock: the frame playback started from plus the seconds since times the frames per
//! second, rounded down, looping from the last keyed frame back to the first (a shot is watched
//! over and over while it is framed). Paused, the frame stays where it is.
//!
//! Each frame's settings are `render --frames`' ([`FrameSettings`]); the window's camera is
//! made anew from them whenever the frame changes, so a change by hand holds until then.

use std::time::Instant;

use crate::frame_settings::FrameSettings;

/// A keyframed shot in the preview: each frame's settings and the clock that picks the frame.
#[derive(Clone, Debug)]
pub struct Playback {
    pub clock: PlaybackClock,
    frames: FrameSettings,
    /// The frame the camera was last made for.
    shown: Option<u32>,
}

impl Playback {
    /// The camera shows `shown` already (the preview opens on it).
    pub fn new(frames: FrameSettings, clock: PlaybackClock, shown: Option<u32>) -> Self {
        Self {
            clock,
            frames,
            shown,
        }
    }

    pub fn frames(&self) -> &FrameSettings {
        &self.frames
    }

    /// Advances the clock to `now`; the frame to show, where it is not the one shown.
    pub fn next_frame(&mut self, now: Instant) -> Option<u32> {
        self.clock.tick(now);
        let frame = self.clock.frame();
        (self.shown != Some(frame)).then(|| {
            self.shown = Some(frame);
            frame
        })
    }
}

/// The frame shown, over the keyframes' range, and whether it plays.
#[derive(Clone, Debug, PartialEq)]
pub struct PlaybackClock {
    first: u32,
    last: u32,
    fps: f64,
    frame: u32,
    /// While playing: when the clock started and the frame it started from.
    started: Option<(Instant, u32)>,
}

impl PlaybackClock {
    /// Paused at `first`, over frames `first` to `last` (both in), playing at `fps`.
    pub fn new((first, last): (u32, u32), fps: f64) -> Self {
        Self {
            first,
            last: last.max(first),
            fps,
            frame: first,
            started: None,
        }
    }

    pub fn frame(&self) -> u32 {
        self.frame
    }

    /// The first and last frames.
    pub fn range(&self) -> (u32, u32) {
        (self.first, self.last)
    }

    pub fn fps(&self) -> f64 {
        self.fps
    }

    pub fn is_playing(&self) -> bool {
        self.started.is_some()
    }

    /// The frame `seconds` after frame `from` while playing: `from + floor(seconds x fps)`,
    /// looping over the range.
    pub fn frame_after(&self, from: u32, seconds: f64) -> u32 {
        let length = u64::from(self.last - self.first) + 1;
        let advanced = (seconds.max(0.0) * self.fps).floor() as u64;
        let offset =
            (u64::from(from.clamp(self.first, self.last) - self.first) + advanced) % length;
        self.first + offset as u32
    }

    /// Plays from the frame shown, or pauses on it.
    pub fn toggle(&mut self, now: Instant) {
        self.tick(now);
        self.started = match self.started {
            Some(_) => None,
            None => Some((now, self.frame)),
        };
    }

    /// Shows `frame` (clamped to the range); while playing, playback goes on from it.
    pub fn set_frame(&mut self, frame: u32, now: Instant) {
        self.frame = frame.clamp(self.first, self.last);
        if self.started.is_some() {
            self.started = Some((now, self.frame));
        }
    }

    /// Moves `by` frames (clamped to the range).
    pub fn step(&mut self, by: i64, now: Instant) {
        let frame = (i64::from(self.frame) + by).clamp(0, i64::from(u32::MAX));
        self.set_frame(frame as u32, now);
    }

    /// Advances a playing clock to `now`.
    pub fn tick(&mut self, now: Instant) {
        if let Some((start, from)) = self.started {
            let seconds = now.saturating_duration_since(start).as_secs_f64();
            self.frame = self.frame_after(from, seconds);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn elapsed_time_gives_the_frame() {
        let clock = PlaybackClock::new((1, 120), 24.0);
        // floor(t x 24) frames on from the start.
        assert_eq!(clock.frame_after(1, 0.0), 1);
        assert_eq!(clock.frame_after(1, 0.99 / 24.0), 1);
        assert_eq!(clock.frame_after(1, 1.0 / 24.0), 2);
        assert_eq!(clock.frame_after(1, 2.5), 61);
        assert_eq!(clock.frame_after(10, 0.5), 22);
        // The last frame, then back to the first: 120 frames last 5 s.
        assert_eq!(clock.frame_after(1, 119.0 / 24.0), 120);
        assert_eq!(clock.frame_after(1, 5.0), 1);
        assert_eq!(clock.frame_after(100, 1.0), 4);
        assert_eq!(clock.frame_after(1, 12.5), 61);
        let slow = PlaybackClock::new((0, 9), 2.0);
        assert_eq!(slow.frame_after(0, 3.0), 6);
        assert_eq!(slow.frame_after(8, 3.0), 4);
        // One keyed frame: it stays.
        let single = PlaybackClock::new((5, 5), 24.0);
        assert_eq!(single.frame_after(5, 100.0), 5);
    }

    #[test]
    fn play_pause_and_set_frame() {
        let t0 = Instant::now();
        let at = |s: f64| t0 + Duration::from_secs_f64(s);
        let mut clock = PlaybackClock::new((1, 48), 24.0);
        assert_eq!((clock.frame(), clock.is_playing()), (1, false));
        clock.tick(at(1.0));
        assert_eq!(clock.frame(), 1, "paused, the frame stays");
        clock.toggle(at(1.0));
        clock.tick(at(1.5));
        assert_eq!(clock.frame(), 13);
        // Pausing keeps the frame playback reached.
        clock.toggle(at(1.75));
        assert_eq!((clock.frame(), clock.is_playing()), (19, false));
        clock.tick(at(9.0));
        assert_eq!(clock.frame(), 19);
        // Playing on from there.
        clock.toggle(at(10.0));
        clock.tick(at(10.25));
        assert_eq!(clock.frame(), 25);
        // The slider while playing: playback goes on from the frame set.
        clock.set_frame(40, at(11.0));
        clock.tick(at(11.5));
        assert_eq!(clock.frame(), 4, "40 + 12 = 52 loops to frame 4 of 1-48");
        clock.toggle(at(11.5));
        clock.set_frame(500, at(12.0));
        assert_eq!(clock.frame(), 48, "clamped to the range");
        clock.step(1, at(12.0));
        assert_eq!(clock.frame(), 48);
        clock.step(-3, at(12.0));
        assert_eq!(clock.frame(), 45);
        clock.set_frame(0, at(12.0));
        clock.step(-1, at(12.0));
        assert_eq!(clock.frame(), 1);
    }
}
