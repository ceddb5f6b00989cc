//! Direct light at a surface point (`lit`): the scene's lights, each through a shadow ray, and the
//! uniform environment through one cosine-distributed ray. shaders/include/shading.glsl mirrors
//! it.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

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

impl Renderer {
    /// The light that `surface`, of diffuse colour `diffuse`, reflects towards the viewer from
    /// `lights` and the environment of radiance `environment`, with the rays traced.
    pub(super) fn direct_light(
        &self,
        surface: &SurfacePoint,
        diffuse: Vec3,
        lights: &[Light],
        environment: Vec3,
        draw: LightDraw,
    ) -> (Vec3, u64) {
        let origin = shadow_origin(surface);
        let n = surface.shading_normal;
        let mut radiance = Vec3::ZERO;
        let mut rays = 0;
        for light in lights {
            let Some(incident) = light.incident(origin) else {
                continue;
            };
            let cosine = n.dot(incident.direction);
            if cosine <= 0.0 {
                continue;
            }
            rays += 1;
            if !self.occluded(
                origin,
                incident.direction,
                incident.distance,
                draw.shadow_key,
            ) {
                radiance += diffuse * FRAC_1_PI * incident.irradiance * cosine;
            }
        }
        if environment != Vec3::ZERO {
            // Density cos / pi: the estimate of Kd / pi * L * cos is Kd * L where the ray leaves.
            let direction = cosine_direction(n, draw.environment);
            // A direction under the surface's own plane is blocked by the surface.
            if direction.dot(surface.geometric_normal) > 0.0 {
                rays += 1;
                if !self.occluded(origin, direction, f32::INFINITY, draw.shadow_key) {
                    radiance += diffuse * environment;
                }
            }
        }
        (radiance, rays)
    }
}
