//! Vulkan itself: instance and validation, device selection and submissions, buffers, images,
//! queries, pipelines and the ray-tracing pipeline's shader binding table, render passes, fences and semaphores, embedded SPIR-V, the window
//! surface and its swapchain, and errors. It knows nothing of cameras or scenes. The crate's
//! `unsafe` code lives here, behind owning types and safe methods.

pub(crate) mod accel;
pub(crate) mod adapter;
pub(crate) mod buffer;
pub(crate) mod counters;
pub(crate) mod descriptors;
pub(crate) mod device;
pub(crate) mod error;
pub(crate) mod features;
pub(crate) mod image;
pub(crate) mod instance;
pub(crate) mod pipeline;
pub(crate) mod pipeline_cache;
pub(crate) mod query;
pub(crate) mod recorder;
pub(crate) mod render_pass;
pub(crate) mod sbt;
pub(crate) mod shader;
pub(crate) mod surface;
pub(crate) mod swapchain;
pub(crate) mod sync;
