//! Direct light at a surface point (`lit`) from the scene's lights, each through a shadow ray,
//! reflected by the surface's metallic-roughness BRDF (`brdf`); the environment's is `sky.rs`.
//! shaders/include/shading.glsl mirrors it.

use glam::Vec3;

use super::accel::PACKET_SIZE;
use super::clearcoat::LayeredBrdf;
use super::render::Renderer;
use super::surface::{origin_towards, shadow_origin, SurfacePoint};
use crate::scene::Light;

/// What a sample's shading draws besides its camera ray: the blend key of its shadow and bounce
/// rays, its moment in the shutter's span (every ray of its path meets what moves there), and
/// its index, from which each vertex of its path takes its sample dimensions
/// (`sampler::vertex_dimensions`).
#[derive(Clone, Copy, Debug)]
pub(super) struct LightDraw {
    pub shadow_key: u32,
    pub moment: f32,
    pub sample: u32,
}

/// What a surface point's material gives its shading, textures applied: its BRDF, its
/// emission and the share of the environment's light that reaches it (its occlusion map).
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadingInputs {
    pub brdf: LayeredBrdf,
    pub emission: Vec3,
    pub occlusion: f32,
}

/// A packet lane's surface waiting for its direct light: the point, its BRDF and occlusion, the
/// unit direction to the viewer (where the path came from), and what its rays draw.
#[derive(Clone, Copy, Debug)]
pub(super) struct LitLane {
    pub surface: SurfacePoint,
    pub brdf: LayeredBrdf,
    pub occlusion: f32,
    pub to_viewer: Vec3,
    pub draw: LightDraw,
}

impl LitLane {
    /// f(l, v) cos of light arriving from `l`, each layer at its own normal's cosine
    /// (`LayeredBrdf::reflected`).
    fn reflectance(&self, l: Vec3) -> Vec3 {
        self.brdf
            .reflected(self.surface.shading_normal, l, self.to_viewer)
    }
}

/// Whether a direction leaves a surface on its own side (above its geometric plane, where a
/// direction under it is blocked by the surface, and above the shading normal's or the clear
/// coat's), or through it where the surface transmits (below both).
pub(super) fn leaves(lane: &LitLane, d: Vec3) -> bool {
    let g = d.dot(lane.surface.geometric_normal);
    let n = lane.surface.shading_normal;
    let s = d.dot(n);
    (g > 0.0 && (s > 0.0 || lane.brdf.coat_reflects(n, d)))
        || (g < 0.0 && s < 0.0 && lane.brdf.transmits())
}

/// One shadow ray of a packet lane and the light it brings if nothing stops it.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadowRay {
    pub origin: Vec3,
    pub direction: Vec3,
    pub t_max: f32,
    pub light: Vec3,
}

impl Renderer {
    /// The light that each lane's surface reflects towards the viewer from `lights` (a moving
    /// one where the lane's moment has it), `reflected[lane]` added light by light, with the
    /// rays traced. Each light's shadow
    /// rays go to Embree as one packet: the samples of a pixel see nearby points and send their
    /// shadow rays the same way.
    pub(super) fn direct_light(
        &self,
        lanes: &[Option<LitLane>; PACKET_SIZE],
        lights: &[Light],
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let origins = lanes.map(|lane| lane.map(|l| shadow_origin(&l.surface)));
        let draws = Self::shadow_draws(lanes);
        let mut rays = 0;
        for (index, light) in lights.iter().enumerate() {
            let moving = self.moving_lights.iter().find(|m| m.index == index);
            let shadow = std::array::from_fn(|l| {
                let (lane, mut origin) = (lanes[l]?, origins[l]?);
                // A moving light where the lane's moment has it.
                let light = &moving.map_or(*light, |m| m.at(lane.draw.moment));
                let mut incident = light.incident(origin)?;
                let n = lane.surface.shading_normal;
                // A light above the base's normal or the coat's is seen from the front.
                let d = incident.direction;
                if n.dot(d) <= 0.0 && !lane.brdf.coat_reflects(n, d) {
                    // Light from behind reaches the viewer only through the surface.
                    if !lane.brdf.transmits() {
                        return None;
                    }
                    origin = origin_towards(&lane.surface, incident.direction);
                    incident = light.incident(origin)?;
                    if !leaves(&lane, incident.direction) {
                        return None;
                    }
                }
                Some(ShadowRay {
                    origin,
                    direction: incident.direction,
                    t_max: incident.distance,
                    light: lane.reflectance(incident.direction) * incident.irradiance,
                })
            });
            rays += self.add_unoccluded(&shadow, &draws, reflected);
        }
        rays
    }

    /// The blend keys and moments of the lanes' shadow and bounce rays.
    pub(super) fn shadow_draws(
        lanes: &[Option<LitLane>; PACKET_SIZE],
    ) -> [(u32, f32); PACKET_SIZE] {
        lanes.map(|lane| lane.map_or((0, 0.5), |l| (l.draw.shadow_key, l.draw.moment)))
    }

    /// Traces the packet's shadow rays and adds the light of those nothing stops; returns the
    /// rays traced.
    pub(super) fn add_unoccluded(
        &self,
        shadow: &[Option<ShadowRay>; PACKET_SIZE],
        draws: &[(u32, f32); PACKET_SIZE],
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let rays = shadow.map(|s| s.map(|s| (s.origin, s.direction, s.t_max)));
        let occluded = self.accel.occluded_packet(&rays, draws);
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
