//! The acceleration structure of the CPU reference: obvhs's compressed 8-wide BVH (PLOC build
//! with reinsertion, SAH collapse, SIMD traversal), with the watertight triangle test at the leaves.
//! Triangle data is stored in BVH leaf order so a leaf visit reads memory sequentially.

use std::time::{Duration, Instant};

use glam::{Vec2, Vec3, Vec3A};
use obvhs::{
    cwbvh::{builder::build_cwbvh_from_tris, CwBvh},
    ray::{Ray as BvhRay, RayHit},
    triangle::Triangle,
    BvhBuildParams,
};

use super::triangle::WatertightRay;

/// Above this many triangles the build trades a little traversal speed for build time.
const LARGE_SCENE_TRIANGLES: usize = 250_000;

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
            BvhBuildParams::fast_build()
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
        let watertight = WatertightRay::new(origin, direction);
        let ray = BvhRay::new(origin.into(), direction.into(), t_min, t_max);
        let mut hit = RayHit::none();
        let found = self.bvh.ray_traverse(ray, &mut hit, |r, slot| {
            watertight
                .intersect(&self.vertices[slot], r.tmin, r.tmax)
                .map_or(f32::INFINITY, |(t, _)| t)
        });
        if !found {
            return None;
        }
        let slot = hit.primitive_id;
        // The traversal keeps only t; the barycentrics of the winner are recomputed once.
        let (t, barycentric) = watertight
            .intersect(&self.vertices[slot as usize], t_min, t_max)
            .expect("the closest hit intersects again");
        Some(Hit {
            t,
            slot,
            triangle: self.bvh.primitive_indices[slot as usize],
            barycentric,
        })
    }

    /// Whether anything lies on the ray with t in (t_min, t_max): the shadow test.
    pub fn occluded(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> bool {
        let watertight = WatertightRay::new(origin, direction);
        let ray = BvhRay::new(origin.into(), direction.into(), t_min, t_max);
        !self.bvh.ray_traverse_miss(ray, |r, slot| {
            watertight
                .intersect(&self.vertices[slot], r.tmin, r.tmax)
                .map_or(f32::INFINITY, |(t, _)| t)
        })
    }
}
