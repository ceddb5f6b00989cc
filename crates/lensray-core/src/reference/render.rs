//! The reference render loop: every pixel, every sample, in parallel over rows.

use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::{UVec2, Vec2, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::accel::{Accel, AlphaTest, Hit, PACKET_SIZE};
use super::rays::{generate_rays, DispersionPass, LensPacket, PacketSamples};
use super::steps::{Stepped, TriangleSteps, STEPS};
use super::surface::{Materials, SurfaceData, SurfacePoint};
use crate::camera::{Camera, Footprint, Ray};
use crate::film::adaptive::{self, is_class_a, AdaptiveReport};
use crate::film::spectral::{checked_value, d_line_value};
use crate::film::{Image, OnDevice, Progress, Sums};
use crate::sampler::{pixel_sampler, shared_pixel_sampler, CameraSample, PixelSampler};
use crate::scene::emitters::EmitterDistribution;
use crate::scene::motion::{LightSteps, MeshSteps, ObjectMotion};
use crate::scene::order::sided_order;
use crate::scene::{blend_threshold, ray_key, EnvironmentLight, Light, Scene};
use crate::scene::{AOV_BLEND_THRESHOLD, BLEND_CAMERA_SALT};
use crate::settings::{Shading, Shot};

/// Rows rendered between two progress reports.
const ROWS_PER_BAND: u32 = 16;

pub struct Renderer {
    pub(super) accel: Accel,
    pub(super) surfaces: Arc<SurfaceData>,
    pub(super) materials: Arc<Materials>,
    pub(super) lights: Vec<Light>,
    /// The lights that move while the shutter is open, at each step.
    pub(super) moving_lights: Vec<LightSteps>,
    /// The emissive triangles, drawn as lights by their power.
    pub(super) emitters: EmitterDistribution,
    pub(super) environment: Option<Arc<EnvironmentLight>>,
    /// Light the sky by one cosine-distributed ray a surface instead of the two draws weighed
    /// by multiple importance sampling (`with_cosine_sky`).
    pub(super) cosine_sky: bool,
    /// How many directions a map's draw picks among (`SKY_CANDIDATES`; `with_sky_candidates`).
    pub(super) sky_candidates: u32,
    /// Where the frame's own time lies in the shutter's span: the moment the AOVs and focus
    /// picking see moving triangles at.
    frame_moment: f32,
}

/// A packet of camera rays after their closest hits: per lane its ray, hit, blend key and
/// moment, and sample index.
pub(super) struct TracedPacket<'a> {
    pub origins: &'a [Vec3],
    pub directions: &'a [Vec3],
    pub hits: &'a [Option<Hit>],
    pub draws: &'a [(u32, f32)],
    pub indices: &'a [u32],
}

/// One pixel's samples as its packets are traced: the shot, the pixel's sampler, the camera's
/// footprint, a packet of camera rays, and the sums the samples add to.
struct PixelTrace<'a> {
    shot: &'a Shot,
    sampler: &'a PixelSampler,
    pixel_index: u32,
    footprint: Footprint,
    packet: LensPacket,
    sum: &'a mut Vec3,
    /// Class A's sum (adaptive sampling).
    class_a: Option<&'a mut Vec3>,
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
    /// Flattens the scene's meshes and builds the acceleration structure. The triangles are
    /// numbered as the GPU upload numbers them (each mesh's in its sided spatial order,
    /// `scene::order::sided_order`), which a blend draw hashes.
    pub fn new(scene: &Scene) -> Self {
        Self::with_motion(scene, None)
    }

    /// [`Self::new`] with the meshes `motion` names moving through its steps while the shutter
    /// is open (the rest of each, and every other mesh, is `scene`'s), and the lights it names
    /// through theirs. Moving emissive triangles light what they meet but are not drawn as
    /// lights.
    pub fn with_motion(scene: &Scene, motion: Option<&ObjectMotion>) -> Self {
        let count = scene.triangle_count();
        let mut steps = TriangleSteps::default();
        let mut triangles = Vec::with_capacity(count);
        let mut surfaces = SurfaceData {
            normals: Vec::with_capacity(count),
            texcoords: Vec::with_capacity(count),
            texcoords1: Vec::new(),
            colours: Vec::new(),
            tangents: Vec::new(),
            materials: Vec::with_capacity(count),
            steps: Arc::new(TriangleSteps::default()),
        };
        let any_colours = scene.meshes.iter().any(|m| !m.colours.is_empty());
        let any_tangents = scene.meshes.iter().any(|m| !m.tangents.is_empty());
        let any_texcoords1 = scene.meshes.iter().any(|m| !m.texcoords1.is_empty());
        for (m, mesh) in scene.meshes.iter().enumerate() {
            let single_sided =
                |t: usize| !scene.materials[mesh.material_ids[t] as usize].double_sided;
            let moving = motion.and_then(|motion| motion.meshes.iter().find(|s| s.index == m));
            for t in sided_order(&mesh.positions, &mesh.triangles, single_sided) {
                let tri = mesh.triangles[t as usize];
                match moving {
                    Some(moving) => push_moving(&mut steps, triangles.len(), moving, tri),
                    None => steps.push_still(triangles.len()),
                }
                triangles.push(tri.map(|i| Vec3A::from(mesh.positions[i as usize])));
                surfaces.normals.push(if mesh.normals.is_empty() {
                    [Vec3::ZERO; 3]
                } else {
                    tri.map(|i| mesh.normals[i as usize])
                });
                let texcoords = |set: &[Vec2]| match set.is_empty() {
                    true => [Vec2::ZERO; 3],
                    false => tri.map(|i| set[i as usize]),
                };
                surfaces.texcoords.push(texcoords(&mesh.texcoords));
                if any_texcoords1 {
                    surfaces.texcoords1.push(texcoords(&mesh.texcoords1));
                }
                let corners =
                    |values: &[Vec4]| (!values.is_empty()).then(|| tri.map(|i| values[i as usize]));
                if any_colours {
                    surfaces.colours.push(corners(&mesh.colours));
                }
                if any_tangents {
                    surfaces.tangents.push(corners(&mesh.tangents));
                }
                surfaces.materials.push(mesh.material_ids[t as usize]);
            }
        }
        let steps = Arc::new(steps);
        surfaces.steps = Arc::clone(&steps);
        let surfaces = Arc::new(surfaces);
        let materials = Arc::new(Materials {
            materials: scene.materials.clone(),
            textures: scene.textures.clone(),
        });
        let alpha_tested: Vec<bool> = surfaces
            .materials
            .iter()
            .map(|&m| materials.get(m).is_alpha_tested())
            .collect();
        let alpha: Option<AlphaTest> = alpha_tested.contains(&true).then(|| {
            let (surfaces, materials) = (Arc::clone(&surfaces), Arc::clone(&materials));
            Arc::new(move |triangle, b, key| stops(&surfaces, &materials, triangle, b, key))
                as AlphaTest
        });
        let single_sided: Vec<bool> = surfaces
            .materials
            .iter()
            .map(|&m| !materials.get(m).double_sided)
            .collect();
        Self {
            emitters: EmitterDistribution::new(
                &triangles
                    .iter()
                    .map(|t| t.map(Vec3::from))
                    .collect::<Vec<_>>(),
                |t| match steps.row(t as u32) {
                    Some(_) => Vec3::ZERO,
                    None => materials.get(surfaces.materials[t]).emission,
                },
            ),
            accel: Accel::build_with_tests(&triangles, &alpha_tested, &single_sided, alpha, steps),
            surfaces,
            materials,
            lights: scene.lights.clone(),
            moving_lights: motion.map_or(Vec::new(), |motion| motion.lights.clone()),
            environment: scene.environment.clone(),
            cosine_sky: false,
            sky_candidates: crate::interface::SKY_CANDIDATES,
            frame_moment: motion.map_or(0.5, |motion| motion.frame_moment),
        }
    }

    /// This renderer with the sky drawn by one cosine-distributed ray a surface and nothing
    /// else (an unbiased estimator without multiple importance sampling, which the GPU paths
    /// do not offer): what benches/environment.rs compares the default with at equal time.
    pub fn with_cosine_sky(mut self) -> Self {
        self.cosine_sky = true;
        self
    }

    /// This renderer with a map's draw picking among `candidates` directions (at least 1: the
    /// map's power alone, what lensray did before resampling; the GPU paths take
    /// `SKY_CANDIDATES`): what benches/environment.rs and the tests compare the default with.
    pub fn with_sky_candidates(mut self, candidates: u32) -> Self {
        self.sky_candidates = candidates.max(1);
        self
    }

    /// This renderer with no emitters' draw: an emissive triangle's light is found only where
    /// a BRDF's draw meets it, whole (unbiased, what lensray did before emitters were lights):
    /// what benches/emitters.rs compares the default with at equal time.
    pub fn without_emitter_draws(mut self) -> Self {
        self.emitters = EmitterDistribution::new(&[], |_| Vec3::ZERO);
        self
    }

    pub fn bvh_build_time(&self) -> Duration {
        self.accel.build_time
    }

    /// Bytes of the acceleration structure (BVH and leaf-ordered triangles).
    pub fn accel_bytes(&self) -> u64 {
        self.accel.bytes()
    }

    /// Closest hit along a world-space ray, t in (0, inf), as the AOVs' aperture-centre ray
    /// sees it (a blended surface where its alpha exceeds `AOV_BLEND_THRESHOLD`; what moves,
    /// at the frame's own time).
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let range = (0.0, f32::INFINITY);
        let moment = self.frame_moment;
        self.accel
            .closest_hit(ray.origin, ray.direction, range, None, moment)
    }

    /// The closest hits of a packet of camera rays whose keys and moments are `draws`.
    fn closest_hits(
        &self,
        origins: &[Vec3],
        directions: &[Vec3],
        draws: &[(u32, f32)],
        hits: &mut [Option<Hit>],
    ) {
        self.accel
            .closest_hits(origins, directions, draws, (0.0, f32::INFINITY), hits);
    }

    pub fn surface_point(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let v = self.accel.hit_vertices(hit);
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
                match shot.render.noise_threshold {
                    Some(threshold) => Ok(this.render_adaptive(shot, threshold, sums, progress).0),
                    None => Ok(this.accumulate(shot, samples, sums, progress)),
                }
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
                rays += self.add_pixel_samples(shot, pixel, samples.clone(), sum, None);
            }
            rays
        })
    }

    /// Renders `shot` adaptively into `sums` (new, the camera's size): rounds of samples to
    /// the pixels whose error is still at or above `threshold` (`film::adaptive`), `spp` at
    /// most. `progress` follows the rounds.
    pub fn render_adaptive(
        &self,
        shot: &Shot,
        threshold: f32,
        sums: &mut Sums,
        progress: &mut Progress,
    ) -> (RenderStats, AdaptiveReport) {
        let mut stats = RenderStats::default();
        let rounds = adaptive::render_adaptive(
            threshold,
            shot.render.spp,
            sums,
            progress,
            |end, active, sums, class_a| {
                let round = self.accumulate_active(shot, end, active, sums, class_a);
                stats.elapsed += round.elapsed;
                stats.rays += round.rays;
                Ok::<_, std::convert::Infallible>(())
            },
        );
        let Ok(report) = rounds;
        (stats, report)
    }

    /// Brings every pixel marked in `active` from the samples it has to `end` (its indices
    /// `count..end`), adding its class A samples (`film::adaptive::is_class_a`) to `class_a`
    /// too.
    pub fn accumulate_active(
        &self,
        shot: &Shot,
        end: u32,
        active: &[bool],
        sums: &mut Sums,
        class_a: &mut [Vec3],
    ) -> RenderStats {
        let start = Instant::now();
        let width = shot.camera.width as usize;
        let rays: u64 = sums
            .pixels
            .par_chunks_mut(width)
            .zip(class_a.par_chunks_mut(width))
            .zip(active.par_chunks(width))
            .enumerate()
            .map(|(y, ((row, row_a), row_active))| {
                let mut rays = 0;
                for (x, (sum, a)) in row.iter_mut().zip(row_a).enumerate() {
                    if row_active[x] {
                        let pixel = UVec2::new(x as u32, y as u32);
                        let samples = adaptive::pixel_range(sum[3], end);
                        rays += self.add_pixel_samples(shot, pixel, samples, sum, Some(a));
                    }
                }
                rays
            })
            .sum();
        RenderStats {
            elapsed: start.elapsed(),
            rays,
        }
    }

    /// The AOVs of `shot`: the surface seen by the aperture-centre ray through each pixel
    /// centre, from the frame's pose (the G-buffer's camera, which the shutter does not move).
    fn render_aov(&self, shot: &Shot, progress: &mut Progress) -> (Image, RenderStats) {
        let still = shot.camera.clone().with_motion(None);
        let camera = &still;
        let mut image = Image::new(camera.width, camera.height);
        let stats = self.for_each_row(camera, &mut image.pixels, progress, |y, row| {
            for (x, value) in row.iter_mut().enumerate() {
                // The G-buffer's definition: the aperture-centre ray through the pixel centre.
                let centre = UVec2::new(x as u32, y).as_vec2() + Vec2::splat(0.5);
                let ray = camera.first_order_ray(CameraSample::new(centre, Vec2::splat(0.5)));
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

    /// Adds the pixel's samples `samples` of `shot` to its `[sum, count]`, and those of class A
    /// to `class_a` when given (adaptive sampling); returns the rays traced.
    fn add_pixel_samples(
        &self,
        shot: &Shot,
        pixel: UVec2,
        samples: Range<u32>,
        sum_and_count: &mut [f32; 4],
        class_a: Option<&mut Vec3>,
    ) -> u64 {
        let (camera, settings) = (&shot.camera, &shot.render);
        let [r, g, b, count] = *sum_and_count;
        let mut sum = Vec3::new(r, g, b);
        let mut rays = 0;
        let sampler = if settings.shared_samples {
            shared_pixel_sampler(settings.sampler, settings.seed, pixel)
        } else {
            pixel_sampler(settings.sampler, settings.seed, pixel, camera.width)
        };
        let mut trace = PixelTrace {
            shot,
            sampler: &sampler,
            pixel_index: pixel.y * camera.width + pixel.x,
            footprint: camera.footprint(),
            packet: LensPacket::new(),
            sum: &mut sum,
            class_a,
        };
        // The samples of a pixel are coherent: their primary rays are traced as packets. A
        // dispersive lens traces every sample at the d line, then the samples that check it at
        // their wavelengths, gathered into packets of their own (film::spectral, "Dispersion at
        // little cost").
        let mut checks = PacketSamples::new();
        for first in samples.clone().step_by(PACKET_SIZE) {
            let n = (samples.end - first).min(PACKET_SIZE as u32) as usize;
            let run = PacketSamples::run(camera, &sampler, first, n);
            rays += self.trace_packet(&mut trace, &run, DispersionPass::DLine);
            for l in (0..n).filter(|&l| run.checked[l] > 0.0) {
                checks.push(run.indices[l], run.checked[l]);
                if checks.n == PACKET_SIZE {
                    rays += self.trace_packet(&mut trace, &checks, DispersionPass::Checks);
                    checks.n = 0;
                }
            }
        }
        if checks.n > 0 {
            rays += self.trace_packet(&mut trace, &checks, DispersionPass::Checks);
        }
        *sum_and_count = [sum.x, sum.y, sum.z, count + samples.len() as f32];
        rays
    }

    /// Traces and shades the camera rays of `samples` in `pass`, and adds their values to the
    /// pixel's sums; returns the rays traced.
    fn trace_packet(
        &self,
        pixel: &mut PixelTrace,
        samples: &PacketSamples,
        pass: DispersionPass,
    ) -> u64 {
        let settings = &pixel.shot.render;
        let packet = &mut pixel.packet;
        let traced = generate_rays(&pixel.shot.camera, pixel.sampler, samples, pass, packet);
        let mut draws = [(0, 0.5); PACKET_SIZE];
        let mut hits = [None; PACKET_SIZE];
        for (l, draw) in draws.iter_mut().enumerate().take(traced) {
            let index = packet.indices[l];
            let key = ray_key(settings.seed, pixel.pixel_index, index, BLEND_CAMERA_SALT);
            *draw = (key, packet.moments[l]);
        }
        let (o, d) = (&packet.origins[..traced], &packet.directions[..traced]);
        self.closest_hits(o, d, &draws[..traced], &mut hits[..traced]);
        let lanes = TracedPacket {
            origins: &packet.origins[..traced],
            directions: &packet.directions[..traced],
            hits: &hits[..traced],
            draws: &draws[..traced],
            indices: &packet.indices[..traced],
        };
        let (values, rays) = self.shade_packet(&lanes, pixel.sampler, settings, &pixel.footprint);
        for (l, &shaded) in values.iter().enumerate().take(traced) {
            // Through a dispersive lens: the d line's radiance, and where the sample checks
            // it, what its wavelength changes, as linear sRGB (film::spectral).
            let checked = (packet.wavelengths[l] > 0.0).then_some(packet.wavelengths[l]);
            let value = match (pass, checked) {
                (DispersionPass::Checks, Some(lambda)) => checked_value(lambda, shaded),
                _ => d_line_value(checked, shaded),
            };
            let weighted = packet.weights[l] * value;
            *pixel.sum += weighted;
            if let Some(a) = pixel.class_a.as_deref_mut() {
                if is_class_a(packet.indices[l]) {
                    *a += weighted;
                }
            }
        }
        rays
    }

    /// The AOV of `shot.render.shading` of the surface `ray` sees.
    fn aov(&self, shot: &Shot, ray: &Ray) -> Vec3 {
        let (camera, settings) = (&shot.camera, &shot.render);
        let hit = self.intersect(ray);
        match (settings.shading, hit) {
            (Shading::Albedo, None) => settings.background,
            (_, None) => Vec3::ZERO,
            (shading, Some(hit)) => {
                let mut surface = self.surface_point(ray, &hit);
                match shading {
                    Shading::Depth => Vec3::splat(camera.view_depth(surface.position)),
                    Shading::Normal => surface.shading_normal,
                    _ => {
                        let footprint = camera.footprint();
                        let inputs = self.colours(&hit, &mut surface, Some(&footprint));
                        inputs.brdf.base.base_colour
                    }
                }
            }
        }
    }
}

/// Appends triangle `tri` (the renderer's `triangle`) of the mesh `moving` names to `steps`,
/// with its corners, normals and tangents at each step.
fn push_moving(steps: &mut TriangleSteps, triangle: usize, moving: &MeshSteps, tri: [u32; 3]) {
    let step = |k: usize| &moving.steps[k];
    let vertices: Stepped<Vec3A> =
        std::array::from_fn(|k| tri.map(|i| Vec3A::from(step(k).positions[i as usize])));
    let normals: Stepped<Vec3> = match step(0).normals.is_empty() {
        true => [[Vec3::ZERO; 3]; STEPS],
        false => std::array::from_fn(|k| tri.map(|i| step(k).normals[i as usize])),
    };
    let tangents = (!step(0).tangents.is_empty())
        .then(|| std::array::from_fn(|k| tri.map(|i| step(k).tangents[i as usize])));
    steps.push_moving(triangle, vertices, normals, tangents);
}

/// Whether a ray of draw `key` stops at the hit (`triangle`, `b`): the material's alpha test,
/// with the ray's blend draw (`None`: the AOVs' fixed threshold).
fn stops(
    surfaces: &SurfaceData,
    materials: &Materials,
    triangle: u32,
    b: Vec2,
    key: Option<u32>,
) -> bool {
    let material = materials.get(surfaces.materials[triangle as usize]);
    if !material.is_alpha_tested() {
        return true;
    }
    let threshold = match key {
        Some(key) => blend_threshold(key, triangle),
        None => AOV_BLEND_THRESHOLD,
    };
    let texcoords = surfaces.texcoords(triangle, b);
    material.stops_ray(&materials.textures, &texcoords, threshold)
}
