//! The acceleration structure of the CPU reference: obvhs's compressed 8-wide BVH (PLOC build
//! with reinsertion, SAH collapse, SIMD traversal), with the watertight triangle test at the leaves.
//! Triangle data is stored in BVH leaf order so a leaf visit reads memory sequentially.

use std::time::{Duration, Instant};

use glam::{UVec2, Vec2, Vec3, Vec3A};
use obvhs::{
    cwbvh::{builder::build_cwbvh_from_tris, CwBvh},
    ray::Ray as BvhRay,
    triangle::Triangle,
    BvhBuildParams,
};

use super::triangle::WatertightRay;

mod packet;
pub use packet::PACKET_SIZE;

/// Above this many triangles the build trades a little traversal speed for build time.
const LARGE_SCENE_TRIANGLES: usize = 250_000;

/// Collapse traversal cost for those large scenes (fast_build's; other costs were no faster).
const LARGE_SCENE_COLLAPSE_TRAVERSAL_COST: f32 = 3.0;

/// obvhs's ray with its inverse direction from one vector division (`Ray::new` does three scalar
/// ones); zero components become huge finite values, as obvhs's `safe_inverse` makes them, with
/// the sign obvhs's node test assumes (it orders slabs by `direction < 0`, so -0 must give a
/// positive inverse, or every box is missed).
#[inline(always)]
fn bvh_ray(origin: Vec3, direction: Vec3, tmin: f32, tmax: f32) -> BvhRay {
    let direction = Vec3A::from(direction);
    let tiny = Vec3A::splat(f32::EPSILON);
    let signed_tiny = Vec3A::select(direction.cmplt(Vec3A::ZERO), -tiny, tiny);
    let safe = Vec3A::select(direction.abs().cmple(tiny), signed_tiny, direction);
    BvhRay {
        origin: origin.into(),
        direction,
        inv_direction: safe.recip(),
        tmin,
        tmax,
    }
}

/// A closest hit: `slot` indexes the leaf-ordered triangle arrays, `triangle` the caller's order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub slot: u32,
    pub triangle: u32,
    /// Weights of v1 and v2 (v0's is 1 - x - y), as Vulkan ray queries report them.
    pub barycentric: Vec2,
}

pub struct Accel {
    bvh: CwBvh,
    /// Vertices per slot (leaf order).
    vertices: Vec<[Vec3A; 3]>,
    pub build_time: Duration,
}

impl Accel {
    /// Builds over triangles given in the caller's order; `slot_to_triangle` maps back.
    pub fn build(triangles: &[[Vec3A; 3]]) -> Self {
        let start = Instant::now();
        let tris: Vec<Triangle> = triangles
            .iter()
            .map(|t| Triangle {
                v0: t[0],
                v1: t[1],
                v2: t[2],
            })
            .collect();
        let params = if triangles.len() > LARGE_SCENE_TRIANGLES {
            BvhBuildParams {
                collapse_traversal_cost: LARGE_SCENE_COLLAPSE_TRAVERSAL_COST,
                ..BvhBuildParams::fast_build()
            }
        } else {
            BvhBuildParams::medium_build()
        };
        let bvh = build_cwbvh_from_tris(&tris, params, &mut Duration::default());
        let vertices = bvh
            .primitive_indices
            .iter()
            .map(|&i| triangles[i as usize])
            .collect();
        Self {
            bvh,
            vertices,
            build_time: start.elapsed(),
        }
    }

    /// Bytes of the BVH and of its leaf-ordered triangles.
    pub fn bytes(&self) -> u64 {
        (std::mem::size_of_val(self.bvh.nodes.as_slice())
            + std::mem::size_of_val(self.bvh.primitive_indices.as_slice())
            + std::mem::size_of_val(self.vertices.as_slice())) as u64
    }

    /// The caller's triangle index of each slot.
    pub fn slot_to_triangle(&self) -> &[u32] {
        &self.bvh.primitive_indices
    }

    pub fn vertices(&self, slot: u32) -> &[Vec3A; 3] {
        &self.vertices[slot as usize]
    }

    /// Closest hit with t in (t_min, t_max).
    pub fn closest_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        self.closest_hit_where(origin, direction, t_min, t_max, &|_, _| true)
    }

    /// Closest hit with t in (t_min, t_max) among those `stops(slot, barycentric)` accepts (the
    /// alpha test: rays pass through where a mask has no surface).
    pub fn closest_hit_where(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
        stops: &impl Fn(u32, Vec2) -> bool,
    ) -> Option<Hit> {
        let watertight = WatertightRay::new(origin, direction);
        let ray = bvh_ray(origin, direction, t_min, t_max);
        // One traversal per axis permutation, so the leaf test has no run-time indexing.
        let (slot, t, barycentric) = crate::with_axes!(watertight.axes(), |KX, KY, KZ| self
            .closest_hit_axes::<KX, KY, KZ>(&watertight, ray, stops))?;
        Some(Hit {
            t,
            slot,
            triangle: self.bvh.primitive_indices[slot as usize],
            barycentric,
        })
    }

    /// obvhs's traversal macro with the triangle test inlined at the leaves (the closure-based
    /// `ray_traverse` does not inline it).
    #[inline(always)]
    fn closest_hit_axes<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        watertight: &WatertightRay,
        mut ray: BvhRay,
        stops: &impl Fn(u32, Vec2) -> bool,
    ) -> Option<(u32, f32, Vec2)> {
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        let mut best = None;
        obvhs::traverse!(
            self.bvh,
            node,
            state,
            node.intersect_ray(&ray, state.oct_inv4),
            {
                let slot = state.primitive_id;
                if let Some((t, b)) = watertight.intersect_axes::<KX, KY, KZ>(
                    &self.vertices[slot as usize],
                    ray.tmin,
                    ray.tmax,
                ) {
                    if stops(slot, b) {
                        ray.tmax = t;
                        best = Some((slot, t, b));
                    }
                }
            }
        );
        best
    }

    /// Whether anything lies on the ray with t in (t_min, t_max): the shadow test.
    pub fn occluded(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> bool {
        self.occluded_where(origin, direction, t_min, t_max, &|_, _| true)
    }

    /// Whether a hit that `stops(slot, barycentric)` accepts lies on the ray with t in
    /// (t_min, t_max).
    pub fn occluded_where(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
        stops: &impl Fn(u32, Vec2) -> bool,
    ) -> bool {
        let watertight = WatertightRay::new(origin, direction);
        let ray = bvh_ray(origin, direction, t_min, t_max);
        crate::with_axes!(watertight.axes(), |KX, KY, KZ| self
            .occluded_axes::<KX, KY, KZ>(&watertight, ray, stops))
    }

    #[inline(always)]
    fn occluded_axes<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        watertight: &WatertightRay,
        ray: BvhRay,
        stops: &impl Fn(u32, Vec2) -> bool,
    ) -> bool {
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        let mut occluded = false;
        'search: {
            obvhs::traverse!(
                self.bvh,
                node,
                state,
                node.intersect_ray(&ray, state.oct_inv4),
                {
                    let slot = state.primitive_id;
                    if let Some((_, b)) = watertight.intersect_axes::<KX, KY, KZ>(
                        &self.vertices[slot as usize],
                        ray.tmin,
                        ray.tmax,
                    ) {
                        if stops(slot, b) {
                            occluded = true;
                            break 'search;
                        }
                    }
                }
            );
        }
        occluded
    }
}
