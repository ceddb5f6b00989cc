//! Ray traversal: Embree against brute force, ray packets against single rays, and the
//! packets' first-order rays (`reference::first_order_rays`) against `Camera::first_order_ray`.

use glam::{Vec3, Vec3A};
use lensray_core::camera::{CameraParams, LensParams, ProjectionParams};
use lensray_core::reference::{Accel, Hit, WatertightRay};
use lensray_core::sampler::SamplerKind;

use crate::rand01;

/// Embree's robust triangle test and lensray's watertight one (Woop et al.) compute t with
/// different arithmetic: a few ulps apart, never a different surface.
const T_RELATIVE_TOLERANCE: f32 = 1e-5;

/// Embree's kernels differ per instruction set (SSE4.2, AVX2, AVX-512: `LENSRAY_EMBREE_CONFIG`)
/// and between its packet and single-ray paths in the order of their arithmetic, so the same
/// hit's t and barycentrics may come out a few ulps apart (AVX2 puts a hit at 5 at 4.9999995,
/// one ulp under). Embree's floats are compared within these bounds, never exactly.
const EMBREE_T_ULPS: u32 = 4;
const EMBREE_BARYCENTRIC_TOLERANCE: f32 = 1e-5;

/// Ulps between two finite floats of one sign.
fn ulps_apart(a: f32, b: f32) -> u32 {
    a.to_bits().abs_diff(b.to_bits())
}

/// Whether two of Embree's answers are the same hit: the same triangle, t within
/// `EMBREE_T_ULPS`, barycentrics within `EMBREE_BARYCENTRIC_TOLERANCE`.
fn same_hit(a: Option<Hit>, b: Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.triangle == b.triangle
                && ulps_apart(a.t, b.t) <= EMBREE_T_ULPS
                && (a.barycentric - b.barycentric).abs().max_element()
                    <= EMBREE_BARYCENTRIC_TOLERANCE
        }
        _ => false,
    }
}

#[test]
fn closest_hit_equals_brute_force_watertight_test() {
    let mut s = 17u32;
    let mut tris = Vec::new();
    for _ in 0..2000 {
        let c = Vec3A::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        let v = |s: &mut u32| c + Vec3A::new(rand01(s), rand01(s), rand01(s)) - 0.5;
        tris.push([v(&mut s), v(&mut s), v(&mut s)]);
    }
    let accel = Accel::build(&tris);
    let mut mismatches = Vec::new();
    let (mut hits, mut worst) = (0, 0.0f32);
    for i in 0..2000 {
        let origin = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 14.0 - 2.0;
        let target = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        let dir = (target - origin).normalize();
        let wt = WatertightRay::new(origin, dir);
        let brute = tris
            .iter()
            .filter_map(|t| wt.intersect(t, 0.0, f32::INFINITY).map(|h| h.0))
            .fold(f32::INFINITY, f32::min);
        let embree = accel
            .closest_hit(origin, dir, (0.0, f32::INFINITY), None, 0.5)
            .map_or(f32::INFINITY, |h| h.t);
        if brute.is_finite() != embree.is_finite() {
            mismatches.push((i, brute, embree));
        } else if brute.is_finite() {
            hits += 1;
            let error = (brute - embree).abs() / brute.max(1.0);
            worst = worst.max(error);
            if error > T_RELATIVE_TOLERANCE {
                mismatches.push((i, brute, embree));
            }
        }
    }
    assert!(hits > 1000, "too few hits to mean anything: {hits}");
    assert!(
        mismatches.is_empty(),
        "Embree vs brute force beyond {T_RELATIVE_TOLERANCE} relative (worst {worst:e}), \
         (ray, brute t, Embree t): {mismatches:?}"
    );
}

/// Random triangles plus a tessellated grid (shared edges and vertices) for the packet tests.
fn packet_test_triangles() -> Vec<[Vec3A; 3]> {
    let mut s = 91u32;
    let mut tris = Vec::new();
    for _ in 0..3000 {
        let c = Vec3A::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        let v = |s: &mut u32| c + (Vec3A::new(rand01(s), rand01(s), rand01(s)) - 0.5) * 0.8;
        tris.push([v(&mut s), v(&mut s), v(&mut s)]);
    }
    // A 20 x 20 grid in the plane z = 12 - x / 4 (tilted, so t varies across it).
    let p = |i: u32, j: u32| {
        let (x, y) = (i as f32 * 0.5, j as f32 * 0.5);
        Vec3A::new(x, y, 12.0 - x * 0.25)
    };
    for i in 0..20 {
        for j in 0..20 {
            tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
            tris.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
        }
    }
    tris
}

#[test]
fn packet_hits_equal_single_ray_hits() {
    let tris = packet_test_triangles();
    let accel = Accel::build(&tris);
    let mut s = 5u32;
    let mut checked = 0;
    let mut hits_seen = 0;
    for packet in 0..3000 {
        let n = 1 + packet % lensray_core::reference::PACKET_SIZE;
        let mut origins = Vec::new();
        let mut directions = Vec::new();
        // Thirds: coherent (a lens disk through one focal point, as the renderer's samples),
        // incoherent (random origins and directions), and coherent around a 45-degree diagonal
        // (lanes with different axis permutations in one packet).
        let kind = packet % 3;
        let eye = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 14.0 - 2.0;
        let focus = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        for _ in 0..n {
            let (origin, direction) = match kind {
                0 => {
                    let o = eye
                        + (Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) - 0.5) * 0.2;
                    (o, (focus - o).normalize())
                }
                1 => {
                    let o = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 14.0 - 2.0;
                    let d = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 2.0 - 1.0;
                    (o, d.normalize_or(Vec3::X))
                }
                _ => {
                    let o = Vec3::new(-1.0, -1.0, 5.0)
                        + (Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) - 0.5) * 0.5;
                    let d = Vec3::new(1.0, 1.0, 0.0)
                        + (Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) - 0.5) * 0.02;
                    (o, d.normalize())
                }
            };
            origins.push(origin);
            directions.push(direction);
        }
        let mut hits = vec![None; n];
        let t_max = if packet % 7 == 0 { 6.0 } else { f32::INFINITY };
        let draws = vec![(0, 0.5); n];
        accel.closest_hits(&origins, &directions, &draws, (0.0, t_max), &mut hits);
        for l in 0..n {
            let single = accel.closest_hit(origins[l], directions[l], (0.0, t_max), None, 0.5);
            assert!(
                same_hit(hits[l], single),
                "packet {packet} lane {l}: origin {:?} direction {:?}: packet {:?}, single ray {:?}",
                origins[l],
                directions[l],
                hits[l],
                single
            );
            checked += 1;
            hits_seen += single.is_some() as usize;
        }
    }
    assert!(
        hits_seen > checked / 4,
        "too few hits to mean anything: {hits_seen} of {checked}"
    );
}

#[test]
fn packet_hits_on_shared_edges_have_the_single_ray_distance() {
    // Rays through the grid's vertices and along its edges: the edge functions are exactly zero
    // (the double-precision path). Two triangles then hit at the same t, and which of them is
    // reported depends on visiting order, so compare the distance.
    let tris = packet_test_triangles();
    let accel = Accel::build(&tris);
    let mut origins = Vec::new();
    let mut directions = Vec::new();
    for i in 1..20 {
        for j in 1..20 {
            let x = i as f32 * 0.5 + if (i + j) % 2 == 0 { 0.0 } else { 0.25 };
            origins.push(Vec3::new(x, j as f32 * 0.5, 30.0));
            directions.push(-Vec3::Z);
        }
    }
    for (o, d) in origins.chunks(13).zip(directions.chunks(13)) {
        let mut hits = vec![None; o.len()];
        accel.closest_hits(
            o,
            d,
            &vec![(0, 0.5); o.len()],
            (0.0, f32::INFINITY),
            &mut hits,
        );
        for l in 0..o.len() {
            let single = accel.closest_hit(o[l], d[l], (0.0, f32::INFINITY), None, 0.5);
            assert!(
                single.is_some() && hits[l].is_some(),
                "ray {:?} missed the grid",
                o[l]
            );
            let (packet_t, single_t) = (hits[l].unwrap().t, single.unwrap().t);
            assert!(
                ulps_apart(packet_t, single_t) <= EMBREE_T_ULPS,
                "ray from {:?}: packet t {packet_t}, single-ray t {single_t}",
                o[l]
            );
        }
    }
}

#[test]
fn rays_with_negative_zero_components_hit() {
    // -Vec3::Z is (-0, -0, -1): the BVH's slab order must not take -0 for a negative direction.
    let scene_tris = vec![[
        Vec3A::new(-1.0, -1.0, 0.0),
        Vec3A::new(1.0, -1.0, 0.0),
        Vec3A::new(0.0, 1.0, 0.0),
    ]];
    let accel = Accel::build(&scene_tris);
    let hit = accel.closest_hit(
        Vec3::new(0.1, 0.2, 5.0),
        -Vec3::Z,
        (0.0, f32::INFINITY),
        None,
        0.5,
    );
    let t = hit.expect("the ray hits the triangle").t;
    assert!(
        ulps_apart(t, 5.0) <= EMBREE_T_ULPS,
        "t {t}, {} ulps from 5 (bound {EMBREE_T_ULPS})",
        ulps_apart(t, 5.0)
    );
    let mut hits = [None];
    accel.closest_hits(
        &[Vec3::new(0.1, 0.2, 5.0)],
        &[-Vec3::Z],
        &[(0, 0.5)],
        (0.0, f32::INFINITY),
        &mut hits,
    );
    assert!(
        same_hit(hits[0], hit),
        "packet {:?}, single ray {hit:?}",
        hits[0]
    );
    assert!(accel.occluded(Vec3::new(0.1, 0.2, 5.0), -Vec3::Z, (0.0, 6.0), None, 0.5));
}

#[test]
fn packet_first_order_rays_equal_first_order_ray_bit_for_bit() {
    let lenses = [
        LensParams::Pinhole,
        LensParams::ThinLens {
            aperture_radius: 0.05,
            focus_distance: 3.0,
        },
    ];
    for projection in [
        ProjectionParams::Perspective { vfov_degrees: 50.0 },
        ProjectionParams::Orthographic { height: 4.0 },
    ] {
        for lens in lenses.clone() {
            let cam = CameraParams {
                eye: Vec3::new(0.3, 1.0, 2.0),
                target: Vec3::new(-0.5, 0.2, -3.0),
                up: Vec3::Y,
                projection,
                lens: lens.clone(),
                near: 0.01,
                far: 100.0,
                width: 37,
                height: 23,
                movements: lensray_core::camera::Movements::NONE,
            }
            .build()
            .expect("valid camera");
            let packet = lensray_core::reference::PACKET_SIZE as u32;
            for (px, py) in [(0, 0), (36, 22), (18, 11), (5, 17)] {
                for (seed, kind) in [(1, SamplerKind::Sobol), (99, SamplerKind::Independent)] {
                    for first in [0, packet, 3 * packet] {
                        let pixel = glam::UVec2::new(px, py);
                        let sampler =
                            lensray_core::sampler::pixel_sampler(kind, seed, pixel, cam.width);
                        let mut origins = [Vec3::ZERO; lensray_core::reference::PACKET_SIZE];
                        let mut directions = origins;
                        lensray_core::reference::first_order_rays(
                            &cam,
                            &sampler,
                            first,
                            &mut origins,
                            &mut directions,
                        );
                        for l in 0..packet {
                            let sample = lensray_core::sampler::camera_sample(
                                kind,
                                seed,
                                pixel,
                                cam.width,
                                first + l,
                            );
                            let ray = cam.first_order_ray(sample);
                            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                            assert_eq!(
                                (bits(origins[l as usize]), bits(directions[l as usize])),
                                (bits(ray.origin), bits(ray.direction)),
                                "{projection:?} {lens:?} pixel {pixel} sample {}",
                                first + l
                            );
                        }
                    }
                }
            }
        }
    }
}
