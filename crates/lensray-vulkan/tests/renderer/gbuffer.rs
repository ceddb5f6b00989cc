//! The raster G-buffer: its view depth against traced rays, its albedo against a pinhole
//! render, the AOVs it gives (and the CPU reference's), and the preview's two routes to a view.

use glam::{Vec2, Vec3};
use lensray_core::camera::{Camera, CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::interface::{VIEW_ALBEDO, VIEW_COC, VIEW_DEPTH, VIEW_NORMAL};
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::scene::test_card::test_card;
use lensray_core::settings::{Shading, Shot};
use lensray_vulkan::{focus_distance_at, GpuRenderer};

use crate::support::*;
use lensray_core::sampler::CameraSample;

/// Mesh index of each flattened triangle.
fn triangle_meshes(scene: &lensray_core::scene::Scene) -> Vec<usize> {
    scene
        .meshes
        .iter()
        .enumerate()
        .flat_map(|(m, mesh)| std::iter::repeat_n(m, mesh.triangles.len()))
        .collect()
}

/// Pixels whose 8 neighbours all show the same thing (`id`) as the pixel.
fn interior(width: u32, height: u32, id: &[i64]) -> Vec<bool> {
    let (w, h) = (width as i64, height as i64);
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx < 0
                        || ny < 0
                        || nx >= w
                        || ny >= h
                        || id[(ny * w + nx) as usize] == id[i as usize]
                })
            })
        })
        .collect()
}

fn raster_depth_matches_rays(orthographic: bool) {
    let name = if orthographic {
        "raster_view_depth_matches_rays_orthographic"
    } else {
        "raster_view_depth_matches_rays_perspective"
    };
    let Some((mut gpu, log)) = renderer(name) else {
        return;
    };
    let scene = test_scene();
    gpu.load_scene(&scene).expect("load scene");
    let cam = camera(orthographic, LensParams::Pinhole, 160, 120);
    let g = gpu.render_gbuffer(&cam, BACKGROUND).expect("G-buffer");
    let cpu = CpuRenderer::new(&scene);
    let meshes = triangle_meshes(&scene);

    let n = (cam.width * cam.height) as usize;
    let mut ids = vec![-1i64; n];
    let mut depth = vec![0.0f32; n];
    for y in 0..cam.height {
        for x in 0..cam.width {
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let ray = cam.first_order_ray(CameraSample::new(centre, Vec2::splat(0.5)));
            if let Some(hit) = cpu.intersect(&ray) {
                let i = g.index(x, y);
                ids[i] = meshes[hit.triangle as usize] as i64;
                depth[i] = cam.view_depth(ray.at(hit.t));
            }
        }
    }
    let keep = interior(cam.width, cam.height, &ids);
    let (mut checked, mut good, mut coverage_mismatch) = (0usize, 0usize, 0usize);
    let mut worst = Vec::new();
    for i in 0..n {
        if !keep[i] {
            continue;
        }
        if g.coverage[i] != (ids[i] >= 0) {
            coverage_mismatch += 1;
            continue;
        }
        if ids[i] < 0 {
            assert_eq!(g.view_depth[i], 0.0, "uncovered pixel {i} has a depth");
            continue;
        }
        checked += 1;
        let rel = (g.view_depth[i] - depth[i]).abs() / depth[i];
        if rel <= 1e-3 {
            good += 1;
        } else if worst.len() < 10 {
            worst.push((i, g.view_depth[i], depth[i]));
        }
    }
    assert!(checked > n / 3, "only {checked} covered interior pixels");
    let fraction = good as f64 / checked as f64;
    println!("{name}: {good}/{checked} within 1e-3, coverage mismatches {coverage_mismatch}");
    assert!(
        fraction >= 0.995 && coverage_mismatch * 200 <= checked,
        "{name}: {good}/{checked} covered pixels within 1e-3 ({coverage_mismatch} coverage \
         mismatches); first misses (pixel, raster, ray): {worst:?}"
    );
    finish(gpu, log);
}

#[test]
fn raster_view_depth_matches_rays_perspective() {
    raster_depth_matches_rays(false);
}

#[test]
fn raster_view_depth_matches_rays_orthographic() {
    raster_depth_matches_rays(true);
}

#[test]
fn pinhole_compute_equals_gbuffer_albedo() {
    let Some((mut gpu, log)) = renderer("pinhole_compute_equals_gbuffer_albedo") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    for orthographic in [false, true] {
        let shot = Shot {
            camera: camera(orthographic, LensParams::Pinhole, 128, 96),
            render: settings(Shading::Unlit, 4),
        };
        let cam = &shot.camera;
        let g = gpu.render_gbuffer(cam, BACKGROUND).expect("G-buffer");
        let image = gpu.render(&shot, &mut |_, _| {}).expect("render");
        let ids: Vec<i64> = g
            .albedo
            .iter()
            .map(|a| {
                let q = (*a * 1000.0).round();
                (q.x as i64) << 40 | (q.y as i64) << 20 | q.z as i64
            })
            .collect();
        let keep = interior(cam.width, cam.height, &ids);
        let checked = keep.iter().filter(|&&k| k).count();
        let equal = (0..g.albedo.len())
            .filter(|&i| keep[i] && (image.pixels[i] - g.albedo[i]).abs().max_element() <= 1e-6)
            .count();
        let fraction = equal as f64 / checked as f64;
        if fraction < 0.995 {
            let albedo = Image {
                width: cam.width,
                height: cam.height,
                pixels: g.albedo.clone(),
            };
            let files = write_comparison(&image, &albedo, &format!("pinhole-ortho{orthographic}"));
            panic!("pinhole (ortho {orthographic}): {equal}/{checked} interior pixels equal the albedo; wrote {files}");
        }
    }
    finish(gpu, log);
}

#[test]
fn aovs_come_from_the_gbuffer() {
    let Some((mut gpu, log)) = renderer("aovs_come_from_the_gbuffer") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let cam = camera(false, LensParams::Pinhole, 80, 60);
    let g = gpu.render_gbuffer(&cam, BACKGROUND).expect("G-buffer");
    let aov = |shading| Shot {
        camera: cam.clone(),
        render: settings(shading, 1),
    };
    let depth = gpu
        .render(&aov(Shading::Depth), &mut |_, _| {})
        .expect("depth");
    let normal = gpu
        .render(&aov(Shading::Normal), &mut |_, _| {})
        .expect("normal");
    let albedo = gpu
        .render(&aov(Shading::Albedo), &mut |_, _| {})
        .expect("albedo");
    for i in 0..g.coverage.len() {
        assert_eq!(depth.pixels[i], Vec3::splat(g.view_depth[i]));
        assert_eq!(normal.pixels[i], g.normal[i]);
        assert_eq!(albedo.pixels[i], g.albedo[i]);
        if g.coverage[i] {
            assert!((g.normal[i].length() - 1.0).abs() < 1e-4);
            assert!(g.view_depth[i] > cam.near);
        } else {
            assert_eq!(g.albedo[i], BACKGROUND);
            assert_eq!(g.view_depth[i], 0.0);
        }
    }
    // Autofocus on the centre pixel: the sphere/box region is covered.
    let (cx, cy) = (cam.width / 2, cam.height / 2);
    let f = focus_distance_at(&g, cx, cy).expect("centre covered");
    assert_eq!(f, g.view_depth[g.index(cx, cy)]);
    assert_eq!(focus_distance_at(&g, cam.width, 0), None);
    finish(gpu, log);
}

/// The CPU reference's AOVs are defined as the G-buffer's (aperture-centre ray at each pixel
/// centre), so the two devices agree on them away from silhouettes, with depth of field on.
#[test]
fn gpu_aovs_match_cpu_aovs() {
    let Some((mut gpu, log)) = renderer("gpu_aovs_match_cpu_aovs") else {
        return;
    };
    let scene = test_scene();
    gpu.load_scene(&scene).expect("load scene");
    let cpu = lensray_core::reference::Renderer::new(&scene);
    let lens = LensParams::ThinLens {
        aperture_radius: 0.2,
        focus_distance: 4.0,
    };
    for orthographic in [false, true] {
        let cam = camera(orthographic, lens.clone(), 80, 60);
        for shading in [Shading::Depth, Shading::Normal, Shading::Albedo] {
            let shot = Shot {
                camera: cam.clone(),
                render: settings(shading, 4),
            };
            let g = gpu.render(&shot, &mut |_, _| {}).expect("GPU AOV");
            let (c, _) = cpu.render(&shot, &mut |_, _| {});
            // Depth to 1e-4 of the far distance; colours and normals absolutely.
            let tolerance = if shading == Shading::Depth {
                1e-4 * cam.far
            } else {
                1e-3
            };
            let diff = compare(&g, &c, tolerance);
            let name = format!(
                "aov_{shading:?}_{}",
                if orthographic { "ortho" } else { "persp" }
            );
            assert!(
                diff.within >= 0.995,
                "{name}: {:.4} of pixels within {tolerance} (max {}), {}",
                diff.within,
                diff.max_abs,
                write_comparison(&g, &c, &name)
            );
        }
    }
    finish(gpu, log);
}

/// The preview draws its non-final views with the view pass, straight into the window image,
/// and the final view's frames with the G-buffer and the resolve: both routes must show the
/// same bytes, background included.
#[test]
fn preview_views_by_both_routes_are_equal() {
    let Some((mut gpu, log)) = renderer("preview_views_by_both_routes_are_equal") else {
        return;
    };
    gpu.load_scene(&test_scene()).expect("load scene");
    let lens = LensParams::ThinLens {
        aperture_radius: 0.1,
        focus_distance: 5.0,
    };
    for orthographic in [false, true] {
        let cam = camera(orthographic, lens.clone(), 96, 64);
        assert_view_routes_equal(&mut gpu, &cam, &format!("ortho{orthographic}"));
    }
    finish(gpu, log);
}

/// The same on the textured test card: textured, alpha-tested and plain surfaces, each drawn by
/// its own specialization of the view pass and of the G-buffer pass.
#[test]
fn preview_views_of_textured_surfaces_by_both_routes_are_equal() {
    let test = "preview_views_of_textured_surfaces_by_both_routes_are_equal";
    let Some((mut gpu, log)) = renderer(test) else {
        return;
    };
    gpu.load_scene(&test_card()).expect("load scene");
    let cam = CameraParams {
        eye: Vec3::new(0.0, 1.2, 4.0),
        target: Vec3::new(0.0, 0.8, 0.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 50.0 },
        lens: LensParams::ThinLens {
            aperture_radius: 0.06,
            focus_distance: 4.3,
        },
        near: 0.1,
        far: 100.0,
        width: 96,
        height: 72,
        movements: Movements::NONE,
    }
    .build()
    .expect("valid camera");
    assert_view_routes_equal(&mut gpu, &cam, "card");
    finish(gpu, log);
}

/// Every non-final view of `cam` by the G-buffer and resolve and by the view pass: the same
/// bytes in every pixel, background included (else both routes' images are written, named
/// after `name`).
fn assert_view_routes_equal(gpu: &mut GpuRenderer, cam: &Camera, name: &str) {
    for view in [VIEW_ALBEDO, VIEW_NORMAL, VIEW_DEPTH, VIEW_COC] {
        let routes = gpu
            .probe_view_routes(cam, BACKGROUND, view)
            .expect("both routes");
        let differ: Vec<i32> = routes
            .resolved
            .iter()
            .zip(&routes.drawn)
            .map(|(a, b)| {
                (0..4)
                    .map(|c| (a[c] as i32 - b[c] as i32).abs())
                    .max()
                    .unwrap()
            })
            .filter(|&d| d > 0)
            .collect();
        if !differ.is_empty() {
            let name = format!("view{view}-{name}");
            for (pixels, route) in [(&routes.resolved, "resolved"), (&routes.drawn, "drawn")] {
                let bytes = pixels.iter().flatten().copied().collect();
                image::RgbaImage::from_raw(cam.width, cam.height, bytes)
                    .expect("4 bytes per pixel")
                    .save(output_dir().join(format!("{name}-{route}.png")))
                    .expect("write PNG");
            }
            panic!(
                "view {view} ({name}): {} of {} pixels differ between the resolve and the view \
                 pass, by up to {}/255; wrote {name}-*.png under {}",
                differ.len(),
                routes.drawn.len(),
                differ.iter().max().unwrap(),
                output_dir().display()
            );
        }
    }
}
