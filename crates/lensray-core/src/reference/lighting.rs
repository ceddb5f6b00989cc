//! Direct light at a surface point (`lit`): the scene's lights, each through a shadow ray, and the
//! uniform environment through one cosine-distributed ray (weighed by the surface's occlusion
//! map), each reflected by the surface's metallic-roughness BRDF (`brdf`).
//! shaders/include/shading.glsl mirrors it.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::accel::PACKET_SIZE;
use super::brdf::MetallicRoughness;
use super::render::Renderer;
use super::surface::{shadow_origin, SurfacePoint};
use crate::scene::light::cosine_direction;
use crate::scene::Light;

/// What a sample's shading draws: the blend key of its shadow and environment rays and the
/// point of [0, 1)^2 that picks its environment direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightDraw {
    pub shadow_key: u32,
    pub environment: Vec2,
}

/// What a surface point's material gives its shading, textures applied: its BRDF, its
/// emission and the share of the environment's light that reaches it (its occlusion map).
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadingInputs {
    pub brdf: MetallicRoughness,
    pub emission: Vec3,
    pub occlusion: f32,
}

/// A packet lane's surface waiting for its direct light: the point, its BRDF and occlusion, the
/// unit direction to the viewer, and what its shadow and environment rays draw.
#[derive(Clone, Copy, Debug)]
pub(super) struct LitLane {
    pub surface: SurfacePoint,
    pub brdf: MetallicRoughness,
    pub occlusion: f32,
    pub to_viewer: Vec3,
    pub draw: LightDraw,
}

impl LitLane {
    /// f(l, v) cos(n, l) of light arriving from `l`.
    fn reflectance(&self, l: Vec3) -> Vec3 {
        let n = self.surface.shading_normal;
        self.brdf.evaluate(n, l, self.to_viewer) * n.dot(l)
    }
}

/// One shadow ray of a packet lane and the light it brings if nothing stops it.
#[derive(Clone, Copy, Debug)]
struct ShadowRay {
    origin: Vec3,
    direction: Vec3,
    t_max: f32,
    light: Vec3,
}

impl Renderer {
    /// The light that each lane's surface reflects towards the viewer from `lights` and the
    /// environment of radiance `environment` (`reflected[lane]`, added in the order lights then
    /// environment), with the rays traced. Each light's shadow rays, and then the environment's,
    /// go to Embree as one packet: the samples of a pixel see nearby points and send their
    /// shadow rays the same way.
    pub(super) fn direct_light(
        &self,
        lanes: &[Option<LitLane>; PACKET_SIZE],
        lights: &[Light],
        environment: Vec3,
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let origins = lanes.map(|lane| lane.map(|l| shadow_origin(&l.surface)));
        let keys = lanes.map(|lane| lane.map_or(0, |l| l.draw.shadow_key));
        let mut rays = 0;
        for light in lights {
            let shadow = std::array::from_fn(|l| {
                let (lane, origin) = (lanes[l]?, origins[l]?);
                let incident = light.incident(origin)?;
                let cosine = lane.surface.shading_normal.dot(incident.direction);
                (cosine > 0.0).then(|| ShadowRay {
                    origin,
                    direction: incident.direction,
                    t_max: incident.distance,
                    light: lane.reflectance(incident.direction) * incident.irradiance,
                })
            });
            rays += self.add_unoccluded(&shadow, &keys, reflected);
        }
        if environment != Vec3::ZERO {
            // Density cos / pi: the estimate of the reflected f L cos is f L pi where the ray
            // leaves (a fully rough dielectric's: close to the diffuse colour times L).
            let shadow = std::array::from_fn(|l| {
                let (lane, origin) = (lanes[l]?, origins[l]?);
                let direction =
                    cosine_direction(lane.surface.shading_normal, lane.draw.environment);
                // A direction under the surface's own plane is blocked by the surface.
                let cosine = lane.surface.shading_normal.dot(direction);
                let above = direction.dot(lane.surface.geometric_normal) > 0.0 && cosine > 0.0;
                above.then(|| ShadowRay {
                    origin,
                    direction,
                    t_max: f32::INFINITY,
                    light: lane.brdf.evaluate(
                        lane.surface.shading_normal,
                        direction,
                        lane.to_viewer,
                    ) * (PI * lane.occlusion)
                        * environment,
                })
            });
            rays += self.add_unoccluded(&shadow, &keys, reflected);
        }
        rays
    }

    /// Traces the packet's shadow rays and adds the light of those nothing stops; returns the
    /// rays traced.
    fn add_unoccluded(
        &self,
        shadow: &[Option<ShadowRay>; PACKET_SIZE],
        keys: &[u32; PACKET_SIZE],
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let rays = shadow.map(|s| s.map(|s| (s.origin, s.direction, s.t_max)));
        let occluded = self.accel.occluded_packet(&rays, keys);
        for (l, s) in shadow.iter().enumerate() {
            if let Some(s) = s {
                if occluded & (1 << l) == 0 {
                    reflected[l] += s.light;
                }
            }
        }
        rays.iter().flatten().count() as u64
    }
}
