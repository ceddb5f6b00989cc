//! SPIR-V compiled by build.rs from `shaders/` (the probes' with the `probes` feature only), embedded, and turned into shader modules.

use std::io::Cursor;

use ash::vk;

use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};
use crate::core::pipeline::{RayStages, RayTracingDesc};

macro_rules! spirv {
    ($name:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".spv"))
    };
}

pub(crate) const GBUFFER_VERT: &[u8] = spirv!("gbuffer.vert");
pub(crate) const GBUFFER_FRAG: &[u8] = spirv!("gbuffer.frag");
/// The raster stages' builds for the surfaces with none of their pass's bits (build.rs,
/// PLAIN_SURFACES).
pub(crate) const GBUFFER_PLAIN_VERT: &[u8] = spirv!("gbuffer_plain.vert");
pub(crate) const GBUFFER_PLAIN_FRAG: &[u8] = spirv!("gbuffer_plain.frag");
pub(crate) const VISIBILITY_PLAIN_VERT: &[u8] = spirv!("visibility_plain.vert");
pub(crate) const VISIBILITY_PLAIN_FRAG: &[u8] = spirv!("visibility_plain.frag");
pub(crate) const TRACE_RAYQUERY_COMP: &[u8] = spirv!("trace_rayquery.comp");
pub(crate) const TRACE_SOFTWARE_COMP: &[u8] = spirv!("trace_software.comp");
/// The ray-tracing pipeline's trace pass: trace.comp as its ray generation stage, and its kinds
/// of ray in RT_RAY_* order (closest hit, shadow).
pub(crate) const TRACE_RTPIPELINE: RayTracingDesc<'static> = RayTracingDesc {
    raygen: spirv!("trace_rtpipeline.rgen"),
    rays: &[
        RayStages {
            miss: spirv!("rt_miss.rmiss"),
            closest_hit: Some(spirv!("rt_hit.rchit")),
            any_hit: Some(spirv!("rt_hit.rahit")),
        },
        RayStages {
            miss: spirv!("rt_shadow.rmiss"),
            closest_hit: None,
            any_hit: Some(spirv!("rt_shadow.rahit")),
        },
    ],
};
pub(crate) const RESOLVE_COMP: &[u8] = spirv!("resolve.comp");
pub(crate) const VISIBILITY_VERT: &[u8] = spirv!("visibility.vert");
pub(crate) const VISIBILITY_FRAG: &[u8] = spirv!("visibility.frag");
pub(crate) const HYBRID_PLAN_COMP: &[u8] = spirv!("hybrid_plan.comp");
pub(crate) const GHOSTS_COMP: &[u8] = spirv!("ghosts.comp");
#[cfg(feature = "probes")]
pub(crate) const MIRRORS_COMP: &[u8] = spirv!("mirrors.comp");
#[cfg(feature = "probes")]
pub(crate) const LAYOUTS_COMP: &[u8] = spirv!("layouts.comp");
#[cfg(feature = "probes")]
pub(crate) const SAMPLER_COST_COMP: &[u8] = spirv!("sampler_cost.comp");
#[cfg(feature = "probes")]
pub(crate) const SPECTRAL_COMP: &[u8] = spirv!("spectral.comp");
#[cfg(feature = "probes")]
pub(crate) const ENVIRONMENT_COMP: &[u8] = spirv!("environment.comp");
#[cfg(feature = "probes")]
pub(crate) const TONEMAP_COMP: &[u8] = spirv!("tonemap.comp");

/// A pipeline's vertex and fragment stages.
pub(crate) type RasterStages = (&'static [u8], &'static [u8]);

/// The view pass's builds of gbuffer.vert and view.frag for `$view` (build.rs): for any surfaces,
/// then for plain ones.
macro_rules! view_stages {
    ($view:literal) => {
        [
            (
                include_bytes!(concat!(env!("OUT_DIR"), "/view_", $view, ".vert.spv")),
                include_bytes!(concat!(env!("OUT_DIR"), "/view_", $view, ".frag.spv")),
            ),
            (
                include_bytes!(concat!(env!("OUT_DIR"), "/view_", $view, "_plain.vert.spv")),
                include_bytes!(concat!(env!("OUT_DIR"), "/view_", $view, "_plain.frag.spv")),
            ),
        ]
    };
}

/// The view pass's stages, entry `view - VIEW_ALBEDO` (VIEW_ALBEDO to VIEW_COC).
pub(crate) const VIEW_STAGES: [[RasterStages; 2]; 4] = [
    view_stages!("albedo"),
    view_stages!("normal"),
    view_stages!("depth"),
    view_stages!("coc"),
];

/// A hash (FNV-1a, 64 bits) of every shader lensray renders with: a driver compiles them again
/// when they change, so the pipeline cache's file is named by it.
pub(crate) fn shaders_hash() -> u64 {
    let view_stages = VIEW_STAGES
        .iter()
        .flatten()
        .flat_map(|&(vert, frag)| [vert, frag]);
    [
        GBUFFER_VERT,
        GBUFFER_FRAG,
        GBUFFER_PLAIN_VERT,
        GBUFFER_PLAIN_FRAG,
        TRACE_RAYQUERY_COMP,
        TRACE_SOFTWARE_COMP,
        TRACE_RTPIPELINE.raygen,
        RESOLVE_COMP,
        VISIBILITY_VERT,
        VISIBILITY_FRAG,
        VISIBILITY_PLAIN_VERT,
        VISIBILITY_PLAIN_FRAG,
        HYBRID_PLAN_COMP,
    ]
    .into_iter()
    .chain(view_stages)
    .chain(TRACE_RTPIPELINE.rays.iter().flat_map(|r| {
        [Some(r.miss), r.closest_hit, r.any_hit]
            .into_iter()
            .flatten()
    }))
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
