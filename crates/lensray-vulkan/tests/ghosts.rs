//! A real lens's ghosts traced and drawn on the device (shaders/passes/ghosts.comp) against
//! lensray-core's `FlareLens::distant_source` on the CPU, validation on (tests/renderer.rs says
//! how a machine without a device skips): double-gauss-50 at f/8, round and with seven blades,
//! a source 10 degrees off the axis at three wavelengths, 48 x 48 cells on 0.25 mm bins.
//!
//! The device traces in f32 and sums in fixed point, the CPU in f64: a bin that a triangle's
//! edge grazes may fall in or out, so the bound is on the whole film, per wavelength: the sum
//! of |GPU - CPU| over the bins within 0.5 % of the CPU's light, ghosts and direct apart, and
//! the totals within 0.05 % (measured: 0.08 % and 0.012 % at worst).

mod support;

use std::sync::Arc;

use glam::Vec3;
use lensray_core::camera::aperture::ApertureShape;
use lensray_core::camera::flare::ghosts::{FilmBins, FlareLens};
use lensray_core::camera::{
    Camera, CameraParams, LensParams, Movements, ProjectionParams, RealLensParams,
};
use lensray_core::optics::builtin;
use lensray_vulkan::GhostRequest;

use support::*;

fn camera(blades: Option<u32>) -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, 1.2, 0.0),
        target: Vec3::new(0.0, 1.2, -10.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 45.0 },
        lens: LensParams::Real(RealLensParams {
            prescription: Arc::new(builtin::lens("double-gauss-50").expect("built in")),
            f_number: Some(8.0),
            focus_distance: 12.0,
            sensor_height_mm: 24.0,
            dispersion: true,
            movements: Movements::NONE,
        }),
        near: 0.05,
        far: 100.0,
        width: 240,
        height: 136,
        movements: Movements::NONE,
    }
    .build()
    .expect("a camera")
    .with_aperture(
        ApertureShape {
            blades,
            rotation_degrees: 10.0,
            ..ApertureShape::ROUND
        }
        .build()
        .expect("an aperture"),
    )
    .expect("the stop takes the shape")
}

#[test]
fn gpu_ghosts_match_the_cpu_s() {
    let test = "gpu_ghosts_match_the_cpu_s";
    let Some((gpu, log)) = renderer(test) else {
        return;
    };
    let wavelengths = [610.0, 550.0, 465.0];
    let request = GhostRequest {
        degrees: 10.0,
        wavelengths_nm: &wavelengths,
        grid: 48,
        bins: FilmBins {
            columns: 160,
            rows: 120,
            bin_mm: 0.25,
        },
    };
    for blades in [None, Some(7)] {
        let camera = camera(blades);
        let real = camera.lens.real().expect("a real lens");
        let lens = FlareLens::of(real);
        let cpu = lens.distant_source(
            request.degrees,
            request.wavelengths_nm,
            request.grid,
            request.bins,
        );
        let device = gpu.ghost_light(&camera, &lens, &request).expect("ghosts");
        for (w, lambda) in wavelengths.iter().enumerate() {
            for (what, a, b) in [
                ("ghosts", &device.ghosts[w], &cpu.ghosts[w]),
                ("direct", &device.direct[w], &cpu.direct[w]),
            ] {
                let total: f64 = b.iter().sum();
                let device_total: f64 = a.iter().sum();
                let off: f64 = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum();
                println!(
                    "{blades:?} blades, {} nm, {what}: CPU {total:.5e}, GPU {device_total:.5e} ({:+.3} %), |GPU - CPU| {:.3} % of it",
                    lambda,
                    100.0 * (device_total / total - 1.0),
                    100.0 * off / total
                );
                assert!(total > 0.0, "{what}: no light");
                assert!(
                    off < 0.005 * total,
                    "{what} at {lambda} nm: off by {off} of {total}"
                );
                assert!(
                    (device_total / total - 1.0).abs() < 0.0005,
                    "{what} at {lambda} nm: {device_total} against {total}"
                );
            }
        }
    }
    finish(gpu, log);
}
