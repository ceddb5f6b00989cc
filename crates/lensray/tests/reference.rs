//! The CPU reference renderer against analytic answers.

use std::path::PathBuf;

use glam::{Vec2, Vec3, Vec3A};
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::film::colour::linear_to_srgb;
use lensray_core::film::Image;
use lensray_core::reference::{Accel, Renderer, WatertightRay};
use lensray_core::sampler::{hash_u32, SamplerKind};
use lensray_core::scene::{Material, Mesh, Scene};
use lensray_core::settings::{PointLight, RenderSettings, Shading};

mod edge_fit;

fn rand01(state: &mut u32) -> f32 {
    *state = hash_u32(state.wrapping_add(0x9e37_79b9));
    (*state >> 8) as f32 / 16_777_216.0
}

/// An axis-aligned quad in the plane z = `z`, facing -z, covering [x0, x1] x [y0, y1].
fn quad(x0: f32, x1: f32, y0: f32, y1: f32, z: f32, material: u32) -> Mesh {
    Mesh {
        name: "quad".into(),
        positions: vec![
            Vec3::new(x0, y0, z),
            Vec3::new(x1, y0, z),
            Vec3::new(x1, y1, z),
            Vec3::new(x0, y1, z),
        ],
        normals: vec![],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material_ids: vec![material; 2],
    }
}

fn material(name: &str, diffuse: Vec3, emission: Vec3) -> Material {
    Material {
        name: name.into(),
        diffuse,
        emission,
    }
}

/// Camera at the origin looking along world -z (so camera +x is world +x, camera +y world +y).
fn camera(width: u32, height: u32, lens: LensParams) -> Camera {
    CameraParams {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 40.0 },
        lens,
        near: 0.01,
        far: 100.0,
        width,
        height,
    }
    .build()
    .expect("valid camera")
}

fn settings(shading: Shading, spp: u32) -> RenderSettings {
    RenderSettings {
        spp,
        seed: 1,
        sampler: SamplerKind::default(),
        shading,
        background: Vec3::new(0.2, 0.3, 0.4),
        light: PointLight {
            position: Vec3::new(0.0, 0.0, 0.0),
            intensity: Vec3::splat(10.0),
        },
        shared_samples: false,
    }
}

#[test]
fn bvh_closest_hit_equals_brute_force() {
    let mut s = 17u32;
    let mut tris = Vec::new();
    for _ in 0..2000 {
        let c = Vec3A::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        let v = |s: &mut u32| c + Vec3A::new(rand01(s), rand01(s), rand01(s)) - 0.5;
        tris.push([v(&mut s), v(&mut s), v(&mut s)]);
    }
    let accel = Accel::build(&tris);
    let mut mismatches = Vec::new();
    for i in 0..2000 {
        let origin = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 14.0 - 2.0;
        let target = Vec3::new(rand01(&mut s), rand01(&mut s), rand01(&mut s)) * 10.0;
        let dir = (target - origin).normalize();
        let wt = WatertightRay::new(origin, dir);
        let brute = tris
            .iter()
            .filter_map(|t| wt.intersect(t, 0.0, f32::INFINITY).map(|h| h.0))
            .fold(f32::INFINITY, f32::min);
        let bvh = accel
            .closest_hit(origin, dir, 0.0, f32::INFINITY)
            .map_or(f32::INFINITY, |h| h.t);
        if brute != bvh {
            mismatches.push((i, brute, bvh));
        }
    }
    assert!(
        mismatches.is_empty(),
        "BVH vs brute force (ray, brute t, bvh t): {mismatches:?}"
    );
}

#[test]
fn unlit_shows_diffuse_colour_and_background() {
    let red = Vec3::new(0.9, 0.1, 0.1);
    // Left half of the view covered by a red wall at z = -5.
    let scene = Scene {
        meshes: vec![quad(-10.0, 0.0, -10.0, 10.0, -5.0, 0)],
        materials: vec![material("red", red, Vec3::ZERO)],
    };
    let cam = camera(32, 24, LensParams::Pinhole);
    let s = settings(Shading::Unlit, 4);
    let (image, stats) = Renderer::new(&scene).render(&cam, &s, &mut |_, _| {});
    assert_eq!(stats.rays, 32 * 24 * 4);
    for row in 0..24 {
        assert_eq!(image.get(5, row), red, "left pixel ({row})");
        assert_eq!(image.get(26, row), s.background, "right pixel ({row})");
    }
}

#[test]
fn lit_matches_lambert_with_inverse_square() {
    // A white wall at z = -4, facing the camera; light at (1, 0.5, -1), intensity 10 W/sr.
    let kd = Vec3::new(0.5, 0.6, 0.7);
    let ke = Vec3::new(0.01, 0.02, 0.03);
    let scene = Scene {
        meshes: vec![quad(-50.0, 50.0, -50.0, 50.0, -4.0, 0)],
        materials: vec![material("wall", kd, ke)],
    };
    let cam = camera(16, 16, LensParams::Pinhole);
    let mut s = settings(Shading::Lit, 1);
    s.light.position = Vec3::new(1.0, 0.5, -1.0);
    let renderer = Renderer::new(&scene);
    let (image, _) = renderer.render(&cam, &s, &mut |_, _| {});
    let mut worst = 0.0f32;
    for row in 0..16 {
        for col in 0..16 {
            // Recompute the sample's hit point with the same sampler, then the formula by hand.
            let sample = lensray_core::sampler::camera_sample(
                s.sampler,
                s.seed,
                glam::UVec2::new(col, row),
                16,
                0,
            );
            let ray = cam.generate_ray(sample.film, sample.lens);
            let t = (-4.0 - ray.origin.z) / ray.direction.z;
            let p = ray.at(t);
            let to_light = s.light.position - p;
            let d2 = to_light.length_squared();
            let cos = to_light.normalize().z.max(0.0); // wall normal facing the camera is +z
            let expected = ke + kd / std::f32::consts::PI * s.light.intensity * cos / d2;
            let got = image.get(col, row);
            worst = worst.max(((got - expected) / expected).abs().max_element());
        }
    }
    assert!(
        worst < 1e-3,
        "worst relative error against Lambert: {worst}"
    );
}

/// Writes an image as an sRGB PNG under target/test-output (for a failing test to show).
fn write_png(image: &Image, name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/test-output");
    std::fs::create_dir_all(&dir).expect("create target/test-output");
    let path = dir.join(name);
    let encode = |v: f32| (linear_to_srgb(v).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    let mut buf = image::RgbImage::new(image.width, image.height);
    for (i, p) in image.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        buf.put_pixel(x, y, image::Rgb([encode(p.x), encode(p.y), encode(p.z)]));
    }
    buf.save(&path).expect("write PNG");
    path
}

/// What a pixel of the shadow scene shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Seen {
    Occluder,
    LitWall,
    ShadowedWall,
    /// Anything else (only ever a rendered value).
    Other,
}

#[test]
fn shadow_ray_blocks_the_light() {
    // The camera looks along -z at a wall z = WALL; a square occluder [-H, H]^2 at z = OCC sits
    // between the wall and a point light up and to the right, so the shadow falls down and to
    // the left of where the occluder itself is seen. Wall: red emission plus a grey diffuse
    // term; occluder: blue emission, no diffuse term. Each of the three cases has its own value.
    const WALL: f32 = -4.0;
    const OCC: f32 = -2.5;
    const H: f32 = 0.2;
    let light = Vec3::new(0.8, 0.3, -1.0);
    let wall_emission = Vec3::new(0.05, 0.0, 0.0);
    let occluder_emission = Vec3::new(0.0, 0.0, 0.05);
    let scene = Scene {
        meshes: vec![
            quad(-50.0, 50.0, -50.0, 50.0, WALL, 0),
            quad(-H, H, -H, H, OCC, 1),
        ],
        materials: vec![
            material("wall", Vec3::splat(0.8), wall_emission),
            material("occluder", Vec3::ZERO, occluder_emission),
        ],
    };
    let (width, height) = (128u32, 96u32);
    let cam = camera(width, height, LensParams::Pinhole);
    let mut s = settings(Shading::Lit, 1);
    s.light.position = light;
    let (image, _) = Renderer::new(&scene).render(&cam, &s, &mut |_, _| {});

    // The analytic class of the ray through a raster point, written out independently of the
    // camera module: vfov 40 degrees, square pixels, row 0 at the top, camera +x = world +x.
    let half_height = (20.0f32).to_radians().tan();
    let pixel_size = 2.0 * half_height / height as f32;
    let inside = |p: Vec3| p.x.abs() < H && p.y.abs() < H;
    let analytic = |col: u32, row: u32| {
        let dir = Vec3::new(
            (col as f32 + 0.5 - width as f32 / 2.0) * pixel_size,
            (height as f32 / 2.0 - row as f32 - 0.5) * pixel_size,
            -1.0,
        );
        if inside(dir * (OCC / dir.z)) {
            return Seen::Occluder;
        }
        let p = dir * (WALL / dir.z);
        // The segment from the wall point to the light crosses the occluder's plane here.
        let q = p + (light - p) * ((OCC - WALL) / (light.z - WALL));
        if inside(q) {
            Seen::ShadowedWall
        } else {
            Seen::LitWall
        }
    };
    let rendered = |col: u32, row: u32| {
        let c = image.get(col, row);
        if c == occluder_emission {
            Seen::Occluder
        } else if c == wall_emission {
            Seen::ShadowedWall
        } else if c.x > wall_emission.x && c.y > 0.0 && c.z > 0.0 {
            Seen::LitWall
        } else {
            Seen::Other
        }
    };

    // Film samples are jittered inside the pixel: only pixels whose 3x3 neighbourhood is all of
    // one class are sure to be that class (every boundary here is an axis-aligned line).
    let mut mismatches = Vec::new();
    let mut checked = 0;
    for row in 1..height - 1 {
        for col in 1..width - 1 {
            let class = analytic(col, row);
            let uniform =
                (row - 1..=row + 1).all(|r| (col - 1..=col + 1).all(|c| analytic(c, r) == class));
            if uniform {
                checked += 1;
                let got = rendered(col, row);
                if got != class {
                    mismatches.push(format!("({col},{row}): expected {class:?}, got {got:?}"));
                }
            }
        }
    }
    let bounding_box = |class_of: &dyn Fn(u32, u32) -> Seen| {
        let mut b = [u32::MAX, u32::MAX, 0, 0];
        for row in 0..height {
            for col in 0..width {
                if class_of(col, row) == Seen::ShadowedWall {
                    b = [b[0].min(col), b[1].min(row), b[2].max(col), b[3].max(row)];
                }
            }
        }
        b
    };
    let expected_box = bounding_box(&analytic);
    let rendered_box = bounding_box(&rendered);
    let box_differs = expected_box
        .iter()
        .zip(&rendered_box)
        .any(|(a, b)| a.abs_diff(*b) > 1);
    let shadowed = (0..height)
        .flat_map(|r| (0..width).map(move |c| (c, r)))
        .filter(|&(c, r)| analytic(c, r) == Seen::ShadowedWall)
        .count();
    if !mismatches.is_empty() || box_differs {
        let png = write_png(&image, "shadow.png");
        panic!(
            "{} of {checked} pixels differ from the analytic shadow: {}\n\
             shadow box (min col, min row, max col, max row): analytic {expected_box:?}, \
             rendered {rendered_box:?}; image: {}",
            mismatches.len(),
            mismatches.join(", "),
            png.display()
        );
    }
    // Test set-up: a shadow of many pixels, displaced from the occluder, with plenty checked.
    assert!(
        shadowed > 100,
        "only {shadowed} pixels in the analytic shadow"
    );
    assert!(
        checked > (width * height / 2) as usize,
        "only {checked} pixels checked"
    );
}

#[test]
fn depth_aov_is_distance_along_view_axis() {
    let scene = Scene {
        meshes: vec![quad(-50.0, 50.0, -50.0, 50.0, -7.5, 0)],
        materials: vec![Material::default()],
    };
    let cam = camera(20, 10, LensParams::Pinhole);
    let (image, _) =
        Renderer::new(&scene).render(&cam, &settings(Shading::Depth, 2), &mut |_, _| {});
    let worst = image
        .pixels
        .iter()
        .map(|d| (d.x - 7.5).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "depth differs from 7.5 by up to {worst}");
}

#[test]
fn edge_model_is_the_integral_of_the_disk_step() {
    edge_fit::self_check();
}

/// Renders a vertical black/white edge on a plane at view depth `z` through a thin lens, averages
/// the rows and fits the disk-blurred edge profile. Returns the fit, the CoC radius the camera
/// predicts, and the raster x where the edge's pinhole projection falls.
fn fit_edge(z: f32, lens: LensParams) -> (edge_fit::EdgeFit, f32, f32) {
    let (width, height) = (128u32, 32u32);
    let cam = camera(width, height, lens);
    // Put the edge 0.37 px right of a pixel boundary, so the fit also sees the box filter.
    let pixels_per_screen_unit = height as f32 / (2.0 * (20.0f32).to_radians().tan());
    let edge_x = 0.37 * z / pixels_per_screen_unit;
    let scene = Scene {
        meshes: vec![
            quad(-100.0, edge_x, -100.0, 100.0, -z, 0),
            quad(edge_x, 100.0, -100.0, 100.0, -z, 1),
        ],
        materials: vec![
            material("black", Vec3::ZERO, Vec3::ZERO),
            material("white", Vec3::ONE, Vec3::ZERO),
        ],
    };
    let (image, _) =
        Renderer::new(&scene).render(&cam, &settings(Shading::Unlit, 1024), &mut |_, _| {});
    let profile: Vec<f64> = (0..width)
        .map(|c| (0..height).map(|r| image.get(c, r).x as f64).sum::<f64>() / height as f64)
        .collect();
    let projected = cam.project(Vec3::new(edge_x, 0.0, -z)).x;
    (edge_fit::fit(&profile), cam.coc_radius_pixels(z), projected)
}

#[test]
fn depth_of_field_blurs_by_the_circle_of_confusion() {
    // Focused at 5 with aperture radius 1.5: the CoC is 13.2 px at z = 2.5 and 7.7 px at z = 12.
    let lens = LensParams::ThinLens {
        aperture_radius: 1.5,
        focus_distance: 5.0,
    };
    let mut failures = Vec::new();
    // In focus: the edge is sharp, only the pixel box filter remains.
    let (fit, coc, projected) = fit_edge(5.0, lens.clone());
    println!("in focus: {fit:?}, edge projected at {projected}");
    assert!(
        coc < 1e-3,
        "test set-up: CoC {coc} px at the focus distance"
    );
    if fit.radius >= 0.5 || (fit.edge - projected as f64).abs() >= 0.1 {
        failures.push(format!(
            "in focus: {fit:?}, expected a radius below 0.5 px at x = {projected}"
        ));
    }
    // Out of focus, nearer and farther: the profile is the disk-blurred step, of the CoC's
    // radius, centred on the pinhole projection. 5% off in aperture radius changes the CoC by 5%,
    // 5% off in focus distance by 4.8% (z = 2.5) and 8% (z = 12): a 2% tolerance catches either.
    // Measured over 8 seeds at 1024 spp: radius within 0.3%, edge within 0.03 px, rms residual
    // (noise) about 0.002; the residual bound catches a blur of another shape.
    for z in [2.5f32, 12.0] {
        let (fit, coc, projected) = fit_edge(z, lens.clone());
        assert!(coc > 5.0, "test set-up: CoC {coc} px at z = {z}");
        let relative = (fit.radius / coc as f64 - 1.0).abs();
        println!(
            "z = {z}: fitted radius {:.4} px, CoC {coc:.4} px (relative error {relative:.5}), \
             edge {:.4} vs {projected:.4}, rms residual {:.5}",
            fit.radius, fit.edge, fit.rms_residual
        );
        if relative >= 0.02
            || (fit.edge - projected as f64).abs() >= 0.1
            || fit.rms_residual >= 0.008
        {
            failures.push(format!(
                "z = {z}: {fit:?}, expected radius {coc} px at x = {projected}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn renders_are_deterministic() {
    let scene = Scene {
        meshes: vec![quad(-1.0, 1.0, -1.0, 1.0, -3.0, 0)],
        materials: vec![Material::default()],
    };
    let cam = camera(
        24,
        16,
        LensParams::ThinLens {
            aperture_radius: 0.1,
            focus_distance: 2.0,
        },
    );
    let r = Renderer::new(&scene);
    let s = settings(Shading::Lit, 8);
    let (a, _) = r.render(&cam, &s, &mut |_, _| {});
    let (b, _) = r.render(&cam, &s, &mut |_, _| {});
    assert_eq!(a, b);
    let _ = Vec2::ZERO;
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
        accel.closest_hits(&origins, &directions, 0.0, t_max, &mut hits);
        for l in 0..n {
            let single = accel.closest_hit(origins[l], directions[l], 0.0, t_max);
            assert_eq!(
                hits[l], single,
                "packet {packet} lane {l}: origin {:?} direction {:?}",
                origins[l], directions[l]
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
        accel.closest_hits(o, d, 0.0, f32::INFINITY, &mut hits);
        for l in 0..o.len() {
            let single = accel.closest_hit(o[l], d[l], 0.0, f32::INFINITY);
            assert!(
                single.is_some() && hits[l].is_some(),
                "ray {:?} missed the grid",
                o[l]
            );
            assert_eq!(
                hits[l].map(|h| h.t),
                single.map(|h| h.t),
                "ray from {:?}",
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
    let hit = accel.closest_hit(Vec3::new(0.1, 0.2, 5.0), -Vec3::Z, 0.0, f32::INFINITY);
    assert_eq!(hit.map(|h| h.t), Some(5.0));
    let mut hits = [None];
    accel.closest_hits(
        &[Vec3::new(0.1, 0.2, 5.0)],
        &[-Vec3::Z],
        0.0,
        f32::INFINITY,
        &mut hits,
    );
    assert_eq!(hits[0], hit);
    assert!(accel.occluded(Vec3::new(0.1, 0.2, 5.0), -Vec3::Z, 0.0, 6.0));
}

#[test]
fn packet_primary_rays_equal_generate_ray_bit_for_bit() {
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
                        lensray_core::reference::primary_rays(
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
                            let ray = cam.generate_ray(sample.film, sample.lens);
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
