//! Vulkan itself: instance and validation, device selection and submissions, buffers, images,
//! queries, pipelines, embedded SPIR-V, host data in the shaders' layouts (`conv`), and errors.

pub mod buffer;
pub mod conv;
pub mod device;
pub mod error;
pub mod image;
pub mod instance;
pub mod pipeline;
pub mod pipeline_cache;
pub mod query;
pub mod shader;
