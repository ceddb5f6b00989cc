//! SPIR-V compiled by build.rs from `shaders/` (the probes' with the `probes` feature only), embedded, and turned into shader modules.

use std::io::Cursor;

use ash::vk;

use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};

macro_rules! spirv {
    ($name:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".spv"))
    };
}

pub(crate) const GBUFFER_VERT: &[u8] = spirv!("gbuffer.vert");
pub(crate) const GBUFFER_FRAG: &[u8] = spirv!("gbuffer.frag");
pub(crate) const VIEW_FRAG: &[u8] = spirv!("view.frag");
pub(crate) const TRACE_RAYQUERY_COMP: &[u8] = spirv!("trace_rayquery.comp");
pub(crate) const TRACE_SOFTWARE_COMP: &[u8] = spirv!("trace_software.comp");
pub(crate) const RESOLVE_COMP: &[u8] = spirv!("resolve.comp");
pub(crate) const VISIBILITY_VERT: &[u8] = spirv!("visibility.vert");
pub(crate) const VISIBILITY_FRAG: &[u8] = spirv!("visibility.frag");
pub(crate) const HYBRID_PLAN_COMP: &[u8] = spirv!("hybrid_plan.comp");
#[cfg(feature = "probes")]
pub(crate) const MIRRORS_COMP: &[u8] = spirv!("mirrors.comp");
#[cfg(feature = "probes")]
pub(crate) const LAYOUTS_COMP: &[u8] = spirv!("layouts.comp");
#[cfg(feature = "probes")]
pub(crate) const SAMPLER_COST_COMP: &[u8] = spirv!("sampler_cost.comp");
#[cfg(feature = "probes")]
pub(crate) const SPECTRAL_COMP: &[u8] = spirv!("spectral.comp");

/// A hash (FNV-1a, 64 bits) of every shader lensray renders with: a driver compiles them again
/// when they change, so the pipeline cache's file is named by it.
pub(crate) fn shaders_hash() -> u64 {
    [
        GBUFFER_VERT,
        GBUFFER_FRAG,
        VIEW_FRAG,
        TRACE_RAYQUERY_COMP,
        TRACE_SOFTWARE_COMP,
        RESOLVE_COMP,
        VISIBILITY_VERT,
        VISIBILITY_FRAG,
        HYBRID_PLAN_COMP,
    ]
    .iter()
    .flat_map(|spirv| spirv.iter())
    .fold(0xcbf2_9ce4_8422_2325, |hash, &byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A shader module, destroyed on drop (once its pipelines are created).
pub(crate) struct ShaderModule<'a> {
    ctx: &'a Context,
    pub module: vk::ShaderModule,
}

impl<'a> ShaderModule<'a> {
    pub(crate) fn new(ctx: &'a Context, spirv: &[u8]) -> Result<Self, GpuError> {
        // `read_spv` copies into u32 words: include_bytes! gives no alignment guarantee.
        let words = ash::util::read_spv(&mut Cursor::new(spirv))
            .map_err(|e| GpuError::Invalid(format!("embedded SPIR-V is malformed: {e}")))?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: `words` is SPIR-V produced by shaderc in build.rs.
        let module = unsafe { ctx.device.create_shader_module(&info, None) }
            .map_err(vk_err("vkCreateShaderModule"))?;
        Ok(Self { ctx, module })
    }
}

impl Drop for ShaderModule<'_> {
    fn drop(&mut self) {
        // SAFETY: modules may be destroyed as soon as the pipelines using them exist.
        unsafe { self.ctx.device.destroy_shader_module(self.module, None) };
    }
}
