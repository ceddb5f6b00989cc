//! The camera and its lens as the shaders read them: matrices, projection, the aperture's fan,
//! a real lens's surfaces and pupil tables, the spectral tables.

use super::*;

/// `Camera.projection` / `ViewParams.projection` of the shaders.
pub(crate) fn projection_code(camera: &Camera) -> u32 {
    match camera.projection {
        Projection::Perspective { .. } => PROJECTION_PERSPECTIVE,
        Projection::Orthographic { .. } => PROJECTION_ORTHOGRAPHIC,
    }
}

/// The camera as the shaders read it (matrices, projection, thin lens and aperture).
pub(crate) fn gpu_camera(camera: &Camera) -> GpuCamera {
    let lens = camera.lens.first_order();
    let image = lens.aperture.image();
    let turn = lens.aperture.turn();
    GpuCamera {
        // glam and GLSL are both column-major.
        world_from_camera: camera.world_from_camera.to_cols_array(),
        screen_from_raster: camera.screen_from_raster.to_cols_array(),
        projection: projection_code(camera),
        near_z: camera.near,
        aperture_radius: lens.aperture_radius,
        focus_distance: lens.focus_distance,
        aperture_fan_len: lens.aperture.fan().len() as u32,
        aperture_aspect: lens.aperture.shape.aspect,
        aperture_image_columns: image.map_or(0, |i| i.columns()),
        aperture_image_rows: image.map_or(0, |i| i.rows()),
        aperture_turn: [turn.x, turn.y, 0.0, 0.0],
        focus_tilt: [lens.focus_tilt.x, lens.focus_tilt.y, 0.0, 0.0],
        aperture_fan: aperture_fan(lens.aperture.fan()),
        ..motion(camera)
    }
}

/// The camera's motion over the shutter (`Camera.motion_*`; zeros while it is still).
fn motion(camera: &Camera) -> GpuCamera {
    let mut out = GpuCamera::zeroed();
    let Some(motion) = &camera.motion else {
        return out;
    };
    out.motion_steps = motion.poses.len() as u32;
    out.motion_exposure_share = motion.exposure_share;
    out.motion_rolling_share = motion.rolling_share;
    out.motion_height = camera.height as f32;
    for (i, pose) in motion.poses.iter().enumerate() {
        out.motion_eye[i] = pose.eye.extend(0.0).to_array();
        out.motion_rotation[i] = pose.rotation.to_array();
    }
    out
}

// The block holds every pose of a moving camera.
const _: () = assert!(lensray_core::interface::MOTION_STEPS == 8);

/// The fan's vertices, two per vec4 (`Camera.aperture_fan`), zeros after the last.
fn aperture_fan(fan: &[glam::Vec2]) -> [[f32; 4]; APERTURE_MAX_FAN as usize / 2] {
    let mut out = [[0.0; 4]; APERTURE_MAX_FAN as usize / 2];
    for (i, v) in fan.iter().enumerate() {
        out[i / 2][2 * (i % 2)] = v.x;
        out[i / 2][2 * (i % 2) + 1] = v.y;
    }
    out
}

/// No real lens: the shaders trace the thin lens. The block holds the sheen's albedo table
/// whatever the lens.
pub(crate) fn thin_lens() -> GpuLens {
    let mut out = GpuLens::zeroed();
    for (i, &value) in lensray_core::interface::SHEEN_ALBEDO.iter().enumerate() {
        out.sheen_albedo[i / 4][i % 4] = value;
    }
    out
}

/// The real lens of `camera` as the shaders read it (`surface_count` 0: none); an error if
/// it has more surfaces than the GPU's block holds.
pub(crate) fn gpu_lens(camera: &Camera) -> Result<GpuLens, GpuError> {
    let mut out = thin_lens();
    let Some(real) = camera.lens.real() else {
        return Ok(out);
    };
    let interfaces = &real.elements().interfaces;
    if interfaces.len() > LENS_MAX_SURFACES as usize {
        return Err(GpuError::Invalid(format!(
            "lens {} has {} surfaces: the GPU paths trace at most {LENS_MAX_SURFACES}",
            real.name(),
            interfaces.len()
        )));
    }
    let (stop, stop_radius, _) = real.stop();
    let pupil = real.pupil();
    out.surface_count = interfaces.len() as u32;
    out.stop = stop as u32;
    out.stop_radius = stop_radius;
    out.film_z = real.film_z();
    out.entrance_pupil_z = real.entrance_pupil_z();
    // RealLens::film_point's arithmetic, done here once.
    out.film_mm_per_pixel = 2.0 * real.film_half_height() / camera.height as f32;
    let centre = real.raster_centre(camera.width, camera.height);
    out.raster_centre_x = centre.x;
    out.raster_centre_y = centre.y;
    out.rear_z = pupil.rear_z;
    out.film_radius = pupil.film_radius;
    let film = real.film();
    out.film_origin = film.origin.extend(pupil.axis_depth).to_array();
    out.film_right = film.right.extend(0.0).to_array();
    out.film_up = film.up.extend(0.0).to_array();
    out.film_normal = film.normal.extend(0.0).to_array();
    let turn = real.camera_from_lens_turn();
    out.camera_from_lens =
        [turn.x_axis, turn.y_axis, turn.z_axis].map(|c| c.extend(0.0).to_array());
    out.inverse_centre_integral = pupil.inverse_centre_integral;
    out.aperture_transmission_start = camera
        .lens
        .first_order()
        .aperture
        .image()
        .map_or(0, |image| image.table().len() as u32);
    out.dispersive = u32::from(real.dispersive());
    spectral_table(&mut out.spectral_table);
    for (i, s) in interfaces.iter().enumerate() {
        out.surface_shape[i] = [s.z, s.radius, s.aperture_radius, s.conic];
        out.surface_media[i] = [
            s.index_before,
            s.index_after,
            s.dispersion_before,
            s.dispersion_after,
        ];
        let a = s.coefficients;
        out.surface_asphere_low[i] = [a[0], a[1], a[2], a[3]];
        out.surface_asphere_high[i] = [a[4], a[5], a[6], a[7]];
        out.asphere_mask |= u32::from(s.asphere) << i;
    }
    for (i, bin) in pupil.bins.iter().enumerate() {
        let region = |r: &lensray_core::camera::real_lens::Region| {
            [r.centre.x, r.centre.y, r.half.x, r.half.y]
        };
        out.pupil_inner[i] = region(&bin.inner);
        out.pupil_outer[i] = region(&bin.outer);
    }
    Ok(out)
}

/// The SPECTRAL_* tables at their SPECTRAL_AT_* places, four floats a vec4.
fn spectral_table(out: &mut [[f32; 4]; 256]) {
    use lensray_core::interface::{
        SPECTRAL_AT_CDF, SPECTRAL_AT_INV_DENSITY, SPECTRAL_AT_INV_PROBABILITY, SPECTRAL_AT_WEIGHTS,
        SPECTRAL_CDF, SPECTRAL_INV_DENSITY, SPECTRAL_INV_PROBABILITY, SPECTRAL_WEIGHTS,
    };
    let tables: [(u32, &[f32]); 4] = [
        (SPECTRAL_AT_WEIGHTS, &SPECTRAL_WEIGHTS),
        (SPECTRAL_AT_CDF, &SPECTRAL_CDF),
        (SPECTRAL_AT_INV_PROBABILITY, &SPECTRAL_INV_PROBABILITY),
        (SPECTRAL_AT_INV_DENSITY, &SPECTRAL_INV_DENSITY),
    ];
    for (start, table) in tables {
        for (i, &value) in table.iter().enumerate() {
            let at = start as usize + i;
            out[at / 4][at % 4] = value;
        }
    }
}

const _: () = assert!(lensray_core::interface::SPECTRAL_AT_END as usize <= 4 * 256);

// The bins the Rust lens makes are the ones the GPU block holds.
const _: () = assert!(lensray_core::camera::real_lens::PUPIL_BINS == LENS_PUPIL_BINS as usize);

// The sheen's albedo table fills the GPU block's sheen_albedo.
const _: () = assert!(
    (lensray_core::interface::SHEEN_ALBEDO_SIZE * lensray_core::interface::SHEEN_ALBEDO_SIZE)
        as usize
        == 4 * 256
);
