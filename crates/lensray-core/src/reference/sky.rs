//! The environment as a light (`lit`): a uniform sky or an equirectangular map, each lighting a
//! surface by two draws combined by multiple importance sampling (Veach's power heuristic):
//! one drawn from the environment (the map by its power, the uniform sky by the cosine), one
//! drawn from the BRDF (`brdf_sampling.rs`). Each draw is weighed by the share its density has
//! of the two, so smooth metals reflect a map's lamps without speckle and rough surfaces see its
//! broad light without noise. shaders/include/sky.glsl mirrors it function by function
//! (`sky_draw`: shaders/include/shading.glsl).
//!
//! A metal's map draw is resampled (Talbot et al. 2005, resampled importance sampling): of
//! `SKY_CANDIDATES` (`Renderer::with_sky_candidates`) directions drawn by the map's power, one
//! is picked in proportion to the luminance the BRDF would reflect along it over its density,
//! and weighed by the mean of those ratios over its own. By power alone, a glossy metal's draws
//! mostly go to lamps its lobe does not see (behind it, or off the lobe), and the lamp it does
//! see shows as pepper (docs/environment.md, "Metals under a map's lamps").

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::accel::PACKET_SIZE;
use super::brdf_sampling::BrdfSample;
use super::lighting::{leaves, LitLane, ShadowRay};
use super::render::Renderer;
use super::surface::{origin_towards, shadow_origin};
use crate::interface::{SKY_CANDIDATE_STEP, SKY_RESAMPLED_METALLIC};
use crate::scene::environment::luminance;
use crate::scene::light::cosine_direction;
use crate::scene::EnvironmentLight;
use crate::settings::RenderSettings;

/// What lights a scene from afar.
#[derive(Clone, Copy, Debug)]
pub(super) enum Sky<'a> {
    /// Radiance from every direction (`RenderSettings::environment`).
    Uniform(Vec3),
    /// A map that emits somewhere (`Scene::environment`).
    Map(&'a EnvironmentLight),
}

/// A direction drawn from the sky, its density and what arrives along it.
#[derive(Clone, Copy, Debug)]
pub(super) struct SkySample {
    pub direction: Vec3,
    pub pdf: f32,
    pub radiance: Vec3,
}

/// The power heuristic's weight (exponent 2) of a draw of density `a` against one of `b`.
pub(super) fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

impl<'a> Sky<'a> {
    /// The scene's map if it emits, else the settings' uniform sky if it is not black; `None`:
    /// nothing lights from afar.
    pub(super) fn of(
        settings: &RenderSettings,
        environment: Option<&'a EnvironmentLight>,
    ) -> Option<Self> {
        match environment {
            Some(light) => light.sampler.is_some().then_some(Sky::Map(light)),
            None => {
                (settings.environment != Vec3::ZERO).then_some(Sky::Uniform(settings.environment))
            }
        }
    }

    /// Radiance arriving from direction `d` (unit, pointing away from the scene).
    pub(super) fn radiance(&self, d: Vec3) -> Vec3 {
        match self {
            Sky::Uniform(l) => *l,
            Sky::Map(light) => light.map.radiance(d),
        }
    }

    /// The density (per solid angle) of `sample` drawing `d` at a surface of normal `n`.
    pub(super) fn pdf(&self, n: Vec3, d: Vec3) -> f32 {
        match self {
            Sky::Uniform(_) => n.dot(d).max(0.0) * FRAC_1_PI,
            Sky::Map(light) => light.sampler.as_ref().map_or(0.0, |s| s.pdf(&light.map, d)),
        }
    }

    /// The direction point `u` draws at a surface of normal `n`; `None` where none is drawn.
    pub(super) fn sample(&self, n: Vec3, u: Vec2) -> Option<SkySample> {
        match self {
            Sky::Uniform(l) => {
                let direction = cosine_direction(n, u);
                let pdf = n.dot(direction).max(0.0) * FRAC_1_PI;
                (pdf > 0.0).then_some(SkySample {
                    direction,
                    pdf,
                    radiance: *l,
                })
            }
            Sky::Map(light) => {
                let s = light.sampler.as_ref()?.sample(&light.map, u)?;
                Some(SkySample {
                    direction: s.direction,
                    pdf: s.pdf,
                    radiance: s.radiance,
                })
            }
        }
    }
}

/// Candidate `k` of a map's draw at point `u`: `u` moved by k times the R2 sequence's step,
/// so that the candidates of one sample spread over the square and each
/// candidate's points over a pixel's samples stay as stratified as `u`'s. Candidate 0 is `u`.
pub(super) fn candidate_point(u: Vec2, k: u32) -> Vec2 {
    let [x, y] = SKY_CANDIDATE_STEP;
    let k = k as f32;
    Vec2::new((u.x + x * k).fract(), (u.y + y * k).fract())
}

/// The sky's draw at a lane for point `u` (its third coordinate picks among a map's
/// `map_candidates`, where the surface is a metal): the direction and the light it brings if
/// nothing stops it. The power heuristic weighs it by the map's own density, as `sky_along`
/// weighs the BRDF's draws, so that the two weights of any direction still sum to one: the
/// resampled density has no closed form, and the sum is what keeps the estimate unbiased.
pub(super) fn sky_draw(
    sky: &Sky,
    lane: &LitLane,
    u: Vec3,
    map_candidates: u32,
) -> Option<(Vec3, Vec3)> {
    let (n, v) = (lane.surface.shading_normal, lane.to_viewer);
    let candidates = match sky {
        Sky::Map(_) if lane.brdf.base.metallic >= SKY_RESAMPLED_METALLIC => map_candidates,
        _ => 1,
    };
    let (mut pick, mut total) = (u.z, 0.0f32);
    // The picked candidate: its direction, density, light (f L) and luminance.
    let mut picked: Option<(Vec3, f32, Vec3, f32)> = None;
    for k in 0..candidates {
        let Some(s) = sky.sample(n, candidate_point(u.truncate(), k)) else {
            continue;
        };
        if !leaves(lane, s.direction) {
            continue;
        }
        let light = lane.brdf.reflected(n, s.direction, v) * s.radiance;
        if candidates == 1 {
            picked = Some((s.direction, s.pdf, light, 0.0));
            break;
        }
        let target = luminance(light);
        if target.is_nan() || target <= 0.0 {
            continue;
        }
        // One uniform number picks in proportion to the ratios as they stream past: kept with
        // probability ratio / total, and rescaled to stay uniform for the rest.
        total += target / s.pdf;
        let keep = target / s.pdf / total;
        if pick < keep {
            pick /= keep;
            picked = Some((s.direction, s.pdf, light, target));
        } else {
            pick = (pick - keep) / (1.0 - keep);
        }
    }
    let (direction, pdf, light, target) = picked?;
    let w = power_heuristic(pdf, lane.brdf.pdf(n, direction, v));
    let scale = if candidates == 1 {
        w / pdf
    } else {
        w * (total / (candidates as f32 * target))
    };
    Some((direction, light * (scale * lane.occlusion)))
}

/// The light the sky brings along a BRDF draw that leaves the scene, weighed against the sky's
/// own draw of the same direction and by the surface's occlusion.
pub(super) fn sky_along(sky: &Sky, lane: &LitLane, draw: &BrdfSample) -> Vec3 {
    let w = power_heuristic(
        draw.pdf,
        sky.pdf(lane.surface.shading_normal, draw.direction),
    );
    draw.weight * sky.radiance(draw.direction) * (w * lane.occlusion)
}

impl Renderer {
    /// Adds to `reflected` the sky's light drawn from the sky at each lane (points `u[lane]`,
    /// `sky_draw`), weighed against the BRDF's draws, through one packet of shadow rays; returns
    /// the rays.
    pub(super) fn sky_light(
        &self,
        lanes: &[Option<LitLane>; PACKET_SIZE],
        sky: &Sky,
        u: &[Vec3; PACKET_SIZE],
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let shadow = std::array::from_fn(|l| {
            let lane = lanes[l]?;
            let (direction, light) = sky_draw(sky, &lane, u[l], self.sky_candidates)?;
            Some(ShadowRay {
                origin: origin_towards(&lane.surface, direction),
                direction,
                t_max: f32::INFINITY,
                light,
            })
        });
        self.add_unoccluded(&shadow, &Self::shadow_draws(lanes), reflected)
    }

    /// Adds to `reflected` the sky's light by one cosine-distributed ray a lane (f L pi where it
    /// leaves the scene), unweighed: `Renderer::with_cosine_sky`. Returns the rays.
    pub(super) fn sky_by_cosine(
        &self,
        lanes: &[Option<LitLane>; PACKET_SIZE],
        sky: &Sky,
        u: &[Vec2; PACKET_SIZE],
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let shadow = std::array::from_fn(|l| {
            let lane = lanes[l]?;
            let (n, v) = (lane.surface.shading_normal, lane.to_viewer);
            let direction = cosine_direction(n, u[l]);
            leaves(&lane, direction).then(|| ShadowRay {
                origin: shadow_origin(&lane.surface),
                direction,
                t_max: f32::INFINITY,
                light: lane.brdf.reflected(n, direction, v) / n.dot(direction)
                    * sky.radiance(direction)
                    * (std::f32::consts::PI * lane.occlusion),
            })
        });
        self.add_unoccluded(&shadow, &Self::shadow_draws(lanes), reflected)
    }

    /// Adds to `reflected` the sky's light along each lane's BRDF draw (`draws[lane]`), through
    /// one packet of shadow rays (a path's last surface); returns the rays.
    pub(super) fn sky_along_draws(
        &self,
        lanes: &[Option<LitLane>; PACKET_SIZE],
        sky: &Sky,
        draws: &[Option<BrdfSample>; PACKET_SIZE],
        reflected: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let shadow = std::array::from_fn(|l| {
            let (lane, draw) = (lanes[l]?, draws[l]?);
            Some(ShadowRay {
                origin: origin_towards(&lane.surface, draw.direction),
                direction: draw.direction,
                t_max: f32::INFINITY,
                light: sky_along(sky, &lane, &draw),
            })
        });
        self.add_unoccluded(&shadow, &Self::shadow_draws(lanes), reflected)
    }
}
