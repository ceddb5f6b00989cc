//! The preview window's presentation: the swapchain (on the surface of `core::surface`), frames
//! in flight, the resolve of the accumulation into a display image, the view pass, the egui
//! overlay, and the `viewer` that drives a frame.

pub(crate) mod frames;
pub(crate) mod overlay;
pub(crate) mod resolve;
pub(crate) mod swapchain;
pub(crate) mod view_pass;
pub(crate) mod viewer;
