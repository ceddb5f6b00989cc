//! lensray: thin-lens depth of field, rendered by a CPU reference and Vulkan paths that are
//! checked against it.

pub mod camera;
pub mod cli;
pub mod gpu;
pub mod output;
pub mod reference;
pub mod render;
pub mod resolve;
pub mod sampler;
pub mod scene;
pub mod settings;
