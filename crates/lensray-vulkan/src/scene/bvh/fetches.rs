//! Node fetches per ray of the wide BVH against the binary layout it replaces (obvhs's BVH2,
//! leaves of up to 4 triangles, collapse cost 1.5, each node holding both children's boxes,
//! ordered traversal that skips popped nodes beyond the closest hit), both traversed by host
//! mirrors of their shaders over the camera rays of the generated scenes.
//! `LENSRAY_BVH_FETCHES=dense|terrain` measures the full-size scenes (docs/performance.md).

use std::time::Duration;

use glam::{Vec3, Vec3A};
use obvhs::{bvh2::builder::build_bvh2_from_tris, bvh2::Bvh2, triangle::Triangle, BvhBuildParams};

use super::tests::{flatten, traverse};
use super::{BvhParams, FlatBvh};
use lensray_core::reference::WatertightRay;
use lensray_core::scene::file::SceneDescription;

/// Per ray: (node fetches, triangle tests) of the binary layout's ordered traversal.
fn binary_traverse(bvh: &Bvh2, tris: &[[Vec3A; 3]], o: Vec3, d: Vec3) -> (u32, u32) {
    let ray = WatertightRay::new(o, d);
    let (o3, inv) = (Vec3A::from(o), Vec3A::from(d.recip()));
    let entry = |i: u32, t_max: f32| {
        let b = bvh.nodes[i as usize].aabb;
        let (t0, t1) = ((b.min - o3) * inv, (b.max - o3) * inv);
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max) * 1.000_000_4;
        (near <= far).then_some(near)
    };
    let (mut fetches, mut tests, mut best) = (0, 0, f32::INFINITY);
    let mut stack: Vec<(u32, f32)> = Vec::new();
    let mut node = if bvh.nodes[0].prim_count > 0 {
        None
    } else {
        Some(0u32)
    };
    while let Some(n) = node {
        fetches += 1;
        let first = bvh.nodes[n as usize].first_index;
        let mut inner = Vec::new();
        for child in [first, first + 1] {
            let Some(near) = entry(child, best) else {
                continue;
            };
            let c = &bvh.nodes[child as usize];
            if c.prim_count == 0 {
                inner.push((child, near));
                continue;
            }
            for k in c.first_index..c.first_index + c.prim_count {
                tests += 1;
                let tri = &tris[bvh.primitive_indices[k as usize] as usize];
                if let Some((t, _)) = ray.intersect(tri, 0.0, best) {
                    best = t;
                }
            }
        }
        inner.retain(|&(_, near)| near <= best);
        inner.sort_by(|a, b| b.1.total_cmp(&a.1));
        node = inner.pop().map(|(c, _)| c);
        stack.extend(inner);
        if node.is_none() {
            while let Some((c, near)) = stack.pop() {
                if near <= best {
                    node = Some(c);
                    break;
                }
            }
        }
    }
    (fetches, tests)
}

/// Camera rays of `desc` (pinhole, a `w` x `h` grid of pixel centres).
fn camera_rays(desc: &SceneDescription, w: u32, h: u32) -> Vec<(Vec3, Vec3)> {
    let c = &desc.settings.camera;
    let v = |a: Option<[f64; 3]>| {
        Vec3::from_array(a.expect("generated scenes set it").map(|x| x as f32))
    };
    let (eye, target) = (v(c.eye), v(c.target));
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let half = (c.vfov_degrees.unwrap_or(40.0) as f32).to_radians() * 0.5;
    let (sy, sx) = (half.tan(), half.tan() * w as f32 / h as f32);
    (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| {
            let x = (2.0 * (i as f32 + 0.5) / w as f32 - 1.0) * sx;
            let y = (1.0 - 2.0 * (j as f32 + 0.5) / h as f32) * sy;
            (eye, (forward + x * right + y * up).normalize())
        })
        .collect()
}

/// (wide fetches, binary fetches, wide triangle tests, binary triangle tests) per ray.
fn fetches_per_ray(desc: &SceneDescription, w: u32, h: u32) -> [f64; 4] {
    let (positions, indices) = flatten(&desc.scene.meshes);
    let wide = FlatBvh::build(&positions, &indices, &[], &BvhParams::default()).unwrap();
    let tris: Vec<[Vec3A; 3]> = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]].map(|i| Vec3A::from_slice(&positions[i as usize][..3])))
        .collect();
    let obvhs_tris: Vec<Triangle> = tris
        .iter()
        .map(|&[v0, v1, v2]| Triangle { v0, v1, v2 })
        .collect();
    let mut build = BvhBuildParams::medium_build();
    build.max_prims_per_leaf = 4;
    build.collapse_traversal_cost = 1.5;
    let binary = build_bvh2_from_tris(&obvhs_tris, build, &mut Duration::default());
    let rays = camera_rays(desc, w, h);
    let mut sums = [0u64; 4];
    for &(o, d) in &rays {
        let (_, wide_fetches, wide_tests) = traverse(&wide, o, d);
        let (binary_fetches, binary_tests) = binary_traverse(&binary, &tris, o, d);
        for (s, x) in sums
            .iter_mut()
            .zip([wide_fetches, binary_fetches, wide_tests, binary_tests])
        {
            *s += u64::from(x);
        }
    }
    sums.map(|s| s as f64 / rays.len() as f64)
}

#[test]
fn wide_nodes_take_fewer_fetches_than_binary_nodes() {
    let (desc, w, h) = match std::env::var("LENSRAY_BVH_FETCHES").as_deref() {
        Ok("dense") => (lensray_core::scene::generate::dense(1_000_000), 160, 120),
        Ok("terrain") => (lensray_core::scene::terrain::terrain(), 160, 120),
        _ => (lensray_core::scene::generate::dense(20_000), 40, 30),
    };
    let [wide, binary, wide_tests, binary_tests] = fetches_per_ray(&desc, w, h);
    println!(
        "{} triangles, {w}x{h} camera rays: node fetches per ray {wide:.1} (wide) vs {binary:.1} \
         (binary), {:.2}x fewer; triangle tests per ray {wide_tests:.1} vs {binary_tests:.1}",
        desc.scene.triangle_count(),
        binary / wide
    );
    assert!(wide > 1.0 && wide * 1.5 < binary, "{wide} vs {binary}");
}
