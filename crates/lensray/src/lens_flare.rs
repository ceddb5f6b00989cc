//! The lens's own light on a rendered image (`--flare`, `--starburst`; `camera::flare` draws
//! it): what a shot asks for, refused in one line where it cannot be drawn, and the punctual
//! lights in view. `render` (a still or a sequence's frames) adds it to whatever path rendered
//! the image, before the image is exposed, traced on that path's device.

use anyhow::{bail, Result};
use glam::Vec3;

use crate::paths::RenderPath;
use lensray_core::camera::flare::ghosts::FlareLens;
use lensray_core::camera::flare::{Flare, FlareSwitches, PointSource};
use lensray_core::camera::Camera;
use lensray_core::film::Image;
use lensray_core::scene::Light;
use lensray_core::settings::{Settings, Shot, Switch};
use lensray_vulkan::GhostRequest;

/// What `settings` ask the flare to draw.
pub fn switches(settings: &Settings) -> FlareSwitches {
    let lens = &settings.camera.lens;
    FlareSwitches {
        ghosts: lens.flare == Some(Switch::On),
        starburst: lens.starburst == Some(Switch::On),
    }
}

/// The flare `settings` ask of `shot`, `None` where they ask none; an error where the shot
/// cannot have one.
pub fn flare_for(settings: &Settings, shot: &Shot) -> Result<Option<Flare>> {
    flare_of(switches(settings), shot)
}

/// The flare `switches` ask of `shot`, as [`flare_for`].
pub fn flare_of(switches: FlareSwitches, shot: &Shot) -> Result<Option<Flare>> {
    if !(switches.ghosts || switches.starburst) {
        return Ok(None);
    }
    let Some(real) = shot.camera.lens.real() else {
        bail!(
            "--flare and --starburst trace a real lens's surfaces and stop: name one with --lens (a scene file: [camera.lens])"
        );
    };
    if shot.render.shading.is_aov() {
        bail!(
            "--flare and --starburst add light to a rendered image: the {} shading has none",
            shot.render.shading.name()
        );
    }
    if real.film().normal != Vec3::Z {
        bail!("--flare and --starburst follow a lens square to its film: this one tilts (--tilt)");
    }
    let camera = &shot.camera;
    Ok(Some(Flare::new(
        real,
        switches,
        camera.width,
        camera.height,
    )))
}

/// The punctual lights ahead of `camera` (in camera space, with the light each gives the lens).
pub fn point_sources(lights: &[Light], camera: &Camera) -> Vec<PointSource> {
    let eye = camera.world_from_camera.transform_point3(Vec3::ZERO);
    lights
        .iter()
        .filter_map(|light| {
            let incident = light.incident(eye)?;
            let direction = camera
                .camera_from_world
                .transform_vector3(incident.direction)
                .normalize_or_zero();
            (direction.z > 0.0 && incident.irradiance.max_element() > 0.0).then_some(PointSource {
                direction,
                irradiance: incident.irradiance,
            })
        })
        .collect()
}

/// Adds `flare` to `image`, rendered of `shot` with `lights` on `path`, under `exposure`'s
/// scale. A GPU path traces and draws the ghosts on its device (shaders/passes/ghosts.comp),
/// the CPU path on the CPU.
pub fn add(
    flare: &Flare,
    (image, exposure): (&mut Image, f32),
    shot: &Shot,
    lights: &[Light],
    path: &mut dyn RenderPath,
) -> Result<()> {
    let points = point_sources(lights, &shot.camera);
    let mut trace = |lens: &FlareLens, degrees, wavelengths: &[f64], grid, bins| {
        let request = GhostRequest::new(degrees, wavelengths, grid, bins);
        path.ghost_light(&shot.camera, lens, &request)
            .unwrap_or_else(|| Ok(lens.distant_source(degrees, wavelengths, grid, bins)))
    };
    flare.apply_traced(image, exposure, &points, &mut trace)
}
