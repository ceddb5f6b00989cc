//! A generated photographic studio as an environment map: a dim room, three softboxes (key,
//! fill and a strip behind) and a row of small bright practical lamps, whose reflections in
//! glossy surfaces turn into bokeh out of focus. lensray's own work (`lensray generate
//! environment`), so the repository's map carries no third party's licence.

use std::path::Path;

use glam::{Vec2, Vec3};

use super::{map_direction, EnvironmentMap};

/// A rectangle of the sky in degrees (azimuth from -Z towards +X, elevation above the horizon)
/// and its radiance.
struct Softbox {
    azimuth: f32,
    elevation: f32,
    half_width: f32,
    half_height: f32,
    radiance: Vec3,
}

const SOFTBOXES: [Softbox; 3] = [
    // Key: large, warm, front left and above.
    Softbox {
        azimuth: -45.0,
        elevation: 35.0,
        half_width: 14.0,
        half_height: 10.0,
        radiance: Vec3::new(30.0, 27.0, 24.0),
    },
    // Fill: tall, cool, front right.
    Softbox {
        azimuth: 60.0,
        elevation: 15.0,
        half_width: 9.0,
        half_height: 18.0,
        radiance: Vec3::new(5.0, 6.0, 7.5),
    },
    // Strip behind: a rim light.
    Softbox {
        azimuth: 180.0,
        elevation: 45.0,
        half_width: 30.0,
        half_height: 4.0,
        radiance: Vec3::new(16.0, 16.0, 16.0),
    },
];

/// Azimuths of the practical lamps (degrees), all at 8 degrees above the horizon.
const LAMP_AZIMUTHS: [f32; 7] = [-150.0, -110.0, -75.0, 20.0, 95.0, 130.0, 165.0];
/// Angular radius of a lamp (degrees) and its radiance.
const LAMP_RADIUS: f32 = 1.2;
const LAMP_RADIANCE: Vec3 = Vec3::new(400.0, 330.0, 250.0);

/// The studio at `width` x `width / 2` texels (each texel its centre's value).
pub fn studio(width: u32) -> EnvironmentMap {
    let height = (width / 2).max(1);
    let mut texels = Vec::with_capacity((width * height) as usize);
    for row in 0..height {
        for column in 0..width {
            let uv = Vec2::new(
                (column as f32 + 0.5) / width as f32,
                (row as f32 + 0.5) / height as f32,
            );
            texels.push(studio_radiance(map_direction(uv)));
        }
    }
    EnvironmentMap::new(width, height, texels).expect("sizes agree")
}

/// The studio's radiance towards `d` (unit).
fn studio_radiance(d: Vec3) -> Vec3 {
    let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
    let azimuth = d.x.atan2(-d.z).to_degrees();
    for softbox in &SOFTBOXES {
        let da = wrap_degrees(azimuth - softbox.azimuth).abs();
        if da <= softbox.half_width && (elevation - softbox.elevation).abs() <= softbox.half_height
        {
            return softbox.radiance;
        }
    }
    for lamp in LAMP_AZIMUTHS {
        let centre = direction(lamp, 8.0);
        if d.dot(centre).clamp(-1.0, 1.0).acos().to_degrees() <= LAMP_RADIUS {
            return LAMP_RADIANCE;
        }
    }
    if elevation < 0.0 {
        // A grey floor, darker towards the nadir.
        Vec3::splat(0.05 + 0.04 * (1.0 + elevation / 90.0))
    } else {
        // Walls and ceiling, a little brighter up high.
        Vec3::new(0.08, 0.085, 0.095) * (1.0 + elevation / 90.0)
    }
}

/// The unit direction at `azimuth` and `elevation` (degrees).
pub fn direction(azimuth: f32, elevation: f32) -> Vec3 {
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    Vec3::new(e.cos() * a.sin(), e.sin(), -e.cos() * a.cos())
}

/// `degrees` in (-180, 180].
fn wrap_degrees(degrees: f32) -> f32 {
    let wrapped = (degrees + 180.0).rem_euclid(360.0) - 180.0;
    if wrapped == -180.0 {
        180.0
    } else {
        wrapped
    }
}

/// Writes `map` as a Radiance RGBE file (`.hdr`) or OpenEXR (`.exr`), by the extension.
pub fn write_environment(map: &EnvironmentMap, path: &Path) -> Result<(), String> {
    let floats: Vec<f32> = map.texels.iter().flat_map(|t| t.to_array()).collect();
    let image = image::Rgb32FImage::from_raw(map.width, map.height, floats)
        .ok_or_else(|| "the texels do not fill the image".to_string())?;
    image::DynamicImage::ImageRgb32F(image)
        .save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}
