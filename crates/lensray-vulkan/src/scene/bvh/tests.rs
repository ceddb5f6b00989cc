//! A host mirror of the shader's traversal (hit_software.glsl: node groups by octant, the
//! decoded planes, the closest-hit rule) checks the wide BVH against brute force with the same
//! watertight triangle test, and its structure: every triangle in exactly one leaf, every
//! decoded box around its subtree.

use glam::{Vec3, Vec3A};

use super::quantize::{children, Link};
use super::*;
use lensray_core::reference::WatertightRay;
use lensray_core::scene::generate::uv_sphere;
use lensray_core::scene::terrain::icosphere;

fn slab(lo: Vec3A, hi: Vec3A, o: Vec3A, inv: Vec3A, t_max: f32) -> bool {
    let t0 = (lo - o) * inv;
    let t1 = (hi - o) * inv;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element().min(t_max) * 1.000_000_4;
    near <= far
}

/// The shader's octant (traversal_octant).
fn octant(d: Vec3) -> u32 {
    u32::from(d.x >= 0.0) << 2 | u32::from(d.y >= 0.0) << 1 | u32::from(d.z >= 0.0)
}

/// The shader's intersect_node: the groups of hit child nodes and hit leaves' triangles.
fn intersect_node(
    bvh: &FlatBvh,
    index: u32,
    o: Vec3A,
    inv: Vec3A,
    oct: u32,
    t_max: f32,
) -> [(u32, u32); 2] {
    let n = &bvh.nodes[index as usize];
    let mut hits = 0u32;
    for (i, c) in children(n) {
        if !slab(c.lo, c.hi, o, inv, t_max) {
            continue;
        }
        hits |= match c.link {
            Link::Node(_) => 1 << (24 + (i as u32 ^ oct)),
            Link::Leaf { first, count } => ((1 << count) - 1) << (first - n.links[1]),
        };
    }
    let imask = n.header[3] >> 24;
    [
        (n.links[0], (hits & 0xff00_0000) | imask),
        (n.links[1], hits & 0x00ff_ffff),
    ]
}

/// Closest hit (triangle index, t), the nodes fetched and the triangles tested.
pub(super) fn traverse(bvh: &FlatBvh, o: Vec3, d: Vec3) -> (Option<(u32, f32)>, u32, u32) {
    let ray = WatertightRay::new(o, d);
    let (o3, inv) = (Vec3A::from(o), Vec3A::from(d.recip()));
    let oct = octant(d);
    let mut best: Option<(u32, f32)> = None;
    let mut stack = Vec::new();
    let mut nodes = (0u32, 0x8000_0000u32);
    let mut triangles = (0u32, 0u32);
    let (mut fetches, mut tests) = (0, 0);
    loop {
        if nodes.1 & 0xff00_0000 != 0 {
            let bit = 31 - nodes.1.leading_zeros();
            nodes.1 &= !(1 << bit);
            let slot = (bit - 24) ^ oct;
            let node = nodes.0 + (nodes.1 & !(u32::MAX << slot)).count_ones();
            if nodes.1 & 0xff00_0000 != 0 {
                stack.push(nodes);
                assert!(stack.len() <= BVH_STACK_SIZE as usize);
            }
            let t_max = best.map_or(f32::INFINITY, |b| b.1);
            [nodes, triangles] = intersect_node(bvh, node, o3, inv, oct, t_max);
            fetches += 1;
        }
        while triangles.1 != 0 {
            let bit = 31 - triangles.1.leading_zeros();
            triangles.1 &= !(1 << bit);
            let t = &bvh.triangles[(triangles.0 + bit) as usize];
            tests += 1;
            let v = [t.v0, t.v1, t.v2].map(|p| Vec3A::from_slice(&p[..3]));
            let bound = best.map_or(f32::INFINITY, |b| f32::from_bits(b.1.to_bits() + 2));
            let Some((t_hit, _)) = ray.intersect(&v, 0.0, bound) else {
                continue;
            };
            let index = t.v0[3] as u32;
            if best.is_none_or(|b| t_hit < b.1 || (t_hit == b.1 && index < b.0)) {
                best = Some((index, t_hit));
            }
        }
        if nodes.1 & 0xff00_0000 == 0 {
            match stack.pop() {
                Some(group) => nodes = group,
                None => break,
            }
        }
    }
    (best, fetches, tests)
}

pub(super) fn flatten(meshes: &[lensray_core::scene::Mesh]) -> (Vec<[f32; 4]>, Vec<u32>) {
    let (mut positions, mut indices) = (Vec::new(), Vec::new());
    for m in meshes {
        let base = positions.len() as u32;
        positions.extend(m.positions.iter().map(|p| p.extend(1.0).to_array()));
        indices.extend(m.triangles.iter().flatten().map(|i| base + i));
    }
    (positions, indices)
}

/// Spheres, and icospheres sharing edges and vertices with each other (ties at shared edges).
fn test_meshes() -> Vec<lensray_core::scene::Mesh> {
    let mut meshes = vec![
        uv_sphere("a", Vec3::new(0.0, 0.0, 0.0), 1.0, 24, 12, 0),
        uv_sphere("b", Vec3::new(1.5, 0.3, -1.0), 0.7, 16, 8, 0),
    ];
    let (unit, triangles) = icosphere(1);
    for (k, centre) in [Vec3::new(-1.2, 0.4, 0.5), Vec3::new(-1.2, 0.4, 0.5)]
        .iter()
        .enumerate()
    {
        meshes.push(lensray_core::scene::Mesh {
            colours: Vec::new(),
            tangents: Vec::new(),
            name: format!("ico{k}"),
            positions: unit.iter().map(|&p| *centre + 0.5 * p).collect(),
            triangles: triangles.clone(),
            ..Default::default()
        });
    }
    meshes
}

#[test]
fn finds_the_reference_closest_hits() {
    let (positions, indices) = flatten(&test_meshes());
    let tris: Vec<[Vec3A; 3]> = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]].map(|i| Vec3A::from_slice(&positions[i as usize][..3])))
        .collect();
    // The first icosphere's indices (80 triangles a sphere).
    let ico_start = indices.len() - 2 * 240;
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
            medium_build: false,
        },
    ] {
        let bvh = FlatBvh::build(&positions, &indices, &[], &params).unwrap();
        assert_eq!(bvh.triangles.len(), tris.len());
        let (mut hits, mut fetches) = (0, 0);
        for i in 0..600 {
            let a = i as f32 * 0.7;
            let o = Vec3::new(4.0 * a.cos(), 0.5 * (a * 1.3).sin(), 4.0 * a.sin());
            let target = Vec3::new(0.5 * (a * 2.1).sin() - 0.4, 0.4 * (a * 0.7).cos(), -0.3);
            // Every tenth ray through a vertex of the twin icospheres: ties between the two.
            let target = if i % 10 == 0 {
                Vec3::from_slice(&positions[indices[ico_start + (i * 7) % 240] as usize][..3])
            } else {
                target
            };
            let d = (target - o).normalize();
            let want = brute_force(o, d);
            let (got, n, _) = traverse(&bvh, o, d);
            assert_eq!(got, want, "ray {i} with {params:?}");
            hits += usize::from(got.is_some());
            fetches += n;
        }
        assert!(hits > 200, "{hits}");
        assert!(fetches > 600, "{fetches}");
    }
}

#[test]
fn every_triangle_in_one_leaf_inside_every_box_above_it() {
    let (positions, indices) = flatten(&test_meshes());
    for params in [
        BvhParams::default(),
        BvhParams {
            max_leaf_triangles: 1,
            medium_build: true,
        },
    ] {
        let bvh = FlatBvh::build(&positions, &indices, &[], &params).unwrap();
        let mut seen = vec![0u32; bvh.triangles.len()];
        // (node, the decoded boxes on the path to it)
        let mut pending = vec![(0u32, Vec::<(Vec3A, Vec3A)>::new())];
        let mut visited = 0;
        while let Some((k, path)) = pending.pop() {
            visited += 1;
            for (_, c) in children(&bvh.nodes[k as usize]) {
                let mut below = path.clone();
                below.push((c.lo, c.hi));
                match c.link {
                    Link::Node(child) => pending.push((child, below)),
                    Link::Leaf { first, count } => {
                        assert!((1..=params.max_leaf_triangles).contains(&count));
                        for slot in first..first + count {
                            seen[slot as usize] += 1;
                            let b = triangle_box(&bvh.triangles[slot as usize]);
                            for (lo, hi) in &below {
                                assert!(lo.cmple(b.min).all() && hi.cmpge(b.max).all());
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(visited, bvh.nodes.len(), "every node reached once");
        assert!(seen.iter().all(|&n| n == 1), "every triangle in one leaf");
        let mut indices_seen: Vec<u32> = bvh.triangles.iter().map(|t| t.v0[3] as u32).collect();
        indices_seen.sort_unstable();
        assert_eq!(
            indices_seen,
            (0..(indices.len() / 3) as u32).collect::<Vec<_>>()
        );
        let levels = depth(&bvh.nodes);
        assert!((2..=BVH_STACK_SIZE).contains(&levels), "{levels}");
    }
}

#[test]
fn empty_and_single_leaf_scenes() {
    let bvh = FlatBvh::build(&[], &[], &[], &BvhParams::default()).unwrap();
    assert_eq!((bvh.nodes.len(), bvh.triangles.len()), (1, 1));
    assert_eq!(traverse(&bvh, Vec3::new(0.0, 0.0, -1.0), Vec3::Z).0, None);

    let positions = [
        [0.0, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, 1.0],
    ];
    let bvh = FlatBvh::build(&positions, &[0, 1, 2], &[], &BvhParams::default()).unwrap();
    assert_eq!(bvh.nodes.len(), 1);
    let (hit, fetches, tests) = traverse(&bvh, Vec3::new(0.2, 0.2, -1.0), Vec3::Z);
    assert_eq!((hit, fetches, tests), (Some((0, 1.0)), 1, 1));
}
