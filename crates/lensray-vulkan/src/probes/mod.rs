//! Probes for tests and benchmarks (feature `probes`, which the crate's own tests and benches
//! turn on): the GLSL mirrors of the camera and sampler (`mirrors`), the hybrid plan's host
//! reference (`hybrid_plan`), the shared structs as the shaders read them (`layouts`), the
//! preview's two view routes (`view_routes`), the sample generation's cost (`sampler_cost`),
//! pass timings (`timing`) and the GLSL mirror of the spectral weighting (`spectral`).

pub(crate) mod hybrid_plan;
pub(crate) mod layouts;
pub(crate) mod mirrors;
pub(crate) mod sampler_cost;
pub(crate) mod spectral;
pub(crate) mod timing;
pub(crate) mod view_routes;
