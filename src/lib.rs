//! lensray: thin-lens depth of field, rendered by a CPU reference and Vulkan paths that are
//! checked against it.

#![deny(unsafe_code)]

pub mod bench;
pub mod camera;
pub mod cli;
pub mod film;
// The Vulkan module is the only place allowed to use `unsafe` (each block says why).
#[allow(unsafe_code)]
pub mod gpu;
pub mod interface;
pub mod output;
pub mod paths;
pub mod preview;
pub mod reference;
pub mod sampler;
pub mod scene;
pub mod settings;
pub mod stats;
