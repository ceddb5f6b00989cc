//! The hybrid path (docs/hybrid.md): the raster G-buffer decides where rays are needed. Per
//! call of `add_samples`, one submission on the device (`GpuRenderer::plan_on_device`): the
//! G-buffer of the shot, the lit pre-pass under lit shading, then the plan pass (lensray-vulkan's
//! `passes::hybrid_plan`, shaders/passes/hybrid_plan.comp: circle of confusion from the
//! G-buffer depth, maximum over 8x8 tiles, dilated by each tile's maximum over the tiles it
//! reaches; edge marks in a summed-area table; one entry per pixel) written straight into the
//! trace pass's plan buffer, with no readback; then the trace pass in its hybrid mode
//! (shaders/passes/trace.comp) with the device's fastest traversal. Per pixel:
//! - no G-buffer edge within the pixel's dilated CoC (at least one pixel; so in particular a
//!   dilated CoC under half a pixel with a uniform neighbourhood; lit, a shadow boundary found
//!   by the lit pre-pass counts as an edge): the *shortcut*. Unlit its value is the G-buffer's
//!   albedo; lit, per sample, the pre-pass's image (each pixel's surface shaded along its
//!   aperture-centre ray, with one shadow ray) interpolated where the sample's lens ray meets
//!   the pixel's surface depth. Each sample is traced too with probability
//!   1 / HYBRID_CHECK_INVERSE (a hash of the 8x8 tile and the sample) and adds
//!   (traced - shortcut) * HYBRID_CHECK_INVERSE: unbiased;
//! - otherwise every sample is traced. So the samples a pixel costs grow with its dilated CoC
//!   through the window it must see uniform: from the shortcut's checks (spp / 32) to spp. (A
//!   plan entry may stop a pixel's count at `n` < spp; fewer samples where the CoC is small
//!   measured worse at equal error, docs/hybrid.md, so the plan does not);
//! - the 8 pixels of a tile row share one decision (they run in lockstep).
//!
//! `plan` holds the same rules on the host: `Plan::new` is the reference the device plan is
//! checked against (`host_plan` reads the G-buffer back and plans on the host, `device_plan`
//! reads the device's entries back; tests/hybrid.rs compares them). A render reads none of the
//! plan back (`GpuPath::last_plan` does, when asked).
//!
//! Whether a pixel traces sample `i` depends on the plan (camera, settings, scene) only, never on
//! the range asked for, so any split of a range gives the same sums, as for every path.

mod plan;

pub use plan::{device_plan, host_plan, window_radius, Plan, SEGMENT, SHORTCUT_COC, TILE};
