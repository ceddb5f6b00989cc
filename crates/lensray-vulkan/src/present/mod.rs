//! The preview window's presentation: the swapchain (on the surface of `core::surface`), frames
//! in flight, the resolve of the accumulation into a display image, the view pass, the egui
//! overlay, and the `viewer` that drives a frame.

pub mod frames;
pub mod overlay;
pub mod resolve;
pub mod swapchain;
pub mod view_pass;
pub mod viewer;
