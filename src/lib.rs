//! lensray: thin-lens depth of field, rendered by a CPU reference and (later) Vulkan paths that
//! are checked against it.

pub mod camera;
pub mod gpu;
pub mod render;
pub mod sampler;
pub mod scene;
pub mod settings;
