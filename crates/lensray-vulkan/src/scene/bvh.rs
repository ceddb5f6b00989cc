//! The software traversal's BVH (shaders/include/hit_software.glsl), built on the host: obvhs's
//! binary BVH (PLOC, reinsertion) collapsed into an 8-wide one by the SAH-optimal conversion of
//! Ylitie, Karras and Laine ("Efficient incoherent ray traversal on GPUs through compressed wide
//! BVHs", 2017), in two storage-buffer arrays:
//! - 80-byte nodes that hold up to eight children's boxes quantized to 8 bits each
//!   ([`GpuBvhNode`]): one fetch tests eight boxes, and a leaf child (1 to 3 triangles) is named
//!   in its parent, so leaves cost no node fetch. A camera ray of the dense and terrain scenes
//!   fetches 1.9x - 2.3x fewer nodes than with two children's boxes a node (`fetches.rs`);
//! - the triangles' vertices in leaf order (48 bytes each), so a leaf reads contiguous memory
//!   and needs no index buffer.
//!
//! The quantized boxes are recomputed here ([`quantize`]) so that every plane `origin + cell * q`
//! (exact: cells are powers of two, checked in f64) lies outside its child: the quantized boxes
//! never cut into a child. The shader meets the planes at `q * cell_t + origin_t` (the ray in the
//! node's grid), with rounding errors of the size the slab test's far-end margin covers.
//!
//! Triangles that move while the shutter is open are built over the box each sweeps (its
//! vertices at every step: `upload::motion`), flagged for the traversal, which meets them
//! where they are at the ray's moment.
//!
//! Measured choices: see [`BvhParams::default`].

#[cfg(test)]
mod fetches;
mod quantize;
#[cfg(test)]
mod tests;

use std::time::{Duration, Instant};

use glam::Vec3A;
use obvhs::{
    aabb::Aabb,
    cwbvh::builder::{build_cwbvh, build_cwbvh_from_tris},
    triangle::Triangle,
    BvhBuildParams,
};

use crate::core::error::GpuError;
use crate::upload::motion::swept_box;
use lensray_core::interface::{GpuBvhNode, GpuBvhTriangle, BVH_STACK_SIZE};

/// How the BVH is built (the choices measured for the software traversal).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BvhParams {
    /// Most triangles per leaf (1..=3, the wide node's unary count): larger leaves mean fewer
    /// node visits, more triangle tests.
    pub max_leaf_triangles: u32,
    /// obvhs's medium build (wider PLOC search, more reinsertion) instead of its fast one.
    pub medium_build: bool,
}

impl Default for BvhParams {
    /// Leaves of up to 3 triangles, medium build: within noise of the other measured choices on
    /// the dense scene, in the least memory (the measurements and their command:
    /// docs/software-traversal.md, "BVH build choices").
    fn default() -> Self {
        Self {
            max_leaf_triangles: 3,
            medium_build: true,
        }
    }
}

/// The flattened BVH, ready to upload.
#[derive(Clone, Debug)]
pub(crate) struct FlatBvh {
    /// Node 0 is the root.
    pub nodes: Vec<GpuBvhNode>,
    pub triangles: Vec<GpuBvhTriangle>,
    pub build_time: Duration,
}

impl FlatBvh {
    /// Builds over the triangles `indices` (3 per triangle) of `positions`, those whose
    /// vertices move over the box they sweep through `motion_vertices`; the stored index of a
    /// triangle is its position in `indices / 3`.
    pub(crate) fn build(
        positions: &[[f32; 4]],
        indices: &[u32],
        motion_vertices: &[[f32; 4]],
        params: &BvhParams,
    ) -> Result<Self, GpuError> {
        let start = Instant::now();
        let vertex = |i: u32| Vec3A::from_slice(&positions[i as usize][..3]);
        let tris: Vec<Triangle> = indices
            .chunks_exact(3)
            .map(|t| Triangle {
                v0: vertex(t[0]),
                v1: vertex(t[1]),
                v2: vertex(t[2]),
            })
            .collect();
        if tris.is_empty() {
            // One leaf of a degenerate triangle, which no ray hits: the shader needs no special
            // case for an empty scene.
            let triangles = vec![GpuBvhTriangle::default()];
            let nodes = quantize::single_leaf(&triangle_box(&triangles[0]));
            return Ok(Self {
                nodes,
                triangles,
                build_time: start.elapsed(),
            });
        }
        let mut build = if params.medium_build {
            BvhBuildParams::medium_build()
        } else {
            BvhBuildParams::fast_build()
        };
        build.max_prims_per_leaf = params.max_leaf_triangles.clamp(1, 3);
        let swept: Vec<Option<Aabb>> = match motion_vertices.len() > 1 {
            true => (0..tris.len())
                .map(|t| swept_box(positions, indices, motion_vertices, t))
                .collect(),
            false => Vec::new(),
        };
        let bvh = if swept.iter().any(Option::is_some) {
            let boxes: Vec<Aabb> = (tris.iter().zip(&swept))
                .map(|(t, s)| s.unwrap_or_else(|| t.aabb()))
                .collect();
            build_cwbvh(&boxes, build, &mut Duration::default())
        } else {
            build_cwbvh_from_tris(&tris, build, &mut Duration::default())
        };
        let moves = |i: u32| swept.get(i as usize).is_some_and(Option::is_some);
        let triangles: Vec<GpuBvhTriangle> = bvh
            .primitive_indices
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                GpuBvhTriangle {
                    v0: t.v0.extend(i as f32).to_array(),
                    v1: t.v1.extend(if moves(i) { 1.0 } else { 0.0 }).to_array(),
                    v2: t.v2.extend(0.0).to_array(),
                }
            })
            .collect();
        // Each leaf slot's box: a moving triangle's sweep.
        let leaf_boxes: Vec<Aabb> = (bvh.primitive_indices.iter().zip(&triangles))
            .map(|(&i, t)| match swept.get(i as usize) {
                Some(Some(swept)) => *swept,
                _ => triangle_box(t),
            })
            .collect();
        let nodes = if bvh.nodes.is_empty() {
            quantize::single_leaf(&leaf_boxes[0])
        } else {
            quantize::nodes(&bvh.nodes, &leaf_boxes)
        };
        let depth = depth(&nodes);
        if depth > BVH_STACK_SIZE {
            return Err(GpuError::Invalid(format!(
                "the software traversal's BVH is {depth} levels deep, more than its stack of \
                 {BVH_STACK_SIZE} entries"
            )));
        }
        Ok(Self {
            nodes,
            triangles,
            build_time: start.elapsed(),
        })
    }

    /// Bytes of both arrays on the device.
    pub(crate) fn bytes(&self) -> u64 {
        (std::mem::size_of_val(self.nodes.as_slice())
            + std::mem::size_of_val(self.triangles.as_slice())) as u64
    }
}

/// Node levels on the longest root-to-leaf path: children follow their parents in the array,
/// so one pass in order sets every node's level from its parent's.
fn depth(nodes: &[GpuBvhNode]) -> u32 {
    let mut level = vec![0u32; nodes.len()];
    level[0] = 1;
    for (i, n) in nodes.iter().enumerate() {
        for child in quantize::child_nodes(n) {
            level[child as usize] = level[i] + 1;
        }
    }
    level.into_iter().max().unwrap_or(1)
}

/// The box of triangle `t` (exact: the min and max of its vertices).
fn triangle_box(t: &GpuBvhTriangle) -> Aabb {
    let v = [t.v0, t.v1, t.v2].map(|p| Vec3A::from_slice(&p[..3]));
    Aabb {
        min: v[0].min(v[1]).min(v[2]),
        max: v[0].max(v[1]).max(v[2]),
    }
}
