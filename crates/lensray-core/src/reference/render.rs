//! The reference render loop: every pixel, every sample, in parallel over rows.

use std::f32::consts::FRAC_1_PI;
use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::{UVec2, Vec2, Vec3, Vec3A};
use rayon::prelude::*;

use super::accel::{Accel, Hit, PACKET_SIZE};
use super::rays::{primary_rays, real_lens_rays};
use super::surface::{shadow_origin, SurfaceData, SurfacePoint};
use crate::camera::{Camera, Ray};
use crate::film::{Image, OnDevice, Progress, Sums};
use crate::sampler::{pixel_sampler, shared_pixel_sampler};
use crate::scene::{Material, Scene};
use crate::settings::{RenderSettings, Shading, Shot};

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

    /// Bytes of the acceleration structure (BVH and leaf-ordered triangles).
    pub fn accel_bytes(&self) -> u64 {
        self.accel.bytes()
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

    /// Renders the image of `shot`; `progress(done_rows, total_rows)` is called between bands
    /// of rows.
    pub fn render(&self, shot: &Shot, progress: &mut Progress) -> (Image, RenderStats) {
        let whole: Result<_, OnDevice> = crate::film::whole_image(
            &mut &*self,
            progress,
            shot,
            |this: &mut &Self, progress| Ok(this.render_aov(shot, progress)),
            |this, samples, accumulation, progress| {
                let sums = accumulation.host_mut()?;
                Ok(this.accumulate(shot, samples, sums, progress))
            },
            |_, _| Ok(()),
        );
        whole.expect("the CPU keeps its accumulation on the host")
    }

    /// Adds samples `samples` of every pixel of `shot` (thin lens, `Unlit` or `Lit`) to `sums`,
    /// which has the camera's size; `progress(done_rows, total_rows)` is called between bands
    /// of rows. Each pixel's samples are added one after the other to its sum, so any split of
    /// a range gives the same sums.
    pub fn accumulate(
        &self,
        shot: &Shot,
        samples: Range<u32>,
        sums: &mut Sums,
        progress: &mut Progress,
    ) -> RenderStats {
        let camera = &shot.camera;
        debug_assert_eq!((sums.width, sums.height), (camera.width, camera.height));
        self.for_each_row(camera, &mut sums.pixels, progress, |y, row| {
            let mut rays = 0;
            for (x, sum) in row.iter_mut().enumerate() {
                let pixel = UVec2::new(x as u32, y);
                rays += self.add_pixel_samples(shot, pixel, samples.clone(), sum);
            }
            rays
        })
    }

    /// The AOVs of `shot`: the surface seen by the aperture-centre ray through each pixel
    /// centre.
    fn render_aov(&self, shot: &Shot, progress: &mut Progress) -> (Image, RenderStats) {
        let camera = &shot.camera;
        let mut image = Image::new(camera.width, camera.height);
        let stats = self.for_each_row(camera, &mut image.pixels, progress, |y, row| {
            for (x, value) in row.iter_mut().enumerate() {
                // The G-buffer's definition: the aperture-centre ray through the pixel centre.
                let centre = UVec2::new(x as u32, y).as_vec2() + Vec2::splat(0.5);
                let ray = camera.first_order_ray(centre, Vec2::splat(0.5));
                *value = self.aov(shot, &ray);
            }
            row.len() as u64
        });
        (image, stats)
    }

    /// Runs `row_fn(y, row)` over the image's rows in parallel, band after band, counting the
    /// rays it returns.
    fn for_each_row<T: Send>(
        &self,
        camera: &Camera,
        pixels: &mut [T],
        progress: &mut Progress,
        row_fn: impl Fn(u32, &mut [T]) -> u64 + Sync,
    ) -> RenderStats {
        let start = Instant::now();
        let (width, height) = (camera.width, camera.height);
        let rays = AtomicU64::new(0);
        for (band, rows) in pixels
            .chunks_mut((width * ROWS_PER_BAND) as usize)
            .enumerate()
        {
            rows.par_chunks_mut(width as usize)
                .enumerate()
                .for_each(|(r, row)| {
                    let y = band as u32 * ROWS_PER_BAND + r as u32;
                    rays.fetch_add(row_fn(y, row), Ordering::Relaxed);
                });
            let done = ((band as u32 + 1) * ROWS_PER_BAND).min(height);
            progress(done as u64, height as u64);
        }
        RenderStats {
            elapsed: start.elapsed(),
            rays: rays.into_inner(),
        }
    }

    /// Adds the pixel's samples `samples` of `shot` to its `[sum, count]`; returns the rays
    /// traced.
    fn add_pixel_samples(
        &self,
        shot: &Shot,
        pixel: UVec2,
        samples: Range<u32>,
        sum_and_count: &mut [f32; 4],
    ) -> u64 {
        let (camera, settings) = (&shot.camera, &shot.render);
        let [r, g, b, count] = *sum_and_count;
        let mut sum = Vec3::new(r, g, b);
        let mut rays = 0;
        // The samples of a pixel are coherent: their primary rays are traced as packets.
        let mut origins = [Vec3::ZERO; PACKET_SIZE];
        let mut directions = [Vec3::ZERO; PACKET_SIZE];
        let mut hits = [None; PACKET_SIZE];
        let sampler = if settings.shared_samples {
            shared_pixel_sampler(settings.sampler, settings.seed, pixel)
        } else {
            pixel_sampler(settings.sampler, settings.seed, pixel, camera.width)
        };
        if camera.lens.real().is_some() {
            let mut weights = [0.0; PACKET_SIZE];
            for first in samples.clone().step_by(PACKET_SIZE) {
                let n = (samples.end - first).min(PACKET_SIZE as u32) as usize;
                let passed = real_lens_rays(
                    camera,
                    &sampler,
                    (first, n),
                    &mut origins,
                    &mut directions,
                    &mut weights,
                );
                let hits = &mut hits[..passed];
                let (o, d) = (&origins[..passed], &directions[..passed]);
                self.accel.closest_hits(o, d, 0.0, f32::INFINITY, hits);
                for i in 0..passed {
                    let ray = Ray {
                        origin: origins[i],
                        direction: directions[i],
                    };
                    let (value, count) = self.shade(&ray, hits[i], settings);
                    sum += weights[i] * value;
                    rays += count;
                }
            }
            *sum_and_count = [sum.x, sum.y, sum.z, count + samples.len() as f32];
            return rays;
        }
        for first in samples.clone().step_by(PACKET_SIZE) {
            let n = (samples.end - first).min(PACKET_SIZE as u32) as usize;
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
        *sum_and_count = [sum.x, sum.y, sum.z, count + samples.len() as f32];
        rays
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

    /// The AOV of `shot.render.shading` of the surface `ray` sees.
    fn aov(&self, shot: &Shot, ray: &Ray) -> Vec3 {
        let (camera, settings) = (&shot.camera, &shot.render);
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
