//! The acceleration structure of the CPU reference: Embree 3 (Intel's ray-tracing kernels, through
//! the `embree3` crate's safe binding), built in its robust (watertight) mode. Triangles are
//! grouped into Embree geometries by their tests, alpha-tested or not, single-sided or not, so
//! that only candidate hits on alpha-tested or single-sided triangles go through an Embree filter
//! function (the alpha test, the facing test [`is_back_face`]); opaque double-sided scenes pay
//! nothing for either. Triangles that move while the shutter is open (`steps.rs`) are grouped
//! apart too, as Embree motion-blur geometries with a time step per step of the span: a ray's
//! `time` is its sample's moment.
//! docs/performance.md says why Embree and what it measured against lensray's own traversal.

use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use embree3::{
    BufferUsage, BuildQuality, Format, GeometryKind, HitN, IntersectContext, Ray, Ray16, RayHit,
    RayHit16, RayN, Scene, SceneFlags, SoAHit, SoARay, ValidMask, ValidMaskN, ValidityN,
    INVALID_ID,
};

use super::embree::EmbreeSettings;
use super::steps::{TriangleSteps, STEPS};
use glam::{Vec2, Vec3, Vec3A};

/// Rays traced together by [`Accel::closest_hits`]: the samples of one pixel, in one of
/// Embree's packets.
pub const PACKET_SIZE: usize = 16;

/// The alignment Embree's `rtcIntersectN`/`rtcOccludedN` require of a packet of `width` lanes and
/// of its valid mask: one SIMD register of 32-bit lanes (16 bytes for 4, 32 for 8, 64 for 16), as
/// the kernels load them with aligned SSE, AVX and AVX-512 loads.
pub const fn packet_alignment(width: usize) -> usize {
    width * 4
}

/// The valid mask of a [`PACKET_SIZE`]-wide packet, aligned as Embree's 16-wide kernels read it.
/// The `embree3` crate's `ValidMaskN` is only 16-byte aligned, and an AVX-512 CPU faults on a
/// mask that is not 64-byte aligned; this wrapper holds it at offset 0 of a 64-byte aligned type,
/// so every mask lensray hands to Embree is aligned by its type.
#[repr(C, align(64))]
pub struct PacketMask(ValidMaskN<PACKET_SIZE>);

impl PacketMask {
    /// Lane l is active where `active(l)`.
    fn new(active: impl Fn(usize) -> bool) -> Self {
        let mut mask = ValidMaskN::<PACKET_SIZE>::all_active();
        for (l, lane) in mask.lanes_mut().iter_mut().enumerate() {
            if !active(l) {
                *lane = ValidMask::Invalid;
            }
        }
        Self(mask)
    }

    /// The mask as the `embree3` crate passes it on: at this type's 64-byte aligned address.
    fn get(&self) -> &ValidMaskN<PACKET_SIZE> {
        &self.0
    }
}

/// Embree's geometry id of a group of triangles: these bits of their tests and motion.
const ALPHA_TESTED: usize = 1;
const SINGLE_SIDED: usize = 2;
const MOVING: usize = 4;
const GROUPS: usize = 8;

/// A ray's `mask` tells the alpha test which draw the ray makes: its key (in the ray's `id`),
/// or the fixed threshold of the AOVs. Both keep every bit a geometry's mask may test (Embree
/// built with ray masks tests `ray.mask & geometry.mask`, the geometry's all ones).
const MASK_KEYED: u32 = u32::MAX;
const MASK_FIXED: u32 = u32::MAX - 1;

/// Whether a ray stops at a candidate hit `(triangle, barycentric)` of an alpha-tested
/// triangle, for the ray's draw: `Some(key)` the ray's own, `None` the AOVs' fixed threshold.
pub type AlphaTest = Arc<dyn Fn(u32, Vec2, Option<u32>) -> bool + Send + Sync>;

/// A closest hit, in the caller's triangle order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub triangle: u32,
    /// Weights of v1 and v2 (v0's is 1 - x - y), as Vulkan ray queries and Embree report them.
    pub barycentric: Vec2,
    /// The ray's moment in the shutter's span, where a moving triangle was met.
    pub moment: f32,
}

pub struct Accel {
    scene: Scene<'static>,
    /// Each geometry's primitive -> the caller's triangle.
    triangles_of: [Arc<Vec<u32>>; GROUPS],
    /// Vertices per triangle, the caller's order.
    corners: Arc<TriangleVertices>,
    /// Bytes Embree allocated for the scene (its BVH and its copy of the triangles).
    embree_bytes: u64,
    pub build_time: Duration,
}

impl Accel {
    /// Builds over opaque triangles in the caller's order.
    pub fn build(triangles: &[[Vec3A; 3]]) -> Self {
        Self::build_with_tests(triangles, &[], &[], None, Arc::default())
    }

    /// Builds over triangles in the caller's order; those marked in `alpha_tested` (all
    /// opaque when it is empty) stop a ray only where `alpha` says so, those marked in
    /// `single_sided` (all double-sided when it is empty) only a ray that meets their front
    /// face ([`is_back_face`]); those `steps` has move through its steps.
    pub(super) fn build_with_tests(
        triangles: &[[Vec3A; 3]],
        alpha_tested: &[bool],
        single_sided: &[bool],
        alpha: Option<AlphaTest>,
        steps: Arc<TriangleSteps>,
    ) -> Self {
        let start = Instant::now();
        // The CLI checks LENSRAY_EMBREE_CONFIG before any render, in one line.
        let device = EmbreeSettings::from_env()
            .unwrap_or_else(|error| panic!("{error}"))
            .device();
        let allocated = Arc::new(AtomicI64::new(0));
        let counter = Arc::clone(&allocated);
        device.set_memory_monitor_function(move |bytes, _post| {
            counter.fetch_add(bytes as i64, Ordering::Relaxed);
            true
        });
        let mut groups: [Vec<u32>; GROUPS] = Default::default();
        for (i, _) in triangles.iter().enumerate() {
            let tested = alpha.is_some() && alpha_tested.get(i).copied().unwrap_or(false);
            let one_side = single_sided.get(i).copied().unwrap_or(false);
            let moving = steps.row(i as u32).is_some();
            let group = usize::from(tested) * ALPHA_TESTED
                + usize::from(one_side) * SINGLE_SIDED
                + usize::from(moving) * MOVING;
            groups[group].push(i as u32);
        }
        let triangles_of = groups.map(Arc::new);
        let corners = Arc::new(TriangleVertices {
            still: triangles.to_vec(),
            steps: Arc::clone(&steps),
        });
        let mut scene = device.create_scene().expect("an Embree scene");
        scene.set_flags(SceneFlags::ROBUST);
        scene.set_build_quality(if triangles.len() > 250_000 {
            BuildQuality::MEDIUM
        } else {
            BuildQuality::HIGH
        });
        for (group, members) in triangles_of.iter().enumerate() {
            if members.is_empty() {
                continue;
            }
            let mut geometry = device
                .create_geometry(GeometryKind::TRIANGLE)
                .expect("an Embree geometry");
            let moving = group & MOVING != 0;
            if moving {
                geometry.set_time_step_count(STEPS as u32);
            }
            for step in 0..if moving { STEPS } else { 1 } {
                let corners = |t: u32| match steps.row(t) {
                    Some(row) if moving => steps.vertices[row][step],
                    _ => triangles[t as usize],
                };
                let vertices: Vec<[f32; 3]> = members
                    .iter()
                    .flat_map(|&t| corners(t).map(|v| v.to_array()))
                    .collect();
                geometry
                    .set_new_buffer::<[f32; 3]>(
                        BufferUsage::VERTEX,
                        step as u32,
                        Format::FLOAT3,
                        12,
                        vertices.len(),
                    )
                    .expect("Embree vertex buffer")
                    .copy_from_slice(&vertices);
            }
            let indices: Vec<[u32; 3]> = (0..members.len() as u32)
                .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
                .collect();
            geometry
                .set_new_buffer::<[u32; 3]>(BufferUsage::INDEX, 0, Format::UINT3, 12, indices.len())
                .expect("Embree index buffer")
                .copy_from_slice(&indices);
            if group & (SINGLE_SIDED | ALPHA_TESTED) != 0 {
                let filter = Arc::new(SurfaceFilter {
                    triangles_of: Arc::clone(members),
                    corners: (group & SINGLE_SIDED != 0).then(|| Arc::clone(&corners)),
                    alpha: alpha.clone().filter(|_| group & ALPHA_TESTED != 0),
                });
                let each = Arc::clone(&filter);
                geometry.set_intersect_filter_function(
                    move |rays, hits, valid, _, _: Option<&()>| each.run(&rays, &hits, valid),
                );
                geometry.set_occluded_filter_function(
                    move |rays, hits, valid, _, _: Option<&()>| filter.run(&rays, &hits, valid),
                );
            }
            scene.attach_geometry_by_id(&geometry.commit(), group as u32);
        }
        scene.commit();
        Self {
            scene,
            triangles_of,
            corners,
            embree_bytes: allocated.load(Ordering::Relaxed).max(0) as u64,
            build_time: start.elapsed(),
        }
    }

    /// Bytes of Embree's scene and of the vertices kept for shading.
    pub fn bytes(&self) -> u64 {
        self.embree_bytes
            + std::mem::size_of_val(self.corners.still.as_slice()) as u64
            + self.corners.steps.bytes()
    }

    /// The vertices of a triangle that stands still (an emitter: moving ones are not drawn).
    pub fn vertices(&self, triangle: u32) -> &[Vec3A; 3] {
        &self.corners.still[triangle as usize]
    }

    /// The vertices of `triangle` at `moment` of the shutter's span.
    pub fn vertices_at(&self, triangle: u32, moment: f32) -> [Vec3A; 3] {
        self.corners.at(triangle, moment)
    }

    /// The vertices of the triangle `hit` met, where the ray met it.
    pub fn hit_vertices(&self, hit: &Hit) -> [Vec3; 3] {
        self.vertices_at(hit.triangle, hit.moment).map(Vec3::from)
    }

    /// Whether `triangle` moves while the shutter is open.
    pub fn moves(&self, triangle: u32) -> bool {
        self.corners.steps.row(triangle).is_some()
    }

    fn hit(&self, ray: (f32, f32), geometry: u32, primitive: u32, u: f32, v: f32) -> Option<Hit> {
        let (t, moment) = ray;
        (geometry != INVALID_ID).then(|| Hit {
            t,
            triangle: self.triangles_of[geometry as usize][primitive as usize],
            barycentric: Vec2::new(u, v),
            moment,
        })
    }

    /// Closest hit with t in [t_min, t_max] that stops a ray of draw `key` (see [`AlphaTest`])
    /// at `moment` of the shutter's span.
    pub fn closest_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        (t_min, t_max): (f32, f32),
        key: Option<u32>,
        moment: f32,
    ) -> Option<Hit> {
        let mut ray_hit = RayHit::from(ray(origin, direction, (t_min, t_max), key, moment));
        self.scene
            .intersect(&mut IntersectContext::coherent(), &mut ray_hit);
        let (r, h) = (&ray_hit.ray, &ray_hit.hit);
        self.hit((r.tfar, r.time), h.geomID, h.primID, h.u, h.v)
    }

    /// Whether a surface that stops a ray of draw `key` at `moment` lies on the ray, t in
    /// [t_min, t_max]: the shadow test.
    pub fn occluded(
        &self,
        origin: Vec3,
        direction: Vec3,
        (t_min, t_max): (f32, f32),
        key: Option<u32>,
        moment: f32,
    ) -> bool {
        let mut ray = ray(origin, direction, (t_min, t_max), key, moment);
        self.scene
            .occluded(&mut IntersectContext::incoherent(), &mut ray)
    }

    /// The closest hits of up to [`PACKET_SIZE`] rays (lane l drawing `draws[l]`: its key and
    /// moment), t in [t_min, t_max], traced as one Embree packet: the same hits as
    /// [`Accel::closest_hit`] ray by ray, found faster when the rays are coherent (the samples
    /// of a pixel).
    pub fn closest_hits(
        &self,
        origins: &[Vec3],
        directions: &[Vec3],
        draws: &[(u32, f32)],
        (t_min, t_max): (f32, f32),
        hits: &mut [Option<Hit>],
    ) {
        let n = origins.len();
        assert!(n <= PACKET_SIZE && directions.len() == n && draws.len() == n && hits.len() == n);
        let mut packet = Ray16::segment(
            std::array::from_fn(|l| origins.get(l).map_or([0.0; 3], |o| o.to_array())),
            std::array::from_fn(|l| directions.get(l).map_or([0.0, 0.0, 1.0], |d| d.to_array())),
            [t_min; PACKET_SIZE],
            [t_max; PACKET_SIZE],
        );
        for (l, &(key, moment)) in draws.iter().enumerate() {
            packet.id[l] = key;
            packet.time[l] = moment;
            packet.mask[l] = MASK_KEYED;
        }
        let valid = PacketMask::new(|l| l < n);
        let mut ray_hits = RayHit16 {
            ray: packet,
            hit: embree3::Hit16::new(),
        };
        self.scene.intersect16(
            &mut IntersectContext::coherent(),
            &mut ray_hits,
            valid.get(),
        );
        let (r, h) = (&ray_hits.ray, &ray_hits.hit);
        for (l, hit) in hits.iter_mut().enumerate() {
            let ray = (r.tfar[l], r.time[l]);
            *hit = self.hit(ray, h.geomID[l], h.primID[l], h.u[l], h.v[l]);
        }
    }
}

impl Accel {
    /// Which of up to [`PACKET_SIZE`] shadow rays `(origin, direction, t_max)` (lane l drawing
    /// `draws[l]`: its key and moment; `None` lanes inactive) a surface that stops them lies
    /// on, t in [0, t_max]: bit l of the mask. One Embree packet: the shadow rays of a pixel's
    /// samples are coherent.
    pub fn occluded_packet(
        &self,
        rays: &[Option<(Vec3, Vec3, f32)>; PACKET_SIZE],
        draws: &[(u32, f32); PACKET_SIZE],
    ) -> u32 {
        if rays.iter().all(Option::is_none) {
            return 0;
        }
        let ray = |l: usize| rays[l].unwrap_or((Vec3::ZERO, Vec3::Z, 0.0));
        let mut packet = Ray16::segment(
            std::array::from_fn(|l| ray(l).0.to_array()),
            std::array::from_fn(|l| ray(l).1.to_array()),
            [0.0; PACKET_SIZE],
            std::array::from_fn(|l| ray(l).2),
        );
        packet.id = draws.map(|(key, _)| key);
        packet.time = draws.map(|(_, moment)| moment);
        packet.mask = [MASK_KEYED; PACKET_SIZE];
        let valid = PacketMask::new(|l| rays[l].is_some());
        self.scene
            .occluded16(&mut IntersectContext::coherent(), &mut packet, valid.get());
        (0..PACKET_SIZE)
            .filter(|&l| rays[l].is_some() && packet.tfar[l] == f32::NEG_INFINITY)
            .fold(0, |mask, l| mask | 1 << l)
    }
}

/// One Embree ray at `moment`; its `id` and `mask` carry the draw `key` to the alpha test.
fn ray(
    origin: Vec3,
    direction: Vec3,
    (t_min, t_max): (f32, f32),
    key: Option<u32>,
    moment: f32,
) -> Ray {
    let mut ray = Ray::segment(origin.to_array(), direction.to_array(), t_min, t_max);
    ray.id = key.unwrap_or(0);
    ray.mask = if key.is_some() {
        MASK_KEYED
    } else {
        MASK_FIXED
    };
    ray.time = moment;
    ray
}

/// Every triangle's vertices, the caller's order (a moving one's at the frame's own time), and
/// the moving ones' at each step.
struct TriangleVertices {
    still: Vec<[Vec3A; 3]>,
    steps: Arc<TriangleSteps>,
}

impl TriangleVertices {
    /// `triangle`'s vertices at `moment`: between its steps where it moves.
    fn at(&self, triangle: u32, moment: f32) -> [Vec3A; 3] {
        match self.steps.row(triangle) {
            Some(row) => self.steps.vertices_at(row, moment),
            None => self.still[triangle as usize],
        }
    }
}

/// Whether a ray along `direction` that meets triangle `v` reaches its back face: it sees the
/// triangle's vertices clockwise, d . ((v1 - v0) x (v2 - v0)) > 0 (glTF's front face is the
/// counter-clockwise one). A ray in the triangle's plane (0) meets the front.
pub fn is_back_face(direction: Vec3A, v: &[Vec3A; 3]) -> bool {
    direction.dot((v[1] - v[0]).cross(v[2] - v[0])) > 0.0
}

/// Embree's filter for a geometry of single-sided or alpha-tested triangles: rejects the
/// candidate hits on a back face (`corners` given) and those the alpha test lets through
/// (`alpha` given).
struct SurfaceFilter {
    triangles_of: Arc<Vec<u32>>,
    corners: Option<Arc<TriangleVertices>>,
    alpha: Option<AlphaTest>,
}

impl SurfaceFilter {
    fn run(&self, rays: &RayN<'_>, hits: &HitN<'_>, mut valid: ValidityN<'_>) {
        for lane in 0..valid.len() {
            if valid[lane] == 0 {
                continue;
            }
            let triangle = self.triangles_of[hits.prim_id(lane) as usize];
            if let Some(corners) = &self.corners {
                let direction = Vec3A::from(rays.dir(lane));
                let vertices = corners.at(triangle, rays.time(lane));
                if is_back_face(direction, &vertices) {
                    valid[lane] = 0;
                    continue;
                }
            }
            if let Some(alpha) = &self.alpha {
                let key = (rays.mask(lane) == MASK_KEYED).then(|| rays.id(lane));
                let barycentric = Vec2::new(hits.u(lane), hits.v(lane));
                if !alpha(triangle, barycentric, key) {
                    valid[lane] = 0;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Embree's 16-wide kernels fault on AVX-512 CPUs when the packet or its mask is less
    /// aligned than `packet_alignment(16)`: every type lensray hands to a packet call is checked.
    #[test]
    fn packets_and_masks_are_aligned_as_embree_requires() {
        let required = packet_alignment(PACKET_SIZE);
        assert_eq!(required, 64);
        for (name, align) in [
            ("PacketMask", std::mem::align_of::<PacketMask>()),
            ("Ray16", std::mem::align_of::<Ray16>()),
            ("RayHit16", std::mem::align_of::<RayHit16>()),
        ] {
            assert!(
                align >= required,
                "{name} is aligned to {align} bytes; Embree's {PACKET_SIZE}-wide kernels need {required}"
            );
        }
        // The mask Embree reads is the wrapper's first field: the wrapper's address.
        let masks: Vec<PacketMask> = (0..5).map(|n| PacketMask::new(|l| l < n)).collect();
        for mask in &masks {
            let address = std::ptr::from_ref(mask.get()) as usize;
            assert_eq!(address % required, 0, "mask at {address:#x}");
        }
    }

    /// A triangle in z = 0, counter-clockwise seen from +z, single-sided (behind it, at z = -1,
    /// a double-sided one): a ray from +z stops at it (t = 1), a ray from -z passes through it to
    /// nothing, and the shadow tests and 16-wide packets agree; double-sided, it stops both.
    #[test]
    fn single_sided_triangles_stop_only_rays_that_meet_their_front() {
        let front = [
            Vec3A::new(-1.0, -1.0, 0.0),
            Vec3A::new(1.0, -1.0, 0.0),
            Vec3A::new(0.0, 1.0, 0.0),
        ];
        let behind = front.map(|v| v - Vec3A::Z);
        let (from_front, from_back) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -2.0));
        assert!(!is_back_face(Vec3A::NEG_Z, &front) && is_back_face(Vec3A::Z, &front));
        for single_sided in [true, false] {
            let accel = Accel::build_with_tests(
                &[front, behind],
                &[],
                &[single_sided, false],
                None,
                Arc::default(),
            );
            // Embree's distances are its own floats (instruction sets round differently):
            // within 1e-6 of the exact ones.
            let close = |hit: Option<Hit>, want: Option<(u32, f32)>, what: &str| {
                let got = hit.map(|h| (h.triangle, h.t));
                let same = match (got, want) {
                    (Some((a, t)), Some((b, u))) => a == b && (t - u).abs() <= 1e-6,
                    (a, b) => a.is_none() && b.is_none(),
                };
                assert!(same, "{what}: {got:?} against {want:?}");
            };
            let front_hit = accel.closest_hit(from_front, Vec3::NEG_Z, (0.0, 10.0), None, 0.5);
            close(front_hit, Some((0, 1.0)), "from the front");
            // From -z the ray meets the triangle behind first (t = 1), then this one (t = 2):
            // look from between them, at z = -0.5, towards +z.
            let origin = Vec3::new(0.0, 0.0, -0.5);
            let back_hit = accel.closest_hit(origin, Vec3::Z, (0.0, 10.0), None, 0.5);
            let expected = (!single_sided).then_some((0, 0.5));
            close(back_hit, expected, "from behind");
            assert_eq!(
                accel.occluded(origin, Vec3::Z, (0.0, 10.0), None, 0.5),
                !single_sided,
                "shadow ray from behind"
            );
            let mut rays = [None; PACKET_SIZE];
            rays[0] = Some((origin, Vec3::Z, 10.0));
            rays[3] = Some((from_back, Vec3::Z, 1.5));
            let mask = accel.occluded_packet(&rays, &[(0, 0.5); PACKET_SIZE]);
            // Lane 3 meets the double-sided triangle behind at t = 1.
            assert_eq!(mask, if single_sided { 0b1000 } else { 0b1001 });
        }
    }
}
