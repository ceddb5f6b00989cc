//! Real lenses on the GPU (shaders/include/real_lens.glsl, the mirror of lensray-core/src/camera/real_lens
//! and lensray-core/src/optics/trace.rs): the probe traces the same film and lens samples as the CPU for
//! every built-in lens, wide open and stopped down, with round, bladed and image stops; and
//! the traced paths render what the CPU renders. Validation on; see lensray-vulkan's
//! tests/renderer.rs for skips.

mod gpu_support;

use std::sync::Arc;

use glam::{UVec2, Vec3};
use gpu_support::*;
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::RealLensParams;
use lensray_core::camera::{
    ApertureShape, Camera, CameraError, CameraParams, LensParams, Movements, ProjectionParams,
};
use lensray_core::optics::builtin;
use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::sampler::{camera_sample, hash_u32, SamplerKind};
use lensray_core::settings::{Shading, Shot};
use lensray_vulkan::ProbeQuery;

/// A real lens shifted (1, 1.5) mm and tilted 5 degrees toward 30 degrees: its film is not
/// square to the lens's axis (`real_lens::film`).
const LENS_MOVED: Movements = Movements {
    shift: [1.0, 1.5],
    tilt_degrees: 5.0,
    tilt_direction_degrees: 30.0,
};

fn moved_lens_camera(
    name: &str,
    f_number: Option<f64>,
    width: u32,
    height: u32,
    movements: Movements,
) -> Result<Camera, CameraError> {
    CameraParams {
        eye: Vec3::new(2.5, 2.2, 4.5),
        target: Vec3::new(0.0, 0.5, 0.0),
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 45.0 },
        lens: LensParams::Real(RealLensParams {
            prescription: Arc::new(builtin::lens(name).expect("built in")),
            f_number,
            focus_distance: 5.5,
            sensor_height_mm: 24.0,
            dispersion: true,
            movements: Movements::NONE,
        }),
        near: 0.05,
        far: 50.0,
        width,
        height,
        movements,
    }
    .build()
}

/// The wavelengths the probe's rays are traced at: 0 the d line (as without dispersion), and
/// across the visible range.
const WAVELENGTHS_NM: [f32; 5] = [0.0, 400.0, 486.13, 587.56, 700.0];

/// Each lens's f-number, stop and movements in `real_lens_rays_match_the_cpu`: wide open and
/// at f/8, round, six blades and an image, and round moved.
fn ray_cases() -> Vec<(Option<f64>, ApertureShape, Movements)> {
    let hexagon = ApertureShape {
        blades: Some(6),
        rotation_degrees: 15.0,
        ..ApertureShape::ROUND
    };
    let mut cases = Vec::new();
    for f_number in [None, Some(8.0)] {
        for shape in [ApertureShape::ROUND, hexagon.clone(), odd_aperture_image()] {
            cases.push((f_number, shape, Movements::NONE));
        }
        cases.push((f_number, ApertureShape::ROUND, LENS_MOVED));
    }
    cases
}

/// The probe's rays through the lens against `Camera::generate_ray`, at several
/// wavelengths (through aspheres too), square to the film and moved (`LENS_MOVED`; where the
/// moved film leaves a lens's image circle, aspheric-31's, the camera is refused and skipped):
/// the same rays pass, with the same weights, origins and directions. The GPU's sqrt, division and
/// normalize may differ from Rust's in the last bit, so values are compared to 1e-5; a ray
/// grazing an opening may then pass on one side only, which is counted and bounded.
#[test]
fn real_lens_rays_match_the_cpu() {
    let Some((mut gpu, log)) = renderer("real_lens_rays_match_the_cpu") else {
        return;
    };
    let (mut checked, mut grazing, mut passed, mut worst) = (0usize, 0usize, 0usize, 0.0f32);
    let mut failures = Vec::new();
    let cases = ray_cases();
    for name in builtin::names() {
        for (f_number, shape, movements) in &cases {
            let (f_number, shape) = (*f_number, shape.clone());
            {
                let cam = match moved_lens_camera(name, f_number, 97, 61, *movements) {
                    Ok(cam) => cam,
                    Err(e @ CameraError::RealLens(_)) if *movements != Movements::NONE => {
                        println!("{name} f/{f_number:?} {movements:?}: skipped: {e}");
                        continue;
                    }
                    Err(e) => panic!("{name} f/{f_number:?} {movements:?}: {e}"),
                };
                let cam = cam
                    .with_aperture(shape.build().expect("valid aperture"))
                    .expect("the stop takes the shape");
                let queries: Vec<ProbeQuery> = (0..2048u32)
                    .map(|i| ProbeQuery {
                        seed: hash_u32(i / 64),
                        pixel_x: (i * 37) % cam.width,
                        pixel_y: (i / 7) % cam.height,
                        width: cam.width,
                        sample_index: i % 29,
                        dim: 0,
                        hash_input: i,
                        sampler_kind: SamplerKind::Sobol.id(),
                        wavelength_nm: WAVELENGTHS_NM[i as usize % WAVELENGTHS_NM.len()],
                    })
                    .collect();
                let results = gpu.probe_mirrors(&cam, &queries).expect("probe");
                for (q, r) in queries.iter().zip(&results) {
                    let cs = camera_sample(
                        SamplerKind::Sobol,
                        q.seed,
                        UVec2::new(q.pixel_x, q.pixel_y),
                        q.width,
                        q.sample_index,
                    );
                    checked += 1;
                    let wavelength = (q.wavelength_nm > 0.0).then_some(q.wavelength_nm);
                    let cpu = cam.generate_ray(cs, wavelength);
                    let gpu_weight = r.through_lens_origin[3];
                    match cpu {
                        None if gpu_weight < 0.0 => {}
                        Some((ray, weight)) if gpu_weight >= 0.0 => {
                            passed += 1;
                            let o = Vec3::from_slice(&r.through_lens_origin[..3]);
                            let d = Vec3::from_slice(&r.through_lens_direction[..3]);
                            let err = (o - ray.origin).length() / (1.0 + ray.origin.length())
                                + (d - ray.direction).length()
                                + (gpu_weight - weight).abs() / weight.max(1e-3);
                            worst = worst.max(err);
                            if err > 1e-5 {
                                failures.push(format!(
                                    "{name} f/{f_number:?} {:?} {movements:?}: {q:?}: CPU {ray:?} w {weight}, GPU {o} {d} w {gpu_weight}",
                                    shape.blades
                                ));
                            }
                        }
                        _ => grazing += 1,
                    }
                }
            }
        }
    }
    println!(
        "{checked} rays, {passed} passed on both sides, {grazing} passed on one side only, worst difference {worst:.2e}"
    );
    assert!(
        failures.is_empty(),
        "{} rays differ:\n{}",
        failures.len(),
        failures[..failures.len().min(8)].join("\n")
    );
    // A last-bit difference flips a ray only when it grazes an opening.
    assert!(
        grazing * 2000 <= checked,
        "{grazing} of {checked} rays pass on one side only"
    );
    assert!(
        passed * 2 > checked,
        "too few rays pass: {passed} of {checked}"
    );
    finish(gpu, log);
}

/// The traced paths render a real lens as the CPU does, square to the film and moved
/// (`LENS_MOVED`): the same rays, weights and shading.
#[test]
fn traced_paths_render_a_real_lens_as_the_cpu_does() {
    for movements in [Movements::NONE, LENS_MOVED] {
        render_real_lens_on_traced_paths(movements);
    }
}

fn render_real_lens_on_traced_paths(movements: Movements) {
    let shot = Shot {
        camera: moved_lens_camera("double-gauss-50", None, 48, 32, movements)
            .expect("a valid real-lens camera"),
        render: settings(Shading::Lit, 8),
    };
    let (cpu, _) = CpuRenderer::new(&test_scene()).render(&shot, &mut |_, _| {});
    for kind in [PathKind::RayQuery, PathKind::RtPipeline, PathKind::Software] {
        let test = format!("traced_paths_render_a_real_lens_as_the_cpu_does ({kind})");
        let Some(image) = render_path(&test, PathChoice::Only(kind), &shot) else {
            continue;
        };
        let diff = compare(&image, &cpu, 1e-3);
        println!("{kind}, {movements:?}: {diff:?}");
        assert!(
            diff.within > 0.995 && diff.mean_abs < 1e-4,
            "{kind} vs cpu through double-gauss-50, {movements:?}: {diff:?}; images: {}",
            write_comparison(&image, &cpu, &format!("real-lens-{kind}"))
        );
    }
}
