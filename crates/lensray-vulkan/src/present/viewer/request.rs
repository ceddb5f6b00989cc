//! What the application asks of the viewer (its options, a frame's request, samples traced on
//! the host) and what a frame answers (its result and GPU times).

use crate::present::overlay::OverlayFrame;
use crate::{Estimator, GpuOptions};
use lensray_core::settings::Shot;

/// How the window waits for the display (VkPresentModeKHR).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PresentMode {
    /// Wait for vertical blank, never tear (always available).
    #[default]
    Fifo,
    /// Replace the queued image with the newest: no tearing, no waiting.
    Mailbox,
    /// Present at once; may tear.
    Immediate,
}

impl PresentMode {
    pub const ALL: [PresentMode; 3] = [Self::Fifo, Self::Mailbox, Self::Immediate];

    /// The name `--present-mode` takes.
    pub fn name(self) -> &'static str {
        match self {
            Self::Fifo => "fifo",
            Self::Mailbox => "mailbox",
            Self::Immediate => "immediate",
        }
    }
}

/// What the next frame shows.
pub struct FrameRequest<'a> {
    /// The camera and the render settings the frame shows.
    pub shot: &'a Shot,
    /// `lensray_core::interface::VIEW_*`. Samples are added only in the final view.
    pub view: u32,
    /// How the final view's accumulation is exposed and tone mapped (as a PNG of the shot).
    pub display: lensray_core::film::tonemap::Display,
    /// The camera, lens or shading changed: the accumulation starts again.
    pub restart: bool,
    pub target_spp: u32,
    /// Read the G-buffer's view depth at this pixel (answered in this frame's result).
    pub pick: Option<[u32; 2]>,
    pub overlay: Option<OverlayFrame>,
    /// The samples come from the host (the CPU path) instead of the trace pass.
    pub host: Option<HostSamples<'a>>,
}

/// Samples traced on the host for the frame's camera.
pub struct HostSamples<'a> {
    /// New sums and counts of the whole image (`[r, g, b, n]` per pixel, row-major) to show
    /// from this frame on; `None` keeps what the accumulation holds.
    pub sums: Option<&'a [[f32; 4]]>,
    /// Samples every pixel has (adaptively: the pixels still sampling), and whether no pixel
    /// takes more.
    pub spp: u32,
    pub converged: bool,
    /// As `FrameResult::adaptive_active`, of the host's rounds.
    pub adaptive_active: Option<usize>,
}

/// GPU times of one finished frame, ms (timestamps).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameTimes {
    /// The G-buffer pass, or the view pass in the frames of a non-final view.
    pub gbuffer_ms: f64,
    /// Whether the frame drew either (the final view skips the G-buffer once every pixel has
    /// a sample).
    pub gbuffer_drawn: bool,
    /// The trace dispatches (and a restart's clear), the plan excluded.
    pub trace_ms: f64,
    pub resolve_ms: f64,
    /// The hybrid's plan (and lit shortcut pre-pass), in the frames that make one; else 0.
    pub plan_ms: f64,
    /// Copy to the window and the panel.
    pub present_ms: f64,
    pub total_ms: f64,
    /// Pixel-samples the frame traced.
    pub trace_work: u64,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameResult {
    /// False when nothing was drawn (window minimised or being resized).
    pub drawn: bool,
    /// Samples every pixel has (sampling adaptively: the pixels still sampling).
    pub spp: u32,
    pub converged: bool,
    /// Sampling adaptively (`--noise-threshold`): the pixels still taking samples (0 once
    /// every pixel converged or reached the cap); `None`: every pixel takes the same samples.
    pub adaptive_active: Option<usize>,
    /// With a pick: the view depth there, `None` where no surface covers the pixel.
    pub picked_depth: Option<Option<f32>>,
    /// Times of the latest finished frame.
    pub times: Option<FrameTimes>,
}

pub struct ViewerOptions {
    pub gpu: GpuOptions,
    pub present_mode: PresentMode,
    /// How the window adds samples: traced, as the raster path (per sample a visibility pass
    /// through its lens point, then the shading pass: docs/raster.md) or as the hybrid
    /// (docs/hybrid.md, "In the preview").
    pub estimator: Estimator,
}
