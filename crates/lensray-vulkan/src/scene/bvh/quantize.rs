//! The wide BVH's nodes in the shader's layout ([`GpuBvhNode`]), with each child's box
//! quantized so that the planes the shader decodes enclose the child.

use glam::Vec3A;
use obvhs::{aabb::Aabb, cwbvh::node::CwBvhNode};

use lensray_core::interface::GpuBvhNode;

/// Grid steps per axis: the coordinates are bytes.
const STEPS: f32 = 255.0;

/// What a child slot holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Link {
    /// Another node, by index.
    Node(u32),
    /// `count` triangles from slot `first` of the triangle array.
    Leaf { first: u32, count: u32 },
}

/// A child as the shader decodes it: its box and what it holds.
#[derive(Clone, Copy, Debug)]
pub(super) struct Child {
    #[cfg_attr(
        not(test),
        expect(dead_code, reason = "the tests check the decoded boxes")
    )]
    pub lo: Vec3A,
    #[cfg_attr(
        not(test),
        expect(dead_code, reason = "the tests check the decoded boxes")
    )]
    pub hi: Vec3A,
    pub link: Link,
}

/// The shader's nodes for obvhs's `cw` (same tree, same child slots, same triangle order),
/// `leaf_boxes` the box of each triangle in its leaf order.
pub(super) fn nodes(cw: &[CwBvhNode], leaf_boxes: &[Aabb]) -> Vec<GpuBvhNode> {
    // Exact boxes, children before parents: a child node's index exceeds its parent's.
    let mut boxes = vec![Aabb::empty(); cw.len()];
    for k in (0..cw.len()).rev() {
        let node_box = child_boxes(&cw[k], &boxes, leaf_boxes)
            .iter()
            .flatten()
            .fold(Aabb::empty(), |acc, b| acc.union(b));
        boxes[k] = node_box;
    }
    cw.iter()
        .map(|n| {
            let children = child_boxes(n, &boxes, leaf_boxes);
            encode(
                &children,
                n.imask,
                n.child_meta,
                [n.child_base_idx, n.primitive_base_idx],
            )
        })
        .collect()
}

/// One node with one leaf child: triangle slot 0, of box `leaf_box` (scenes of no triangle or
/// one).
pub(super) fn single_leaf(leaf_box: &Aabb) -> Vec<GpuBvhNode> {
    let mut children = [None; 8];
    children[0] = Some(*leaf_box);
    let mut meta = [0u8; 8];
    meta[0] = 0b0010_0000;
    vec![encode(&children, 0, meta, [0, 0])]
}

/// The exact box of each occupied child slot of `n`.
fn child_boxes(n: &CwBvhNode, boxes: &[Aabb], leaf_boxes: &[Aabb]) -> [Option<Aabb>; 8] {
    std::array::from_fn(|i| {
        if n.is_child_empty(i) {
            None
        } else if !n.is_leaf(i) {
            Some(boxes[n.child_node_index(i) as usize])
        } else {
            let (first, count) = n.child_primitives(i);
            Some(
                leaf_boxes[first as usize..(first + count) as usize]
                    .iter()
                    .fold(Aabb::empty(), |acc, b| acc.union(b)),
            )
        }
    })
}

/// The plane `origin + cell * q`, exactly (f64 holds the sum of an f32 and a power of two times a
/// byte): the shader meets it at `q * cell_t + origin_t`, the ray in the node's grid.
fn plane(origin: f32, cell: f32, q: u8) -> f64 {
    f64::from(origin) + f64::from(cell) * f64::from(q)
}

/// The smallest power-of-two cell (as its biased exponent) whose 255 steps from `origin` reach
/// `max` once rounded.
fn cell_exponent(origin: f32, max: f32) -> u8 {
    let extent = (max - origin).max(1e-30);
    let mut exponent = ((extent / STEPS).log2().ceil() as i32 + 127).clamp(1, 254) as u32;
    while exponent < 254 && plane(origin, f32::from_bits(exponent << 23), 255) < f64::from(max) {
        exponent += 1;
    }
    exponent as u8
}

/// Grid coordinates of `[lo, hi]` on one axis: the largest lower plane at or below `lo` and the
/// smallest upper plane at or above `hi`.
fn quantize_axis(origin: f32, cell: f32, lo: f32, hi: f32) -> (u8, u8) {
    let mut q_lo = ((lo - origin) / cell).floor().clamp(0.0, STEPS) as u8;
    let (lo, hi) = (f64::from(lo), f64::from(hi));
    while q_lo > 0 && plane(origin, cell, q_lo) > lo {
        q_lo -= 1;
    }
    let mut q_hi = ((hi - f64::from(origin)) / f64::from(cell))
        .ceil()
        .clamp(0.0, 255.0) as u8;
    while q_hi < 255 && plane(origin, cell, q_hi) < hi {
        q_hi += 1;
    }
    assert!(
        plane(origin, cell, q_lo) <= lo && plane(origin, cell, q_hi) >= hi,
        "a quantized box misses its child: [{lo}, {hi}] from {origin} in cells of {cell}"
    );
    (q_lo, q_hi)
}

/// A node of `children`'s boxes (slots as given), `imask` and `meta` as obvhs names them, and
/// `[first child node, first triangle slot]`.
fn encode(children: &[Option<Aabb>; 8], imask: u8, meta: [u8; 8], bases: [u32; 2]) -> GpuBvhNode {
    let node_box = children
        .iter()
        .flatten()
        .fold(Aabb::empty(), |acc, b| acc.union(b));
    let origin = node_box.min;
    let exponents: [u8; 3] = std::array::from_fn(|a| cell_exponent(origin[a], node_box.max[a]));
    let mut lo = [[0u8; 8]; 3];
    let mut hi = [[0u8; 8]; 3];
    for (i, child) in children.iter().enumerate() {
        let Some(b) = child else { continue };
        for a in 0..3 {
            let cell = f32::from_bits(u32::from(exponents[a]) << 23);
            (lo[a][i], hi[a][i]) = quantize_axis(origin[a], cell, b.min[a], b.max[a]);
        }
    }
    let word = |bytes: &[u8; 8], half: usize| {
        u32::from_le_bytes(bytes[4 * half..4 * half + 4].try_into().expect("4 bytes"))
    };
    let planes = |a: usize| {
        [
            word(&lo[a], 0),
            word(&lo[a], 1),
            word(&hi[a], 0),
            word(&hi[a], 1),
        ]
    };
    GpuBvhNode {
        header: [
            origin.x.to_bits(),
            origin.y.to_bits(),
            origin.z.to_bits(),
            u32::from_le_bytes([exponents[0], exponents[1], exponents[2], imask]),
        ],
        links: [bases[0], bases[1], word(&meta, 0), word(&meta, 1)],
        x_planes: planes(0),
        y_planes: planes(1),
        z_planes: planes(2),
    }
}

/// A byte of a node field's two words of bytes (`words[0]`: bytes 0-3, `words[1]`: 4-7).
fn byte(words: &[u32], i: usize) -> u8 {
    (words[i / 4] >> (8 * (i % 4))) as u8
}

/// The children of `n` in slot order, their planes rounded to f32.
pub(super) fn children(n: &GpuBvhNode) -> impl Iterator<Item = (usize, Child)> + '_ {
    let origin = Vec3A::new(
        f32::from_bits(n.header[0]),
        f32::from_bits(n.header[1]),
        f32::from_bits(n.header[2]),
    );
    let cells = Vec3A::from_array(std::array::from_fn(|a| {
        f32::from_bits(u32::from(byte(&n.header[3..], a)) << 23)
    }));
    let imask = byte(&n.header[3..], 3);
    let planes = [n.x_planes, n.y_planes, n.z_planes];
    (0..8).filter_map(move |i| {
        let meta = byte(&n.links[2..], i);
        if meta == 0 {
            return None;
        }
        let decode = |half: usize| {
            Vec3A::from_array(std::array::from_fn(|a| {
                plane(origin[a], cells[a], byte(&planes[a][2 * half..], i)) as f32
            }))
        };
        let link = if imask & (1 << i) != 0 {
            let slot = u32::from(meta & 0x1f) - 24;
            let before = (u32::from(imask) & ((1u32 << slot) - 1)).count_ones();
            Link::Node(n.links[0] + before)
        } else {
            Link::Leaf {
                first: n.links[1] + u32::from(meta & 0x1f),
                count: (meta >> 5).count_ones(),
            }
        };
        Some((
            i,
            Child {
                lo: decode(0),
                hi: decode(1),
                link,
            },
        ))
    })
}

/// The indices of `n`'s child nodes.
pub(super) fn child_nodes(n: &GpuBvhNode) -> impl Iterator<Item = u32> + '_ {
    children(n).filter_map(|(_, c)| match c.link {
        Link::Node(k) => Some(k),
        Link::Leaf { .. } => None,
    })
}
