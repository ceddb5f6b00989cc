//! `lensray preview`'s logic without a window: the interactive camera, what the window shows,
//! the controls, scripted input, and the camera printout. The Vulkan viewer and the event loop
//! drive these; nothing here knows about winit, Vulkan or egui, so all of it is unit-tested.

pub mod bindings;
pub mod rig;
pub mod script;
pub mod snippet;
pub mod view;

#[cfg(test)]
pub(crate) mod test_scene;

pub use bindings::{action_for_key, controls_help, Action};
pub use rig::{CameraRig, LensReadout};
pub use script::{ScriptEvent, TimedEvent};
pub use view::ViewMode;
