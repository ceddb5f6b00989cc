//! The raster path (docs/raster.md): with the same lens samples per pass, accumulation-buffer
//! depth of field is the same estimator as tracing every sample, so `raster` renders the image
//! of `rayquery` (software where the device has no ray queries) with shared samples, unlit
//! exactly up to the pixels where the rasterizer and the ray-triangle test disagree on an edge.

mod gpu_support;

use gpu_support::{
    compare, moved_camera, render_path, settings, traced_path, write_comparison, MOVED,
};
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::{Camera, LensParams, Movements};
use lensray_core::film::Image;
use lensray_core::settings::{RenderSettings, Shading, Shot};

fn blurred_shot(orthographic: bool, movements: Movements) -> Camera {
    moved_camera(
        orthographic,
        LensParams::ThinLens {
            aperture_radius: 0.12,
            focus_distance: 5.0,
        },
        96,
        72,
        movements,
    )
}

/// The traced path the raster path traces its shadow rays with, and its image of `shot`.
fn traced(test: &str, shot: &Shot) -> Option<(PathChoice, Image)> {
    let choice = PathChoice::Only(traced_path(test)?);
    Some((choice, render_path(test, choice, shot)?))
}

/// `raster` against the traced path with `shared_samples`: at most `max_differing` of the
/// pixels differ by more than `tolerance`, and the mean |difference| stays under `max_mean`.
fn matches_traced(test: &str, orthographic: bool, shading: Shading, bounds: (f32, f64, f64)) {
    matches_traced_with(test, orthographic, shading, bounds, Movements::NONE);
}

/// [`matches_traced`] with the camera moved by `movements`.
fn matches_traced_with(
    test: &str,
    orthographic: bool,
    shading: Shading,
    bounds: (f32, f64, f64),
    movements: Movements,
) {
    let (tolerance, max_differing, max_mean) = bounds;
    let shot = Shot {
        camera: blurred_shot(orthographic, movements),
        render: RenderSettings {
            shared_samples: true,
            ..settings(shading, 8)
        },
    };
    let Some(raster) = render_path(test, PathChoice::Only(PathKind::Raster), &shot) else {
        return;
    };
    let Some((choice, traced)) = traced(test, &shot) else {
        return;
    };
    let diff = compare(&raster, &traced, tolerance);
    println!("{test}: raster vs {choice}: {diff:?}");
    if 1.0 - diff.within > max_differing || diff.mean_abs > max_mean {
        let files = write_comparison(&raster, &traced, test);
        panic!(
            "{test}: raster differs from {choice} with the same lens samples: {:.3} % of the \
             pixels beyond {tolerance} (bound {:.3} %), mean |diff| {:.2e} (bound {max_mean:.0e}); \
             wrote {files}",
            100.0 * (1.0 - diff.within),
            100.0 * max_differing,
            diff.mean_abs
        );
    }
    // Without shared samples the raster path is the same: it always shares them.
    let own = Shot {
        camera: shot.camera,
        render: RenderSettings {
            shared_samples: false,
            ..shot.render
        },
    };
    let Some(again) = render_path(test, PathChoice::Only(PathKind::Raster), &own) else {
        return;
    };
    assert_eq!(
        again, raster,
        "{test}: the raster path always shares samples"
    );
}

/// Unlit, the value of a sample is the colour of the first surface its lens ray meets: equal
/// wherever the rasterizer and the traversal pick the same triangle.
#[test]
fn raster_equals_rayquery_unlit_perspective() {
    matches_traced(
        "raster_equals_rayquery_unlit_perspective",
        false,
        Shading::Unlit,
        (1e-6, 0.005, 2e-4),
    );
}

#[test]
fn raster_equals_rayquery_unlit_orthographic() {
    matches_traced(
        "raster_equals_rayquery_unlit_orthographic",
        true,
        Shading::Unlit,
        (1e-6, 0.005, 2e-4),
    );
}

/// Lit, the hit point comes from the ray and the rasterized triangle's plane instead of the
/// traversal's hit: equal within float rounding, except where a shadow ray grazes an edge.
#[test]
fn raster_matches_rayquery_lit() {
    matches_traced(
        "raster_matches_rayquery_lit",
        false,
        Shading::Lit,
        (1e-3, 0.01, 5e-4),
    );
}

/// Shifted and tilted, rays from one lens point through the tilted plane of focus are still a
/// projective map of the scene: the sheared projection (`ThinLens::pinhole_from_camera`) with
/// its tilt terms rasterizes what the lens rays see, perspective and orthographic.
#[test]
fn raster_equals_rayquery_shifted_and_tilted() {
    for orthographic in [false, true] {
        matches_traced_with(
            &format!("raster_equals_rayquery_shifted_and_tilted_ortho_{orthographic}"),
            orthographic,
            Shading::Unlit,
            (1e-6, 0.005, 2e-4),
            MOVED,
        );
    }
}
