//! The Vulkan renderer on whatever ray-query device is present (lavapipe on CI), validation on:
//! every test ends by checking that the validation layer reported nothing, also after the
//! renderer (device, instance) was destroyed.
//!
//! Without a ray-query device (or the validation layer) these tests fail, unless
//! LENSRAY_SKIP_GPU_TESTS=1; then they are skipped, and scripts/test.sh reports how many.

mod gpu_support;

#[path = "gpu/device.rs"]
mod device;
#[path = "gpu/gbuffer.rs"]
mod gbuffer;
#[path = "gpu/mirrors.rs"]
mod mirrors;
#[path = "gpu/renders.rs"]
mod renders;
