//! The preview window's presentation (on the surface and swapchain of `core`): frames in
//! flight, the resolve of the accumulation into a display image, the view pass, the egui
//! overlay, and the `viewer` that drives a frame.

pub(crate) mod frames;
pub(crate) mod overlay;
pub(crate) mod resolve;
pub(crate) mod view_pass;
pub(crate) mod viewer;
