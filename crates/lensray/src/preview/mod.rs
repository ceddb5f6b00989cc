//! `lensray preview`: the window (`app`, winit + the egui `panel`, drawn by `gpu::Viewer`) and
//! its logic, which knows nothing of winit, Vulkan or egui and is unit-tested: the interactive
//! camera (`rig`), what the window shows (`view`), the controls (`bindings`, `input`), scripted
//! input (`script`, `player`), the camera printout (`snippet`), frame statistics (`frame_log`)
//! and a keyframed shot's frame and playback (`playback`).

pub mod app;
pub mod bindings;
pub mod cpu_feed;
pub mod frame_log;
pub mod input;
pub mod panel;
pub mod playback;
pub mod player;
pub mod rig;
pub mod script;
pub mod snippet;
pub mod view;

#[cfg(test)]
pub(crate) mod test_scene;

pub use bindings::{action_for_key, controls_help, Action};
pub use rig::{CameraRig, LensChoice, LensReadout, RealLensReadout};
pub use script::{ScriptEvent, TimedEvent};
pub use view::ViewMode;
