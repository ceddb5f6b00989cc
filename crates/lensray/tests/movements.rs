//! Shift and tilt (`camera::movements`): a shifted window is a crop of a wider centred one,
//! and every path renders the CPU reference's image of a shifted, tilted shot, perspective and
//! orthographic. The hybrid (tests/hybrid.rs), the raster path (tests/raster.rs), the GLSL
//! mirrors (lensray-vulkan's tests/renderer/mirrors.rs) and the Scheimpflug rule (lensray-core's
//! tests/reference/scheimpflug.rs) are checked beside their kind.

mod gpu_support;

use glam::Vec3;
use gpu_support::{assert_gpu_paths_match_cpu, moved_camera, settings, test_scene};
use gpu_support::{render_path, write_comparison, MOVED};
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::{CameraParams, LensParams, Movements, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::settings::{Shading, Shot};

/// A pinhole looking at the test scene: `scale` of the wide camera's window, `shift` off the
/// axis (fractions of its own image height).
fn pinhole(orthographic: bool, width: u32, height: u32, scale: f64, shift: [f64; 2]) -> Shot {
    let half = 22.5f64.to_radians().tan() * scale;
    let camera = CameraParams {
        eye: Vec3::new(2.5, 2.2, 4.5),
        target: Vec3::new(0.0, 0.5, 0.0),
        up: Vec3::Y,
        projection: if orthographic {
            ProjectionParams::Orthographic {
                height: 4.0 * scale,
            }
        } else {
            ProjectionParams::Perspective {
                vfov_degrees: 2.0 * half.atan().to_degrees(),
            }
        },
        lens: LensParams::Pinhole,
        near: 0.5,
        far: 50.0,
        width,
        height,
        movements: Movements {
            shift,
            ..Movements::NONE
        },
    }
    .build()
    .expect("valid camera");
    Shot {
        camera,
        render: settings(Shading::Depth, 1),
    }
}

/// A shifted pinhole's image is the matching crop of a centred one twice as wide and tall with
/// the same film scale: the window of half the height, shifted by (aspect / 2, 1 / 2) of its
/// height, is the wide window's top-right quadrant, pixel for pixel. Depth AOVs are compared
/// (the surface under each pixel's centre, no sampling). The two cameras reach each pixel
/// centre's screen point through different matrices, equal within float rounding (1e-7
/// relative), so a centre ray grazing a triangle's edge may land on the other side: at most
/// 0.5 % of the pixels may differ, and the rest agree within 1e-5 relative.
#[test]
fn a_shifted_window_is_a_crop_of_a_wider_one() {
    let test = "a_shifted_window_is_a_crop_of_a_wider_one";
    let (w, h) = (96u32, 72u32);
    for orthographic in [false, true] {
        let wide = pinhole(orthographic, 2 * w, 2 * h, 1.0, [0.0, 0.0]);
        let aspect = w as f64 / h as f64;
        let shifted = pinhole(orthographic, w, h, 0.5, [0.5 * aspect, 0.5]);
        let cpu = PathChoice::Only(PathKind::Cpu);
        let (Some(wide_image), Some(shifted_image)) = (
            render_path(test, cpu, &wide),
            render_path(test, cpu, &shifted),
        ) else {
            return;
        };
        let mut crop = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                crop.set(x, y, wide_image.get(x + w, y));
            }
        }
        let differing = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let (a, b) = (shifted_image.get(x, y).x, crop.get(x, y).x);
                (a - b).abs() > 1e-5 * a.abs().max(b.abs()).max(1e-3)
            })
            .count();
        let share = differing as f64 / f64::from(w * h);
        println!(
            "orthographic {orthographic}: {differing} of {} pixels differ",
            w * h
        );
        if share > 0.005 {
            let files = write_comparison(&shifted_image, &crop, &format!("{test}-{orthographic}"));
            panic!(
                "orthographic {orthographic}: {:.2} % of the shifted window's pixels differ \
                 from the crop (bound 0.5 %); wrote {files}",
                100.0 * share
            );
        }
    }
}

/// Shifted and tilted (`MOVED`), each traced GPU path renders the CPU reference's image, and
/// the raster path the reference's shared-sample image, perspective and orthographic
/// (`assert_gpu_paths_match_cpu`'s bounds).
#[test]
fn every_path_agrees_with_the_cpu_on_a_shifted_tilted_shot() {
    let test = "every_path_agrees_with_the_cpu_on_a_shifted_tilted_shot";
    let shots = [false, true].map(|orthographic| {
        let lens = LensParams::ThinLens {
            aperture_radius: 0.12,
            focus_distance: 5.0,
        };
        let shot = Shot {
            camera: moved_camera(orthographic, lens, 64, 48, MOVED),
            render: settings(Shading::Lit, 8),
        };
        (format!("moved-ortho-{orthographic}"), shot)
    });
    assert_gpu_paths_match_cpu(test, &test_scene(), &shots);
}
