//! Probes for tests and benchmarks (feature `probes`, which the crate's own tests and benches
//! turn on): the GLSL mirrors of the camera and sampler (`mirrors`), the hybrid plan's host
//! reference (`hybrid_plan`), the shared structs as the shaders read them (`layouts`), the
//! preview's two view routes (`view_routes`), the sample generation's cost (`sampler_cost`),
//! pass timings (`timing`), the GLSL mirrors of the spectral weighting (`spectral`), of the
//! environment map's lookup and sampling (`environment`) and of the tone maps (`tonemap`).

pub(crate) mod environment;
pub(crate) mod hybrid_plan;
pub(crate) mod layouts;
pub(crate) mod mirrors;
pub(crate) mod sampler_cost;
pub(crate) mod spectral;
pub(crate) mod timing;
pub(crate) mod tonemap;
pub(crate) mod view_routes;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::recorder::Access;
use lensray_core::interface::PROBE_GROUP_SIZE;

/// Runs a probe's pipeline once over `count` queries (its push constant) and waits until
/// `output`, which the shader writes, can be read on the host.
pub(crate) fn run_probe(
    ctx: &Context,
    pipeline: &Pipeline,
    count: u32,
    output: &Buffer,
) -> Result<(), GpuError> {
    ctx.submit_and_wait(|rec| {
        let groups = [count.div_ceil(PROBE_GROUP_SIZE), 1, 1];
        let push = bytemuck::bytes_of(&count);
        rec.dispatch(
            pipeline,
            push,
            groups,
            &[(output.buffer, Access::ComputeWrite)],
        );
        rec.read_on_host(&[output]);
        Ok(())
    })
}
