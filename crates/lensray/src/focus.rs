//! Focusing on what the image shows: the view depth under a pixel (`--focus-at`), and the plane
//! of focus through the surfaces under three pixels (`--focus-plane`, `camera::FocusPlane`; the
//! preview's Shift+clicks). Neither command-line nor window code: `render` and the preview both
//! focus through it.

use anyhow::{Context, Result};
use glam::{DVec3, Vec2, Vec3};

use crate::paths::RenderPath;
use lensray_core::camera::{Camera, FocusPlane};
use lensray_core::settings::{tilt_model, Settings, Shot};

/// The view depth at `pixel`, or an error naming the option and the pixel when it lies outside
/// the image or shows no surface.
pub fn focus_depth_at(
    path: &mut dyn RenderPath,
    camera: &Camera,
    pixel: [u32; 2],
    option: &str,
) -> Result<f32> {
    let [x, y] = pixel;
    if x >= camera.width || y >= camera.height {
        anyhow::bail!(
            "{option} {x},{y} lies outside the {}x{} image",
            camera.width,
            camera.height
        );
    }
    path.focus_depth_at(camera, pixel)?.with_context(|| {
        format!("{option} {x},{y}: no surface at that pixel (it shows the background)")
    })
}

/// The camera-space points of the surfaces under `pixels` (their centres) of `camera`.
pub fn surface_points(
    path: &mut dyn RenderPath,
    camera: &Camera,
    pixels: [[u32; 2]; 3],
) -> Result<[DVec3; 3]> {
    let mut points = [DVec3::ZERO; 3];
    for (point, pixel) in points.iter_mut().zip(pixels) {
        let z = focus_depth_at(path, camera, pixel, "--focus-plane")?;
        *point = pixel_point(camera, pixel, z).as_dvec3();
    }
    Ok(points)
}

/// The camera-space point at view depth `z` under the centre of `pixel` of `camera` (on its
/// aperture-centre ray): where a picked surface lies.
pub fn pixel_point(camera: &Camera, pixel: [u32; 2], z: f32) -> Vec3 {
    let centre = Vec2::new(pixel[0] as f32 + 0.5, pixel[1] as f32 + 0.5);
    camera.camera_point(centre, z)
}

/// Lays the plane of focus through the surfaces under `settings`' three focus-plane pixels,
/// seen by `shot`'s camera: sets focus distance, tilt and tilt direction in `settings` (the
/// pixels dropped), prints them with the options that reproduce them, and returns the shot
/// `resolve` makes of the new settings.
pub fn lay_focus_plane(
    path: &mut dyn RenderPath,
    settings: &mut Settings,
    shot: &Shot,
    resolve: &dyn Fn(&Settings) -> Result<Shot>,
) -> Result<Shot> {
    let pixels = settings
        .camera
        .focus_plane
        .take()
        .context("no focus plane to lay")?;
    let points = surface_points(path, &shot.camera, pixels)?;
    let plane = FocusPlane::through(points, tilt_model(&settings.camera, &shot.camera))
        .map_err(|e| anyhow::anyhow!("--focus-plane: {e}"))?;
    apply(settings, &plane);
    let resolved = resolve(settings)?;
    let miss = plane_miss(&resolved.camera, &points);
    eprintln!(
        "focus plane: {}; it passes within {miss:.2e} of the three points",
        describe(&plane)
    );
    Ok(resolved)
}

/// `plane`'s focus distance, tilt and tilt direction in `settings`.
pub fn apply(settings: &mut Settings, plane: &FocusPlane) {
    let c = &mut settings.camera;
    c.focus_distance = Some(plane.focus_distance);
    c.tilt = Some(plane.tilt_degrees);
    c.tilt_direction = Some(plane.tilt_direction_degrees);
    c.focus_plane = None;
}

/// The plane in words, with the options that lay it.
pub fn describe(plane: &FocusPlane) -> String {
    let FocusPlane {
        focus_distance: d,
        tilt_degrees: t,
        tilt_direction_degrees: a,
    } = plane;
    format!(
        "focus distance {d:.4}, tilt {t:.3} deg, tilt direction {a:.2} deg \
         (--focus-distance {d:.6} --tilt {t:.6} --tilt-direction {a:.4})"
    )
}

/// The largest distance (world units) from `points` (camera space) to `camera`'s plane of
/// focus.
pub fn plane_miss(camera: &Camera, points: &[DVec3; 3]) -> f64 {
    let lens = camera.lens.first_order();
    let normal = lens.focus_tilt.as_dvec2().extend(1.0);
    points
        .iter()
        .map(|p| (normal.dot(*p) - f64::from(lens.focus_distance)).abs() / normal.length())
        .fold(0.0, f64::max)
}
