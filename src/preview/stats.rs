//! Frame statistics of the preview: wall-clock frame times and the GPU times of its passes,
//! summarised by medians (the exit line and the panel).

use std::time::Instant;

use crate::gpu::FrameTimes;
use crate::render::stats::median;

#[derive(Debug, Default)]
pub struct FrameLog {
    frames: u64,
    previous: Option<Instant>,
    /// Wall-clock time between consecutive frames, ms.
    frame_ms: Vec<f64>,
    gbuffer_ms: Vec<f64>,
    last_times: Option<FrameTimes>,
    /// The oldest input not yet shown by a frame.
    input_at: Option<Instant>,
    /// From an input to the submission of the first frame that shows it, ms.
    input_to_frame_ms: Vec<f64>,
}

impl FrameLog {
    /// A frame was drawn at `at`; `times` are the GPU times of an earlier finished frame.
    pub fn record(&mut self, at: Instant, times: Option<FrameTimes>) {
        self.frames += 1;
        if let Some(previous) = self.previous {
            self.frame_ms.push((at - previous).as_secs_f64() * 1e3);
        }
        self.previous = Some(at);
        if let Some(t) = times {
            self.gbuffer_ms.push(t.gbuffer_ms);
            self.last_times = Some(t);
        }
    }

    /// An input that changes the picture arrived.
    pub fn input(&mut self, at: Instant) {
        self.input_at.get_or_insert(at);
    }

    /// The frame submitted at `at` shows every input so far.
    pub fn shown(&mut self, at: Instant) {
        if let Some(input) = self.input_at.take() {
            self.input_to_frame_ms
                .push((at - input).as_secs_f64() * 1e3);
        }
    }

    /// Median time from an input to the submission of the frame showing it (None: no input).
    pub fn median_input_to_frame_ms(&self) -> Option<f64> {
        (!self.input_to_frame_ms.is_empty()).then(|| median(&self.input_to_frame_ms))
    }

    /// The event loop slept (converged): the next frame's interval is not a frame time.
    pub fn pause(&mut self) {
        self.previous = None;
    }

    pub fn frames(&self) -> u64 {
        self.frames
    }

    pub fn median_frame_ms(&self) -> f64 {
        median(&self.frame_ms)
    }

    pub fn median_gbuffer_ms(&self) -> f64 {
        median(&self.gbuffer_ms)
    }

    pub fn last_frame_ms(&self) -> Option<f64> {
        self.frame_ms.last().copied()
    }

    pub fn last_times(&self) -> Option<FrameTimes> {
        self.last_times
    }
}
