//! The Vulkan renderer on whatever ray-query device is present (lavapipe on CI), validation on:
//! every test ends by checking that the validation layer reported nothing, also after the
//! renderer (device, instance) was destroyed.
//!
//! Without a ray-query device (or the validation layer) these tests fail, unless
//! LENSRAY_SKIP_GPU_TESTS=1; then they are skipped, and scripts/test.sh reports how many.

mod support;

#[path = "renderer/device.rs"]
mod device;
#[path = "renderer/environment.rs"]
mod environment;
#[path = "renderer/gbuffer.rs"]
mod gbuffer;
#[path = "renderer/mirrors.rs"]
mod mirrors;
#[path = "renderer/renders.rs"]
mod renders;
