//! Vulkan itself: instance and validation, device selection and submissions, buffers, images,
//! queries, pipelines, embedded SPIR-V and errors. It knows nothing of cameras or scenes.

pub mod buffer;
pub mod device;
pub mod error;
pub mod image;
pub mod instance;
pub mod pipeline;
pub mod pipeline_cache;
pub mod query;
pub mod shader;
