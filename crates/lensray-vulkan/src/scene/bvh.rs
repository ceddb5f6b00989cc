//! The software traversal's BVH (shaders/include/hit_software.glsl), built on the host: obvhs's binary
//! BVH (PLOC, reinsertion, SAH leaf collapse), flattened into two storage-buffer arrays:
//! - nodes that hold both children's boxes (Aila and Laine, "Understanding the efficiency of ray
//!   traversal on GPUs", 2009): one 64-byte fetch tests two boxes, and a leaf child is named in
//!   its parent (first triangle, count), so leaves cost no node fetch;
//! - the triangles' vertices in leaf order (48 bytes each), so a leaf reads contiguous memory
//!   and needs no index buffer.
//!
//! Measured choices: see [`BvhParams::default`].

use std::time::{Duration, Instant};

use glam::Vec3A;
use obvhs::{aabb::Aabb, bvh2::builder::build_bvh2_from_tris, triangle::Triangle, BvhBuildParams};

use crate::core::error::GpuError;
use lensray_core::interface::{GpuBvhNode, GpuBvhTriangle, BVH_STACK_SIZE};

/// How the BVH is built (the choices measured for the software traversal).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BvhParams {
    /// Most triangles per leaf (1..=255): larger leaves mean fewer node visits, more triangle
    /// tests.
    pub max_leaf_triangles: u32,
    /// Cost of a node visit against a triangle test in the SAH leaf collapse (x10, integer so
    /// the struct stays `Eq`): higher collapses more.
    pub collapse_cost_x10: u32,
    /// obvhs's medium build (wider PLOC search, more reinsertion) instead of its fast one.
    pub medium_build: bool,
}

impl Default for BvhParams {
    /// Leaves of up to 4 triangles, collapse cost 1.5 (obvhs's default is 3.0), medium build:
    /// the fastest of the measured choices, or tied with the fastest, on a small and a 1M-triangle
    /// scene, at a third less memory than one triangle per leaf (the measurements and their
    /// command: docs/software-traversal.md, "BVH build choices").
    fn default() -> Self {
        Self {
            max_leaf_triangles: 4,
            collapse_cost_x10: 15,
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

/// A child as its parent names it: its box and its link.
#[derive(Clone, Copy)]
struct Child {
    aabb: Aabb,
    link: u32,
    count: u32,
}

impl FlatBvh {
    /// Builds over the triangles `indices` (3 per triangle) of `positions`; the stored index of
    /// a triangle is its position in `indices / 3`.
    pub(crate) fn build(
        positions: &[[f32; 4]],
        indices: &[u32],
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
            let leaf = Child {
                aabb: Aabb {
                    min: Vec3A::ZERO,
                    max: Vec3A::ZERO,
                },
                link: 0,
                count: 1,
            };
            return Ok(Self {
                nodes: vec![node(leaf, leaf)],
                triangles: vec![GpuBvhTriangle::default()],
                build_time: start.elapsed(),
            });
        }
        let mut build = if params.medium_build {
            BvhBuildParams::medium_build()
        } else {
            BvhBuildParams::fast_build()
        };
        build.max_prims_per_leaf = params.max_leaf_triangles.clamp(1, 255);
        build.collapse_traversal_cost = params.collapse_cost_x10.max(1) as f32 / 10.0;
        let bvh = build_bvh2_from_tris(&tris, build, &mut Duration::default());

        let triangles = bvh
            .primitive_indices
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                GpuBvhTriangle {
                    v0: t.v0.extend(i as f32).to_array(),
                    v1: t.v1.extend(0.0).to_array(),
                    v2: t.v2.extend(0.0).to_array(),
                }
            })
            .collect();

        let child = |i: usize| {
            let n = &bvh.nodes[i];
            Child {
                aabb: n.aabb,
                link: n.first_index,
                count: n.prim_count,
            }
        };
        let mut nodes = Vec::with_capacity(bvh.nodes.len() / 2 + 1);
        // Inner nodes on the longest root-to-leaf path: the traversal's stack holds fewer.
        let mut depth = 1;
        let root = &bvh.nodes[0];
        if root.prim_count > 0 {
            // A root that is a leaf: both children name it (tested twice, tiny scenes only).
            nodes.push(node(child(0), child(0)));
        } else {
            // Depth-first, the first child right after its parent; `pending` holds (obvhs node
            // of an inner node, its slot in `nodes`, its depth).
            nodes.push(GpuBvhNode::default());
            let mut pending = vec![(0usize, 0usize, 1u32)];
            while let Some((bvh_index, slot, d)) = pending.pop() {
                depth = depth.max(d);
                let first = bvh.nodes[bvh_index].first_index as usize;
                let mut pair = [child(first), child(first + 1)];
                for (k, c) in pair.iter_mut().enumerate() {
                    if c.count == 0 {
                        let child_slot = nodes.len();
                        nodes.push(GpuBvhNode::default());
                        c.link = child_slot as u32;
                        pending.push((first + k, child_slot, d + 1));
                    }
                }
                nodes[slot] = node(pair[0], pair[1]);
            }
        }
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

fn node(a: Child, b: Child) -> GpuBvhNode {
    let (a0, a1, b0, b1) = (a.aabb.min, a.aabb.max, b.aabb.min, b.aabb.max);
    GpuBvhNode {
        a_xy: [a0.x, a1.x, a0.y, a1.y],
        b_xy: [b0.x, b1.x, b0.y, b1.y],
        ab_z: [a0.z, a1.z, b0.z, b1.z],
        children: [a.link, b.link, a.count, b.count],
    }
}

#[cfg(test)]
mod tests {
    //! A host mirror of the shader's traversal (hit_software.glsl, without its floating-point
    //! details) checks the flattened structure against brute force with the same watertight
    //! triangle test.

    use super::*;
    use glam::Vec3;
    use lensray_core::reference::WatertightRay;
    use lensray_core::scene::generate::uv_sphere;

    fn slab(lo: Vec3, hi: Vec3, o: Vec3, inv: Vec3, t_max: f32) -> Option<f32> {
        let t0 = (lo - o) * inv;
        let t1 = (hi - o) * inv;
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max) * 1.000_000_4;
        (near <= far).then_some(near)
    }

    /// Closest hit: (triangle index, t).
    fn traverse(bvh: &FlatBvh, o: Vec3, d: Vec3) -> Option<(u32, f32)> {
        let ray = WatertightRay::new(o, d);
        let inv = d.recip();
        let mut best: Option<(u32, f32)> = None;
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let n = &bvh.nodes[n as usize];
            let t_max = best.map_or(f32::INFINITY, |b| b.1);
            let boxes = [
                (
                    Vec3::new(n.a_xy[0], n.a_xy[2], n.ab_z[0]),
                    Vec3::new(n.a_xy[1], n.a_xy[3], n.ab_z[1]),
                ),
                (
                    Vec3::new(n.b_xy[0], n.b_xy[2], n.ab_z[2]),
                    Vec3::new(n.b_xy[1], n.b_xy[3], n.ab_z[3]),
                ),
            ];
            for (k, (lo, hi)) in boxes.into_iter().enumerate() {
                if slab(lo, hi, o, inv, t_max).is_none() {
                    continue;
                }
                let (link, count) = (n.children[k], n.children[2 + k]);
                if count == 0 {
                    stack.push(link);
                    continue;
                }
                for slot in link..link + count {
                    let t = &bvh.triangles[slot as usize];
                    let v = [t.v0, t.v1, t.v2].map(|p| Vec3A::from_slice(&p[..3]));
                    let limit = best.map_or(f32::INFINITY, |b| b.1);
                    if let Some((t_hit, _)) = ray.intersect(&v, 0.0, limit) {
                        best = Some((t.v0[3] as u32, t_hit));
                    }
                }
            }
            assert!(stack.len() <= BVH_STACK_SIZE as usize);
        }
        best
    }

    fn flatten(meshes: &[lensray_core::scene::Mesh]) -> (Vec<[f32; 4]>, Vec<u32>) {
        let (mut positions, mut indices) = (Vec::new(), Vec::new());
        for m in meshes {
            let base = positions.len() as u32;
            positions.extend(m.positions.iter().map(|p| p.extend(1.0).to_array()));
            indices.extend(m.triangles.iter().flatten().map(|i| base + i));
        }
        (positions, indices)
    }

    #[test]
    fn finds_the_reference_closest_hits() {
        let meshes = [
            uv_sphere("a", Vec3::new(0.0, 0.0, 0.0), 1.0, 24, 12, 0),
            uv_sphere("b", Vec3::new(1.5, 0.3, -1.0), 0.7, 16, 8, 0),
        ];
        let (positions, indices) = flatten(&meshes);
        let tris: Vec<[Vec3A; 3]> = indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]].map(|i| Vec3A::from_slice(&positions[i as usize][..3])))
            .collect();
        // The closest hit by brute force: the nearest t, the first triangle at it.
        let brute_force = |o: Vec3, d: Vec3| {
            let ray = WatertightRay::new(o, d);
            (0..tris.len() as u32)
                .filter_map(|i| {
                    ray.intersect(&tris[i as usize], 0.0, f32::INFINITY)
                        .map(|h| (i, h.0))
                })
                .fold(None, |best: Option<(u32, f32)>, hit| match best {
                    Some(b) if b.1 <= hit.1 => Some(b),
                    _ => Some(hit),
                })
        };
        for params in [
            BvhParams::default(),
            BvhParams {
                max_leaf_triangles: 1,
                collapse_cost_x10: 30,
                medium_build: false,
            },
        ] {
            let bvh = FlatBvh::build(&positions, &indices, &params).unwrap();
            assert_eq!(bvh.triangles.len(), tris.len());
            let mut hits = 0;
            for i in 0..400 {
                let a = i as f32 * 0.7;
                let o = Vec3::new(4.0 * a.cos(), 0.5 * (a * 1.3).sin(), 4.0 * a.sin());
                let target = Vec3::new(0.5 * (a * 2.1).sin(), 0.4 * (a * 0.7).cos(), -0.3);
                let d = (target - o).normalize();
                let want = brute_force(o, d);
                let got = traverse(&bvh, o, d);
                assert_eq!(got, want, "ray {i} with {params:?}");
                hits += usize::from(got.is_some());
            }
            assert!(hits > 100, "{hits}");
        }
    }

    #[test]
    fn empty_and_single_leaf_scenes() {
        let bvh = FlatBvh::build(&[], &[], &BvhParams::default()).unwrap();
        assert_eq!((bvh.nodes.len(), bvh.triangles.len()), (1, 1));
        assert_eq!(traverse(&bvh, Vec3::new(0.0, 0.0, -1.0), Vec3::Z), None);

        let positions = [
            [0.0, 0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 1.0],
        ];
        let bvh = FlatBvh::build(&positions, &[0, 1, 2], &BvhParams::default()).unwrap();
        assert_eq!(bvh.nodes.len(), 1);
        let hit = traverse(&bvh, Vec3::new(0.2, 0.2, -1.0), Vec3::Z).expect("hit");
        assert_eq!(hit, (0, 1.0));
    }
}
