//! Frame statistics of the preview: wall-clock frame times and the GPU times of its passes,
//! summarised by medians (the exit line and the panel).

use std::time::Instant;

use lensray_core::stats::median;
use lensray_vulkan::FrameTimes;

#[derive(Debug, Default)]
pub struct FrameLog {
    frames: u64,
    previous: Option<Instant>,
    /// Wall-clock time between consecutive frames, ms.
    frame_ms: Vec<f64>,
    gbuffer_ms: Vec<f64>,
    /// GPU times of the hybrid's plans (frames that made one).
    plan_ms: Vec<f64>,
    last_times: Option<FrameTimes>,
    /// The oldest input not yet shown by a frame.
    input_at: Option<Instant>,
    /// From an input to the submission of the first frame that shows it, ms.
    input_to_frame_ms: Vec<f64>,
    /// Samples per pixel traced (finished frames' trace work over the image's pixels) and the
    /// frame intervals they came in, ms, from frame SETTLE_FRAMES on (pipeline compiles and the
    /// first plan excluded).
    samples_per_pixel: f64,
    sampled_ms: f64,
}

/// Frames left out of the sample rate at the start.
const SETTLE_FRAMES: u64 = 5;

impl FrameLog {
    /// A frame was drawn at `at`; `times` are the GPU times of an earlier finished frame.
    /// `pixels`: of the image.
    pub fn record(&mut self, at: Instant, times: Option<FrameTimes>, pixels: u64) {
        self.frames += 1;
        let settled = self.frames > SETTLE_FRAMES;
        if let Some(previous) = self.previous {
            let ms = (at - previous).as_secs_f64() * 1e3;
            self.frame_ms.push(ms);
            if settled {
                self.sampled_ms += ms;
            }
        }
        self.previous = Some(at);
        if let Some(t) = times {
            if t.gbuffer_drawn {
                self.gbuffer_ms.push(t.gbuffer_ms);
            }
            if t.plan_ms > 0.0 {
                self.plan_ms.push(t.plan_ms);
            }
            self.last_times = Some(t);
            if settled {
                self.samples_per_pixel += t.trace_work as f64 / pixels.max(1) as f64;
            }
        }
    }

    /// Samples per pixel traced per second of frames (None before any was timed): the rate
    /// at which the accumulation grows while nothing moves.
    pub fn samples_per_pixel_per_second(&self) -> Option<f64> {
        (self.sampled_ms > 0.0).then(|| self.samples_per_pixel / (self.sampled_ms * 1e-3))
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

    /// Median GPU time of the hybrid's plans (None: no plan was made).
    pub fn median_plan_ms(&self) -> Option<f64> {
        (!self.plan_ms.is_empty()).then(|| median(&self.plan_ms))
    }

    pub fn last_frame_ms(&self) -> Option<f64> {
        self.frame_ms.last().copied()
    }

    pub fn last_times(&self) -> Option<FrameTimes> {
        self.last_times
    }
}
