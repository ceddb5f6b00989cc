//! Emissive triangles as lights (`lit`): one triangle drawn by its power
//! (`scene::emitters::EmitterDistribution`), a point drawn uniformly on it, and a shadow ray to it,
//! combined with the BRDF's draws by multiple importance sampling (the power heuristic): the
//! draw here is weighed against the BRDF's density of its direction, and a bounce that meets an
//! emissive triangle weighs its emission against `EmitterDistribution::pdf` of the point it met
//! (`integrator.rs`). A double-sided emitter emits from both faces; a single-sided one only
//! from its front (counter-clockwise) face, the only one any ray sees (`is_back_face`).

use glam::{Vec2, Vec3, Vec3A};

use super::accel::{is_back_face, PACKET_SIZE};
use super::lighting::{leaves, LitLane, ShadowRay};
use super::render::Renderer;
use super::sky::power_heuristic;
use super::surface::{origin_towards, shadow_origin};
use crate::interface::EMITTER_SHADOW_SHORTEN;
use crate::scene::emitters::{area_normal, uniform_point};
use crate::scene::texture::FootprintSets;

impl Renderer {
    /// The emission of `triangle` at barycentrics `b` seen along `d` (unit, towards the
    /// triangle): its material's emission, textured unfiltered; 0 from behind a single-sided
    /// one.
    pub(super) fn emission_towards(&self, triangle: u32, b: Vec2, d: Vec3) -> Vec3 {
        let material = self
            .materials
            .get(self.surfaces.materials[triangle as usize]);
        let vertices = self.accel.vertices(triangle);
        if !material.double_sided && is_back_face(Vec3A::from(d), vertices) {
            return Vec3::ZERO;
        }
        let texcoords = self.surfaces.texcoords(triangle, b);
        let duv = FootprintSets::default();
        material.emission_at(&self.materials.textures, &texcoords, &duv)
    }

    /// The density per solid angle with which a lane's emitter draw picks the point a ray along
    /// unit `d` meets at `distance` on `triangle`.
    pub(super) fn emitter_pdf(&self, triangle: u32, d: Vec3, distance: f32) -> f32 {
        let (_, normal) = area_normal(&self.accel.vertices(triangle).map(Vec3::from));
        self.emitters.pdf(triangle, normal, d, distance)
    }

    /// Adds to `reflected` the emitters' light drawn at each lane (points `u[lane]`), weighed
    /// against the BRDF's draw of the same direction when `mis` (the BRDF's draws meet
    /// emitters: every vertex but a path's last), through one packet of shadow rays; returns
    /// the rays.
    pub(super) fn emitter_light(
        &self,
        lanes: &[Option<LitLane>; PACKET_SIZE],
        u: &[Vec2; PACKET_SIZE],
        mis: bool,
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let shadow = std::array::from_fn(|l| {
            let lane = lanes[l]?;
            let (triangle, u) = self.emitters.pick(u[l]);
            let vertices = self.accel.vertices(triangle).map(Vec3::from);
            let (barycentric, position) = uniform_point(&vertices, u);
            let front = shadow_origin(&lane.surface);
            // Behind a surface that transmits where the point is behind it (light through
            // it); an opaque one's emitters in its own plane stay unseen.
            let origin = if lane.brdf.transmits() {
                origin_towards(&lane.surface, position - front)
            } else {
                front
            };
            let to_light = position - origin;
            let distance = to_light.length();
            let direction = to_light / distance;
            if distance.is_nan() || distance <= 0.0 || !leaves(&lane, direction) {
                return None;
            }
            let emission = self.emission_towards(triangle, barycentric, direction);
            let pdf = self.emitter_pdf(triangle, direction, distance);
            if emission == Vec3::ZERO || !pdf.is_finite() || pdf <= 0.0 {
                return None;
            }
            let (n, v) = (lane.surface.shading_normal, lane.to_viewer);
            let w = if mis {
                power_heuristic(pdf, lane.brdf.pdf(n, direction, v))
            } else {
                1.0
            };
            let f = lane.brdf.reflected(n, direction, v);
            Some(ShadowRay {
                origin,
                direction,
                t_max: distance * (1.0 - EMITTER_SHADOW_SHORTEN),
                light: f * emission * (w / pdf),
            })
        });
        self.add_unoccluded(&shadow, &Self::shadow_draws(lanes), reflected)
    }
}
