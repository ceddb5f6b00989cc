//! A packet's samples shaded (`unlit` or `lit`): each lane's surface, then its path. A `lit`
//! path shades `RenderSettings::bounces` surfaces: at each, the scene's lights (`lighting.rs`),
//! the emissive triangles (`emitters.rs`) and the sky, each of the last two by multiple
//! importance sampling with the BRDF (`sky.rs`); from each but the last it goes on along the
//! direction its BRDF drew (`brdf_sampling.rs`), and the surface found there adds its emission
//! (weighed against the emitters' draw of it) and its own direct light, weighed by f cos / pdf
//! of every turn so far. At the last surface the BRDF's draw only asks whether the sky is open
//! (so the emitters' draw there counts whole). Surfaces met after the camera's are read
//! without texture filtering (no pixel footprint follows a bounce).
//! trace.comp's shade_sample mirrors it.

use glam::{Vec2, Vec3};

use super::accel::{Hit, PACKET_SIZE};
use super::brdf::MetallicRoughness;
use super::brdf_sampling::BrdfSample;
use super::clearcoat::{Clearcoat, LayeredBrdf};
use super::lighting::{leaves, LightDraw, LitLane, ShadingInputs};
use super::render::{Renderer, TracedPacket};
use super::sheen::Sheen;
use super::sky::{power_heuristic, sky_along, Sky};
use super::surface::{origin_towards, SurfacePoint};
use super::surface_frame::{reflection_safe_normal, vertex_coloured};
use super::transmission::dielectric_of;
use crate::camera::{Footprint, Ray};
use crate::sampler::{
    emitter_dimensions, fresnel_dimension, pixel_dimension, sky_pick_dimension, vertex_dimensions,
    PixelSampler,
};
use crate::scene::texture::FootprintSets;
use crate::scene::{BLEND_CAMERA_SALT, BLEND_SHADOW_SALT};
use crate::settings::{RenderSettings, Shading};

/// The points a path's vertex draws with, each of [0, 1)^3: its sky's (the third picks among a
/// map's candidates) and its BRDF's (the third picks whether glass reflects).
fn vertex_points(
    sampler: &PixelSampler,
    lanes: &[Option<LitLane>; PACKET_SIZE],
    vertex: u32,
) -> ([Vec3; PACKET_SIZE], [Vec3; PACKET_SIZE]) {
    let [sx, sy, bx, by] = vertex_dimensions(vertex);
    let point = |l: usize, x: u32, y: u32| {
        lanes[l].map_or(Vec2::ZERO, |lane| {
            let s = lane.draw.sample;
            Vec2::new(
                pixel_dimension(sampler, s, x),
                pixel_dimension(sampler, s, y),
            )
        })
    };
    let choice = |l: usize, dimension: u32| {
        lanes[l].map_or(0.0, |lane| {
            pixel_dimension(sampler, lane.draw.sample, dimension)
        })
    };
    (
        std::array::from_fn(|l| point(l, sx, sy).extend(choice(l, sky_pick_dimension(vertex)))),
        std::array::from_fn(|l| point(l, bx, by).extend(choice(l, fresnel_dimension(vertex)))),
    )
}

/// The points of [0, 1)^2 a path's vertex draws its emitter point with.
fn emitter_points(
    sampler: &PixelSampler,
    lanes: &[Option<LitLane>; PACKET_SIZE],
    vertex: u32,
) -> [Vec2; PACKET_SIZE] {
    let [x, y] = emitter_dimensions(vertex);
    std::array::from_fn(|l| {
        lanes[l].map_or(Vec2::ZERO, |lane| {
            let s = lane.draw.sample;
            Vec2::new(
                pixel_dimension(sampler, s, x),
                pixel_dimension(sampler, s, y),
            )
        })
    })
}

impl Renderer {
    /// What the material of `surface` (hit `hit`) gives shading, textures filtered over the
    /// pinhole's pixel footprint (`None`: read unfiltered, at their finest level), with the
    /// mesh's vertex colours; a normal map tilts `surface.shading_normal`.
    pub(super) fn colours(
        &self,
        hit: &Hit,
        surface: &mut SurfacePoint,
        footprint: Option<&Footprint>,
    ) -> ShadingInputs {
        let material = self.materials.get(surface.material);
        let textures = &self.materials.textures;
        let mut inputs = ShadingInputs {
            brdf: LayeredBrdf {
                base: MetallicRoughness {
                    base_colour: material.diffuse,
                    metallic: material.metallic,
                    roughness: material.roughness,
                    specular: material.specular,
                    dielectric: dielectric_of(material, material.transmission, surface.back_face),
                },
                clearcoat: Clearcoat {
                    weight: material.clearcoat,
                    roughness: material.clearcoat_roughness,
                    normal: surface.shading_normal,
                },
                sheen: Sheen {
                    colour: material.sheen_colour,
                    roughness: material.sheen_roughness,
                },
            },
            emission: material.emission,
            occlusion: 1.0,
        };
        let colour = self.surfaces.colour(hit.triangle, hit.barycentric);
        if !material.is_textured() {
            inputs.brdf.base.base_colour = vertex_coloured(inputs.brdf.base.base_colour, colour);
            return inputs;
        }
        let vertices = self.accel.hit_vertices(hit);
        let duv = match footprint {
            Some(footprint) => {
                self.surfaces
                    .texcoord_footprints(hit.triangle, vertices, surface, footprint)
            }
            None => FootprintSets::default(),
        };
        let texcoords = &surface.texcoords;
        inputs.brdf.base.base_colour =
            vertex_coloured(material.diffuse_at(textures, texcoords, &duv), colour);
        // The coat's normal is the vertex normal tilted by the coat's own map, not the base's.
        let surfaces = &self.surfaces;
        inputs.brdf.clearcoat.normal = surfaces.normal_mapped(
            material.clearcoat_normal_map(),
            textures,
            hit,
            vertices,
            surface,
            &duv,
        );
        surface.shading_normal = surfaces.normal_mapped(
            material.normal_map(),
            textures,
            hit,
            vertices,
            surface,
            &duv,
        );
        (inputs.brdf.base.metallic, inputs.brdf.base.roughness) =
            material.metallic_roughness_at(textures, texcoords, &duv);
        (
            inputs.brdf.clearcoat.weight,
            inputs.brdf.clearcoat.roughness,
        ) = material.clearcoat_at(textures, texcoords, &duv);
        let transmission = material.transmission_at(textures, texcoords, &duv);
        inputs.brdf.base.dielectric = dielectric_of(material, transmission, surface.back_face);
        (inputs.brdf.sheen.colour, inputs.brdf.sheen.roughness) =
            material.sheen_at(textures, texcoords, &duv);
        inputs.emission = material.emission_at(textures, texcoords, &duv);
        inputs.occlusion = material.occlusion_at(textures, texcoords, &duv);
        inputs
    }

    /// The values of a packet's samples (`unlit` or `lit`), with the rays traced.
    pub(super) fn shade_packet(
        &self,
        lanes: &TracedPacket,
        sampler: &PixelSampler,
        settings: &RenderSettings,
        footprint: &Footprint,
    ) -> ([Vec3; PACKET_SIZE], u64) {
        let mut values = [Vec3::ZERO; PACKET_SIZE];
        let mut lit = [None; PACKET_SIZE];
        for l in 0..lanes.hits.len() {
            let ray = Ray {
                origin: lanes.origins[l],
                direction: lanes.directions[l],
            };
            let (key, moment) = lanes.draws[l];
            let draw = LightDraw {
                shadow_key: key ^ BLEND_CAMERA_SALT ^ BLEND_SHADOW_SALT,
                moment,
                sample: lanes.indices[l],
            };
            (values[l], lit[l]) =
                self.shade_surface(&ray, lanes.hits[l], settings, Some(footprint), draw);
        }
        let mut rays = lanes.hits.len() as u64;
        if lit.iter().any(Option::is_some) {
            rays += self.trace_paths(lit, sampler, settings, &mut values);
        }
        (values, rays)
    }

    /// Adds to `values` the light of each lane's path from its first surface on; returns the
    /// rays traced.
    fn trace_paths(
        &self,
        mut lanes: [Option<LitLane>; PACKET_SIZE],
        sampler: &PixelSampler,
        settings: &RenderSettings,
        values: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        let sky = Sky::of(settings, self.environment.as_deref());
        // With the cosine's draw alone, the BRDF's draws bring no sky.
        let brdf_sky = sky.filter(|_| !self.cosine_sky);
        let mut throughput = [Vec3::ONE; PACKET_SIZE];
        let mut rays = 0;
        for vertex in 0..settings.bounces {
            if lanes.iter().all(Option::is_none) {
                break;
            }
            let last = vertex + 1 == settings.bounces;
            let mut reflected = [Vec3::ZERO; PACKET_SIZE];
            rays += self.direct_light(&lanes, &self.lights, &mut reflected);
            if !self.emitters.is_empty() {
                // The last vertex's BRDF draw meets no emitter: the emitters' draw counts whole.
                let points = emitter_points(sampler, &lanes, vertex);
                rays += self.emitter_light(&lanes, &points, !last, &mut reflected);
            }
            if last && sky.is_none() {
                // Nothing more to draw (the default render): no sampler dimensions, no BRDF
                // draw.
                for l in 0..PACKET_SIZE {
                    values[l] += throughput[l] * reflected[l];
                }
                break;
            }
            let (sky_points, brdf_points) = vertex_points(sampler, &lanes, vertex);
            match &sky {
                Some(sky) if self.cosine_sky => {
                    let points = sky_points.map(|p| p.truncate());
                    rays += self.sky_by_cosine(&lanes, sky, &points, &mut reflected);
                }
                Some(sky) => rays += self.sky_light(&lanes, sky, &sky_points, &mut reflected),
                None => {}
            }
            // The BRDF's draws: toward the sky, and where the path goes on.
            let draws: [Option<BrdfSample>; PACKET_SIZE] = std::array::from_fn(|l| {
                let lane = lanes[l]?;
                let n = lane.surface.shading_normal;
                let draw = lane.brdf.sample(n, lane.to_viewer, brdf_points[l])?;
                leaves(&lane, draw.direction).then_some(draw)
            });
            if last {
                if let Some(sky) = &brdf_sky {
                    rays += self.sky_along_draws(&lanes, sky, &draws, &mut reflected);
                }
            }
            for l in 0..PACKET_SIZE {
                values[l] += throughput[l] * reflected[l];
            }
            if last {
                break;
            }
            rays += self.bounce(
                &mut lanes,
                &draws,
                brdf_sky.as_ref(),
                &mut throughput,
                values,
            );
        }
        rays
    }

    /// Takes each lane's path one surface on along its BRDF's draw: a draw that leaves the
    /// scene brings the sky's light (weighed against the sky's draws) and ends the path; one
    /// that meets a surface adds its emission and makes it the lane's next. Returns the rays.
    fn bounce(
        &self,
        lanes: &mut [Option<LitLane>; PACKET_SIZE],
        draws: &[Option<BrdfSample>; PACKET_SIZE],
        sky: Option<&Sky>,
        throughput: &mut [Vec3; PACKET_SIZE],
        values: &mut [Vec3; PACKET_SIZE],
    ) -> u64 {
        // The packet's rays, gathered: Embree traces a prefix of lanes.
        let going: Vec<usize> = (0..PACKET_SIZE)
            .filter(|&l| lanes[l].is_some() && draws[l].is_some())
            .collect();
        let origins: Vec<Vec3> = going
            .iter()
            .map(|&l| origin_towards(&lanes[l].unwrap().surface, draws[l].unwrap().direction))
            .collect();
        let directions: Vec<Vec3> = going.iter().map(|&l| draws[l].unwrap().direction).collect();
        let ray_draws: Vec<(u32, f32)> = going
            .iter()
            .map(|&l| lanes[l].unwrap().draw)
            .map(|draw| (draw.shadow_key, draw.moment))
            .collect();
        let mut hits = vec![None; going.len()];
        if !going.is_empty() {
            let range = (0.0, f32::INFINITY);
            self.accel
                .closest_hits(&origins, &directions, &ray_draws, range, &mut hits);
        }
        let mut next = [None; PACKET_SIZE];
        for (k, &l) in going.iter().enumerate() {
            let (lane, draw) = (lanes[l].unwrap(), draws[l].unwrap());
            let Some(hit) = hits[k] else {
                if let Some(sky) = sky {
                    values[l] += throughput[l] * sky_along(sky, &lane, &draw);
                }
                continue;
            };
            throughput[l] *= draw.weight;
            let ray = Ray {
                origin: origins[k],
                direction: directions[k],
            };
            let (emission, surface) = self.lit_surface(&ray, hit, None, lane.draw);
            throughput[l] *= self.volume_transmittance(&surface, hit.t);
            values[l] += throughput[l] * emission * self.emission_weight(&draw, &hit);
            next[l] = Some(surface);
        }
        *lanes = next;
        going.len() as u64
    }

    /// The weight of the emission a BRDF draw meets at `hit` against the emitters' draw of the
    /// same point (1 where nothing is drawn from the emitters).
    fn emission_weight(&self, draw: &BrdfSample, hit: &Hit) -> f32 {
        if self.emitters.is_empty() {
            return 1.0;
        }
        let distance = hit.t * draw.direction.length();
        let pdf = self.emitter_pdf(hit.triangle, draw.direction.normalize(), distance);
        power_heuristic(draw.pdf, pdf)
    }

    /// A sample's value without its direct light: the background, the `unlit` colour, or the
    /// emission of a `lit` surface with what its direct light needs.
    pub(super) fn shade_surface(
        &self,
        ray: &Ray,
        hit: Option<Hit>,
        settings: &RenderSettings,
        footprint: Option<&Footprint>,
        draw: LightDraw,
    ) -> (Vec3, Option<LitLane>) {
        let Some(hit) = hit else {
            if settings.environment_seen {
                if let Some(light) = &self.environment {
                    return (light.map.radiance(ray.direction.normalize()), None);
                }
            }
            return (settings.background, None);
        };
        let material = self
            .materials
            .get(self.surfaces.materials[hit.triangle as usize]);
        if settings.shading == Shading::Unlit
            && material.diffuse_texture.is_none()
            && !self.surfaces.has_colours(hit.triangle)
        {
            // Visibility only: the material is all that is needed.
            return (material.diffuse, None);
        }
        if settings.shading == Shading::Unlit {
            let mut surface = self.surface_point(ray, &hit);
            let inputs = self.colours(&hit, &mut surface, footprint);
            return (inputs.brdf.base.base_colour, None);
        }
        let (emission, lane) = self.lit_surface(ray, hit, footprint, draw);
        (emission, Some(lane))
    }

    /// What is left of light that crossed `distance` of a volume to leave it at `lane`'s
    /// surface (a back face of a material with an attenuation): Beer-Lambert's
    /// exp(-attenuation distance); 1 elsewhere.
    fn volume_transmittance(&self, lane: &LitLane, distance: f32) -> Vec3 {
        let material = self.materials.get(lane.surface.material);
        if !lane.surface.back_face || material.thin || material.attenuation == Vec3::ZERO {
            return Vec3::ONE;
        }
        (-material.attenuation * distance).exp()
    }

    /// A lit surface's emission and its lane, its shading normal made safe for reflection
    /// (`reflection_safe_normal`).
    fn lit_surface(
        &self,
        ray: &Ray,
        hit: Hit,
        footprint: Option<&Footprint>,
        draw: LightDraw,
    ) -> (Vec3, LitLane) {
        let mut surface = self.surface_point(ray, &hit);
        let inputs = self.colours(&hit, &mut surface, footprint);
        let to_viewer = -ray.direction.normalize();
        let ng = surface.geometric_normal;
        surface.shading_normal = reflection_safe_normal(ng, to_viewer, surface.shading_normal);
        let mut brdf = inputs.brdf;
        if brdf.clearcoat.weight > 0.0 {
            brdf.clearcoat.normal = reflection_safe_normal(ng, to_viewer, brdf.clearcoat.normal);
        }
        let lane = LitLane {
            surface,
            brdf,
            occlusion: inputs.occlusion,
            to_viewer,
            draw,
        };
        (inputs.emission, lane)
    }
}
