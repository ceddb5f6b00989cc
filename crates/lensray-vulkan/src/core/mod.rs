//! Vulkan itself: instance and validation, device selection and submissions, buffers, images,
//! queries, pipelines, embedded SPIR-V, the window surface and errors. It knows nothing of
//! cameras or scenes.

pub mod adapter;
pub mod buffer;
pub mod counters;
pub mod device;
pub mod error;
pub mod image;
pub mod instance;
pub mod pipeline;
pub mod pipeline_cache;
pub mod query;
pub mod shader;
pub mod surface;
