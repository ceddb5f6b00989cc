//! Packet traversal: the samples of one pixel go down the BVH together. Each node's child boxes
//! are tested against all rays of the packet with vectorised code (structure of arrays, active
//! lane masks); the triangle test runs lane by lane with the single-ray test's exact arithmetic,
//! so every ray gets bit-identically the hit it would get alone.

use glam::{Vec2, Vec3, Vec3A, Vec4};
use obvhs::cwbvh::node::CwBvhNode;

use super::{bvh_ray, Accel, Hit};
use crate::reference::triangle::WatertightRay;

/// Rays traced together by [`Accel::closest_hits`]: the samples of one pixel.
pub const PACKET_SIZE: usize = 16;

/// Per-lane arrays of a ray packet (structure of arrays, so node tests vectorize across rays).
struct Packet {
    origin: [[f32; PACKET_SIZE]; 3],
    /// The watertight test's shear and scale per lane (`WatertightRay::shear`).
    shear: [[f32; PACKET_SIZE]; 3],
    inv_direction: [[f32; PACKET_SIZE]; 3],
    t_max: [f32; PACKET_SIZE],
}

/// Lanes of `mask`, lowest first.
#[inline(always)]
fn lanes(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            lane
        })
    })
}

/// The lanes of `active` whose ray passes through child `child` of `node`: obvhs's slab test
/// (`CwBvhNode::intersect_ray`, same arithmetic, same `EPSILON` near limit) for every lane at once.
#[inline(always)]
fn child_hits(
    node: &CwBvhNode,
    child: usize,
    adj_inv: &[[f32; PACKET_SIZE]; 3],
    adj_origin: &[[f32; PACKET_SIZE]; 3],
    t_max: &[f32; PACKET_SIZE],
) -> u32 {
    let lo = [
        node.child_min_x[child] as f32,
        node.child_min_y[child] as f32,
        node.child_min_z[child] as f32,
    ];
    let hi = [
        node.child_max_x[child] as f32,
        node.child_max_y[child] as f32,
        node.child_max_z[child] as f32,
    ];
    let mut near = [BOX_EPSILON; PACKET_SIZE];
    let mut far = *t_max;
    for axis in 0..3 {
        for l in 0..PACKET_SIZE {
            let a = lo[axis] * adj_inv[axis][l] + adj_origin[axis][l];
            let b = hi[axis] * adj_inv[axis][l] + adj_origin[axis][l];
            // Plain compare-and-select (no NaN can occur: the inverse direction is finite), which
            // compiles to single min/max instructions unlike f32::min/max.
            let (entry, exit) = if a < b { (a, b) } else { (b, a) };
            near[l] = if entry > near[l] { entry } else { near[l] };
            far[l] = if exit < far[l] { exit } else { far[l] };
        }
    }
    // glam's comparison mask is a movemask; a bit-by-bit loop here does not vectorize.
    let mut mask = 0u32;
    for q in 0..PACKET_SIZE / 4 {
        let near = Vec4::from_slice(&near[4 * q..]);
        let far = Vec4::from_slice(&far[4 * q..]);
        mask |= near.cmple(far).bitmask() << (4 * q);
    }
    mask
}

/// Leaves reached by at most this many of a packet's rays are tested ray by ray.
const SCALAR_LEAF_LANES: u32 = 2;

/// obvhs's near limit of the node test (`cwbvh::node::EPSILON`).
const BOX_EPSILON: f32 = 0.0001;

impl Accel {
    /// The closest hit of each of up to [`PACKET_SIZE`] rays, t in (t_min, t_max): the same hits
    /// (triangle, t, barycentrics) as [`Accel::closest_hit`] ray by ray, found by traversing the
    /// BVH once for all of them, which pays off when they are coherent (the samples of a pixel).
    pub fn closest_hits(
        &self,
        origins: &[Vec3],
        directions: &[Vec3],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit>],
    ) {
        self.closest_hits_where(origins, directions, t_min, t_max, hits, &|_, _, _| true);
    }

    /// [`Accel::closest_hits`] among the hits `stops(lane, slot, barycentric)` accepts.
    pub fn closest_hits_where(
        &self,
        origins: &[Vec3],
        directions: &[Vec3],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit>],
        stops: &impl Fn(usize, u32, Vec2) -> bool,
    ) {
        let n = origins.len();
        assert!(n <= PACKET_SIZE && directions.len() == n && hits.len() == n);
        let mut packet = Packet {
            origin: [[0.0; PACKET_SIZE]; 3],
            shear: [[0.0; PACKET_SIZE]; 3],
            inv_direction: [[1.0; PACKET_SIZE]; 3],
            t_max: [f32::NEG_INFINITY; PACKET_SIZE],
        };
        let mut watertight = [WatertightRay::new(Vec3::ZERO, Vec3::Z); PACKET_SIZE];
        for l in 0..n {
            let ray = bvh_ray(origins[l], directions[l], t_min, t_max);
            for axis in 0..3 {
                packet.origin[axis][l] = ray.origin[axis];
                packet.inv_direction[axis][l] = ray.inv_direction[axis];
            }
            packet.t_max[l] = t_max;
            watertight[l] = WatertightRay::new(origins[l], directions[l]);
            let shear = watertight[l].shear();
            for axis in 0..3 {
                packet.shear[axis][l] = shear[axis];
            }
        }
        let mut best = [None; PACKET_SIZE];
        // The triangle test's axis permutation is fixed per traversal: one traversal per
        // permutation present (nearly always one for the samples of a pixel).
        let mut remaining = if n == 0 { 0 } else { u32::MAX >> (32 - n) };
        while remaining != 0 {
            let axes = watertight[remaining.trailing_zeros() as usize].axes();
            let group = lanes(remaining)
                .filter(|&l| watertight[l].axes() == axes)
                .fold(0, |m, l| m | 1 << l);
            remaining &= !group;
            crate::with_axes!(axes, |KX, KY, KZ| self.packet_traverse::<KX, KY, KZ>(
                &mut packet,
                &watertight,
                group,
                t_min,
                &mut best,
                stops
            ));
        }
        for (hit, best) in hits.iter_mut().zip(best) {
            *hit = best.map(|(slot, t, barycentric)| Hit {
                t,
                slot,
                triangle: self.bvh.primitive_indices[slot as usize],
                barycentric,
            });
        }
    }

    /// Depth-first traversal of the lanes in `active` (which share the permutation KX, KY, KZ),
    /// children in the order obvhs visits them for the first lane's octant, each child with the
    /// lanes whose rays pass through its box.
    #[inline(always)]
    fn packet_traverse<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        packet: &mut Packet,
        watertight: &[WatertightRay; PACKET_SIZE],
        active: u32,
        t_min: f32,
        best: &mut [Option<(u32, f32, Vec2)>; PACKET_SIZE],
        stops: &impl Fn(usize, u32, Vec2) -> bool,
    ) {
        if self.bvh.nodes.is_empty() {
            return;
        }
        let first = active.trailing_zeros() as usize;
        let octant = ((packet.inv_direction[0][first] < 0.0) as usize) << 2
            | ((packet.inv_direction[1][first] < 0.0) as usize) << 1
            | (packet.inv_direction[2][first] < 0.0) as usize;
        // obvhs bounds the depth at 32 levels; each level pushes at most 7 children.
        let mut stack = [(0u32, 0u32); 256];
        let mut scratch = TriangleLanes::default();
        stack[0] = (0, active);
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let (index, mask) = stack[depth];
            let node = &self.bvh.nodes[index as usize];
            let extent = node.compute_extent();
            let p = Vec3A::from(node.p);
            let mut adj_inv = [[0.0; PACKET_SIZE]; 3];
            let mut adj_origin = [[0.0; PACKET_SIZE]; 3];
            for axis in 0..3 {
                for l in 0..PACKET_SIZE {
                    let inv = packet.inv_direction[axis][l];
                    adj_inv[axis][l] = extent[axis] * inv;
                    adj_origin[axis][l] = (p[axis] - packet.origin[axis][l]) * inv;
                }
            }
            let mut child_masks = [0u32; 8];
            for (child, m) in child_masks.iter_mut().enumerate() {
                if node.child_meta[child] != 0 {
                    *m = mask & child_hits(node, child, &adj_inv, &adj_origin, &packet.t_max);
                }
            }
            // Leaves first, as obvhs does, so their hits shorten the rays before going deeper.
            for k in 0..8 {
                let child = k ^ octant;
                let m = child_masks[child];
                if m == 0 || !node.is_leaf(child) {
                    continue;
                }
                let (start, count) = node.child_primitives(child);
                if m.count_ones() <= SCALAR_LEAF_LANES {
                    // Few rays reach this leaf: the scalar test per ray is cheaper than the
                    // packet test (the same arithmetic, so the same hits).
                    for slot in start..start + count {
                        let v = &self.vertices[slot as usize];
                        for l in lanes(m) {
                            if let Some((t, b)) = watertight[l].intersect_axes::<KX, KY, KZ>(
                                v,
                                t_min,
                                packet.t_max[l],
                            ) {
                                if stops(l, slot, b) {
                                    packet.t_max[l] = t;
                                    best[l] = Some((slot, t, b));
                                }
                            }
                        }
                    }
                    continue;
                }
                for slot in start..start + count {
                    let v = &self.vertices[slot as usize];
                    let (hits, edge) = triangle_lanes::<KX, KY, KZ>(packet, v, t_min, &mut scratch);
                    for l in lanes(hits & m) {
                        let inv_det = 1.0 / scratch.det[l];
                        let t = scratch.t_scaled[l] * inv_det;
                        let b = Vec2::new(scratch.v[l] * inv_det, scratch.w[l] * inv_det);
                        if stops(l, slot, b) {
                            packet.t_max[l] = t;
                            best[l] = Some((slot, t, b));
                        }
                    }
                    // Lanes on an edge in single precision: the scalar test's double-precision path.
                    for l in lanes(edge & m) {
                        if let Some((t, b)) =
                            watertight[l].intersect_axes::<KX, KY, KZ>(v, t_min, packet.t_max[l])
                        {
                            if stops(l, slot, b) {
                                packet.t_max[l] = t;
                                best[l] = Some((slot, t, b));
                            }
                        }
                    }
                }
            }
            // Inner children pushed far to near, so the nearest is visited next.
            for k in (0..8).rev() {
                let child = k ^ octant;
                let m = child_masks[child];
                if m != 0 && !node.is_leaf(child) {
                    stack[depth] = (node.child_node_index(child), m);
                    depth += 1;
                }
            }
        }
    }
}

/// Per-lane intermediate values of [`triangle_lanes`], for the lanes that hit.
#[derive(Default)]
struct TriangleLanes {
    v: [f32; PACKET_SIZE],
    w: [f32; PACKET_SIZE],
    det: [f32; PACKET_SIZE],
    t_scaled: [f32; PACKET_SIZE],
}

/// [`WatertightRay::intersect_axes`] for every lane at once, operation for operation (so results
/// are bit-identical): returns the lanes that hit with t in (t_min, t_max[lane]) and the lanes
/// whose single-precision edge functions hit zero, which the caller redoes with the scalar test
/// (its double-precision path). For hit lanes, `out` holds what the final division needs.
#[inline(always)]
fn triangle_lanes<const KX: usize, const KY: usize, const KZ: usize>(
    packet: &Packet,
    vertices: &[Vec3A; 3],
    t_min: f32,
    out: &mut TriangleLanes,
) -> (u32, u32) {
    let (v0, v1, v2) = (vertices[0], vertices[1], vertices[2]);
    let mut hit = [0.0f32; PACKET_SIZE];
    let mut edge = [0.0f32; PACKET_SIZE];
    for l in 0..PACKET_SIZE {
        let o = [
            packet.origin[0][l],
            packet.origin[1][l],
            packet.origin[2][l],
        ];
        let (sx, sy, sz) = (packet.shear[0][l], packet.shear[1][l], packet.shear[2][l]);
        let (a_x, a_y, a_z) = (v0[KX] - o[KX], v0[KY] - o[KY], v0[KZ] - o[KZ]);
        let (b_x, b_y, b_z) = (v1[KX] - o[KX], v1[KY] - o[KY], v1[KZ] - o[KZ]);
        let (c_x, c_y, c_z) = (v2[KX] - o[KX], v2[KY] - o[KY], v2[KZ] - o[KZ]);
        let ax = a_x - sx * a_z;
        let ay = a_y - sy * a_z;
        let bx = b_x - sx * b_z;
        let by = b_y - sy * b_z;
        let cx = c_x - sx * c_z;
        let cy = c_y - sy * c_z;
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let on_edge = u == 0.0 || v == 0.0 || w == 0.0;
        let outside = (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0);
        let det = u + v + w;
        let t_scaled = u * (sz * a_z) + v * (sz * b_z) + w * (sz * c_z);
        let (t_abs, det_abs) = if det < 0.0 {
            (-t_scaled, -det)
        } else {
            (t_scaled, det)
        };
        let in_range = t_abs > t_min * det_abs && t_abs < packet.t_max[l] * det_abs;
        let ok = !on_edge && !outside && det != 0.0 && in_range;
        hit[l] = if ok { 1.0 } else { 0.0 };
        edge[l] = if on_edge { 1.0 } else { 0.0 };
        out.v[l] = v;
        out.w[l] = w;
        out.det[l] = det;
        out.t_scaled[l] = t_scaled;
    }
    (lane_mask(&hit), lane_mask(&edge))
}

/// The lanes whose value is non-zero, as a bit mask (glam's movemask: a bit-by-bit loop does not
/// vectorize).
#[inline(always)]
fn lane_mask(values: &[f32; PACKET_SIZE]) -> u32 {
    let mut mask = 0u32;
    for q in 0..PACKET_SIZE / 4 {
        mask |= Vec4::from_slice(&values[4 * q..])
            .cmpne(Vec4::ZERO)
            .bitmask()
            << (4 * q);
    }
    mask
}
