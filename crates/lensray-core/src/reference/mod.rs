//! The CPU reference renderer: the ground truth every GPU path is compared with.
//!
//! Shading definitions (the GPU compute pass implements the same, see `shaders/passes/trace.comp`):
//! - Camera rays: `Camera::generate_ray` from the shared sampler's `camera_sample`, t in (0, inf).
//! - `unlit`: the base colour of the first hit, background on a miss.
//! - `lit`: the emission plus, for each of the scene's lights, f(l, v) * E * cos when a shadow
//!   ray from `surface::shadow_origin` towards the light, t in (0, d), is unoccluded
//!   (`lighting`), plus the environment (a uniform sky or a map) by multiple importance
//!   sampling of the environment and the BRDF (`sky`, `brdf_sampling`); f is glTF's
//!   metallic-roughness BRDF (`brdf`); background (or the map) on a miss. Emissive triangles
//!   light too, drawn by their power and weighed against the BRDF's draws (`emitters`). With
//!   `bounces` > 1 the path goes on along the BRDF's draw (`integrator`).
//! - Single-sided surfaces (`Material::double_sided` false): a ray of any kind (camera, shadow,
//!   environment, bounce) that meets one from behind (`is_back_face`: it sees the triangle
//!   clockwise) passes through it, on every path.
//! - `unlit` and `lit` average their `spp` samples per pixel.
//! - AOVs (`depth`, `normal`, `albedo`) are what the raster G-buffer holds: the surface seen by
//!   the aperture-centre ray through each pixel centre (one ray per pixel, no lens blur).

mod accel;
pub mod brdf;
pub mod brdf_sampling;
pub mod clearcoat;
mod embree;
mod emitters;
mod integrator;
#[cfg(test)]
mod layer_tests;
mod lighting;
mod rays;
mod render;
pub mod sheen;
mod sky;
mod steps;
mod surface;
mod surface_frame;
mod transmission;
mod triangle;

pub use accel::{is_back_face, packet_alignment, Accel, AlphaTest, Hit, PacketMask, PACKET_SIZE};
pub use embree::{
    cpu_name, EmbreeConfigError, EmbreeReport, EmbreeSettings, Isa, EMBREE_CONFIG_VAR,
};
pub use rays::first_order_rays;
pub use render::{RenderStats, Renderer};
pub use surface::{shadow_origin, SurfacePoint};
pub use triangle::WatertightRay;
