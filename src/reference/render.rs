//! The reference render loop: every pixel, every sample, in parallel over rows.

use std::f32::consts::FRAC_1_PI;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::{UVec2, Vec2, Vec3, Vec3A};
use rayon::prelude::*;

use super::accel::{Accel, Hit, PACKET_SIZE};
use super::rays::primary_rays;
use super::surface::{shadow_origin, SurfaceData, SurfacePoint};
use crate::camera::{Camera, Ray};
use crate::render::{Image, RenderSettings, Shading};
use crate::sampler::pixel_sampler;
use crate::scene::{Material, Scene};

/// Rows rendered between two progress reports.
const ROWS_PER_BAND: u32 = 16;

pub struct Renderer {
    accel: Accel,
    surfaces: SurfaceData,
    materials: Vec<Material>,
}

/// What a render did, for the summary line and benchmarks.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    pub elapsed: Duration,
    /// Primary and shadow rays.
    pub rays: u64,
}

impl RenderStats {
    pub fn rays_per_second(&self) -> f64 {
        self.rays as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

impl Renderer {
    /// Flattens the scene's meshes and builds the BVH.
    pub fn new(scene: &Scene) -> Self {
        let mut triangles = Vec::with_capacity(scene.triangle_count());
        let mut normals = Vec::with_capacity(scene.triangle_count());
        let mut materials = Vec::with_capacity(scene.triangle_count());
        for mesh in &scene.meshes {
            for (t, tri) in mesh.triangles.iter().enumerate() {
                triangles.push(tri.map(|i| Vec3A::from(mesh.positions[i as usize])));
                normals.push(if mesh.normals.is_empty() {
                    [Vec3::ZERO; 3]
                } else {
                    tri.map(|i| mesh.normals[i as usize])
                });
                materials.push(mesh.material_ids[t]);
            }
        }
        let accel = Accel::build(&triangles);
        let order = accel.slot_to_triangle();
        let surfaces = SurfaceData {
            normals: order.iter().map(|&i| normals[i as usize]).collect(),
            materials: order.iter().map(|&i| materials[i as usize]).collect(),
        };
        Self {
            accel,
            surfaces,
            materials: scene.materials.clone(),
        }
    }

    pub fn bvh_build_time(&self) -> Duration {
        self.accel.build_time
    }

    /// Closest hit along a world-space ray, t in (0, inf).
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.accel
            .closest_hit(ray.origin, ray.direction, 0.0, f32::INFINITY)
    }

    pub fn surface_point(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let v = self.accel.vertices(hit.slot).map(Vec3::from);
        self.surfaces.surface_point(ray, hit, v)
    }

    /// Renders the image; `progress(done_rows, total_rows)` is called between bands of rows.
    pub fn render(
        &self,
        camera: &Camera,
        settings: &RenderSettings,
        progress: &mut dyn FnMut(u64, u64),
    ) -> (Image, RenderStats) {
        let start = Instant::now();
        let (width, height) = (camera.width, camera.height);
        let mut image = Image::new(width, height);
        let rays = AtomicU64::new(0);
        for (band, rows) in image
            .pixels
            .chunks_mut((width * ROWS_PER_BAND) as usize)
            .enumerate()
        {
            rows.par_chunks_mut(width as usize)
                .enumerate()
                .for_each(|(r, row)| {
                    let y = band as u32 * ROWS_PER_BAND + r as u32;
                    let mut row_rays = 0;
                    for (x, pixel) in row.iter_mut().enumerate() {
                        let (value, n) = self.pixel(camera, settings, UVec2::new(x as u32, y));
                        *pixel = value;
                        row_rays += n;
                    }
                    rays.fetch_add(row_rays, Ordering::Relaxed);
                });
            let done = ((band as u32 + 1) * ROWS_PER_BAND).min(height);
            progress(done as u64, height as u64);
        }
        let stats = RenderStats {
            elapsed: start.elapsed(),
            rays: rays.into_inner(),
        };
        (image, stats)
    }

    /// The average of the pixel's samples, and the number of rays traced for it.
    fn pixel(&self, camera: &Camera, settings: &RenderSettings, pixel: UVec2) -> (Vec3, u64) {
        if settings.shading.is_aov() {
            // The G-buffer's definition: the aperture-centre ray through the pixel centre.
            let centre = pixel.as_vec2() + Vec2::splat(0.5);
            let ray = camera.generate_ray(centre, Vec2::splat(0.5));
            return (self.aov(camera, &ray, settings), 1);
        }
        let mut sum = Vec3::ZERO;
        let mut rays = 0;
        // The samples of a pixel are coherent: their primary rays are traced as packets.
        let mut origins = [Vec3::ZERO; PACKET_SIZE];
        let mut directions = [Vec3::ZERO; PACKET_SIZE];
        let mut hits = [None; PACKET_SIZE];
        let sampler = pixel_sampler(settings.sampler, settings.seed, pixel, camera.width);
        for first in (0..settings.spp).step_by(PACKET_SIZE) {
            let n = (settings.spp - first).min(PACKET_SIZE as u32) as usize;
            primary_rays(camera, &sampler, first, &mut origins, &mut directions);
            self.accel.closest_hits(
                &origins[..n],
                &directions[..n],
                0.0,
                f32::INFINITY,
                &mut hits[..n],
            );
            for i in 0..n {
                let ray = Ray {
                    origin: origins[i],
                    direction: directions[i],
                };
                let (value, count) = self.shade(&ray, hits[i], settings);
                sum += value;
                rays += count;
            }
        }
        (sum / settings.spp as f32, rays)
    }

    /// `unlit` and `lit`, with the number of rays traced.
    fn shade(&self, ray: &Ray, hit: Option<Hit>, settings: &RenderSettings) -> (Vec3, u64) {
        let Some(hit) = hit else {
            return (settings.background, 1);
        };
        if settings.shading == Shading::Unlit {
            // Visibility only: the material is all that is needed.
            let material = self.surfaces.materials[hit.slot as usize];
            return (self.materials[material as usize].diffuse, 1);
        }
        let surface = self.surface_point(ray, &hit);
        let material = &self.materials[surface.material as usize];
        let mut radiance = material.emission;
        let origin = shadow_origin(&surface);
        let to_light = settings.light.position - origin;
        let distance = to_light.length();
        let direction = to_light / distance;
        let cosine = surface.shading_normal.dot(direction);
        if cosine <= 0.0 {
            return (radiance, 1);
        }
        if !self.accel.occluded(origin, direction, 0.0, distance) {
            radiance += material.diffuse * FRAC_1_PI * settings.light.intensity * cosine
                / (distance * distance);
        }
        (radiance, 2)
    }

    fn aov(&self, camera: &Camera, ray: &Ray, settings: &RenderSettings) -> Vec3 {
        let hit = self.intersect(ray);
        match (settings.shading, hit) {
            (Shading::Albedo, None) => settings.background,
            (_, None) => Vec3::ZERO,
            (shading, Some(hit)) => {
                let surface = self.surface_point(ray, &hit);
                match shading {
                    Shading::Depth => Vec3::splat(camera.view_depth(surface.position)),
                    Shading::Normal => surface.shading_normal,
                    _ => self.materials[surface.material as usize].diffuse,
                }
            }
        }
    }
}
