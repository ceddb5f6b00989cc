//! lensray: thin-lens depth of field, rendered by a CPU reference and (later) Vulkan paths that
//! are checked against it.

pub mod camera;
pub mod gpu;
pub mod output;
pub mod reference;
pub mod render;
pub mod resolve;
pub mod sampler;
pub mod scene;
pub mod settings;
