//! The `C` key: the current camera as text, so the shot can be rendered headless. Three forms:
//! the scene-file tables (`[camera]`, `[image]`, `[render]`, `[light]`), the equivalent
//! `lensray render` command, and a `[[keyframe]]` table for a sequence ([`keyframe_table`]). Every value is explicit, including what `settings::shot` derived
//! (near, far, the light), so later changes to defaults cannot change the shot; numbers are
//! printed in Rust's shortest round-trip form, so they read back to the same bits. A scene in
//! units other than metres gets its lengths in those units, as its files and command line give
//! them (reading back to the same camera to within rounding).

use std::fmt::Write;
use std::path::Path;

use glam::Vec3;

use lensray_core::camera::Projection;
use lensray_core::scene::units::SceneUnits;
use lensray_core::settings::EnvironmentSetting;
use lensray_core::settings::{
    CameraSettings, ImageSettings, LightType, ProjectionKind, RenderStyle, Settings,
};
use lensray_core::settings::{
    Shot, DEFAULT_F_NUMBER, DEFAULT_SENSOR_HEIGHT_MM, DEFAULT_VFOV_DEGREES,
};

mod keyframe;

pub use keyframe::keyframe_table;

/// The two printouts of one camera.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraSnippet {
    /// Scene-file tables, to paste after a file's `mesh = ...` line.
    pub toml: String,
    /// One `lensray render ...` line.
    pub command: String,
}

impl std::fmt::Display for CameraSnippet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "# scene file:\n{}\n# command line:\n{}\n",
            self.toml, self.command
        )
    }
}

/// The snippet of the camera `settings` (in metres) resolved to (`resolved` is what
/// `shot(settings)` returned), its lengths in the scene's `units`. The command names `--scene`
/// only when `scene` is given, and `--scene-units` when the units are not metres.
pub fn camera_snippet(
    settings: &Settings,
    resolved: &Shot,
    scene: Option<&Path>,
    units: SceneUnits,
) -> CameraSnippet {
    let mut explicit = explicit_settings(settings, resolved);
    let mut toml = String::new();
    if units != SceneUnits::M {
        explicit = explicit.scaled(1.0 / units.metres());
        // The tables belong in a file that gives its units (a top-level key, above them).
        toml = format!("# lengths in {units}: for a scene file with units = \"{units}\"\n");
    }
    toml += &toml::to_string(&explicit).expect("settings serialize to TOML");
    CameraSnippet {
        toml,
        command: render_command(&explicit, scene, units),
    }
}

fn array(v: Vec3) -> [f64; 3] {
    v.as_dvec3().to_array()
}

/// `settings` with every value `settings::shot` filled in written out. Values the user gave stay
/// as given (f64); derived ones come from the resolved f32 values, which convert back exactly. Only
/// the projection's own size is written (`--vfov` and `--ortho-height` exclude each other).
pub fn explicit_settings(settings: &Settings, resolved: &Shot) -> Settings {
    let (camera, render) = (&resolved.camera, &resolved.render);
    let c = &settings.camera;
    let physical = c.focal_length_mm.is_some();
    let real = camera.lens.real();
    // A pinhole without a focus resolves to `LensParams::Pinhole`: writing a focus would change
    // its (unused) focus distance, so it is written only when the lens has one.
    let has_lens =
        physical || real.is_some() || c.aperture_radius.is_some() || c.focus_distance.is_some();
    let (projection, vfov_degrees, ortho_height) = match camera.projection {
        // A real lens's field follows from the lens and the film.
        Projection::Perspective { .. } if real.is_some() => {
            (ProjectionKind::Perspective, None, None)
        }
        Projection::Perspective { .. } => (
            ProjectionKind::Perspective,
            Some(c.vfov_degrees.unwrap_or(DEFAULT_VFOV_DEGREES)),
            None,
        ),
        Projection::Orthographic { height } => (
            ProjectionKind::Orthographic,
            None,
            Some(c.ortho_height.unwrap_or(height as f64)),
        ),
    };
    let eye = c.eye.unwrap_or(array(camera.frame.eye));
    Settings {
        camera: CameraSettings {
            projection: Some(projection),
            eye: Some(eye),
            // Without a target given, any point on the view axis frames the same view.
            target: c
                .target
                .or(Some(array(camera.frame.eye + camera.frame.forward))),
            up: Some(c.up.unwrap_or([0.0, 1.0, 0.0])),
            vfov_degrees,
            ortho_height,
            aperture_radius: (!physical && real.is_none() && has_lens)
                .then(|| c.aperture_radius.unwrap_or(0.0)),
            focus_distance: has_lens.then(|| {
                c.focus_distance
                    .unwrap_or(camera.lens.first_order().focus_distance as f64)
            }),
            focal_length_mm: c.focal_length_mm,
            f_number: match real {
                Some(real) => Some(c.f_number.unwrap_or(real.f_number)),
                None if physical => Some(c.f_number.unwrap_or(DEFAULT_F_NUMBER)),
                // A pinhole's f-number given with a shutter time: the exposure's.
                None => c.exposure.shutter.and(c.f_number),
            },
            sensor_height_mm: (physical || real.is_some())
                .then(|| c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM)),
            near: Some(c.near.unwrap_or(camera.near as f64)),
            far: Some(c.far.unwrap_or(camera.far as f64)),
            shift: c.shift,
            tilt: c.tilt,
            tilt_direction: c.tilt_direction,
            focus_plane: None,
            // The shape as given: what is left out is the round aperture's default.
            aperture: c.aperture.clone(),
            lens: c.lens.clone(),
            // Exposure and tone map as given (the panel's too).
            exposure: c.exposure.clone(),
            // Motion blur and rolling shutter as given.
            shutter: c.shutter.clone(),
        },
        image: ImageSettings {
            width: Some(camera.width),
            height: Some(camera.height),
            spp: Some(render.spp),
            seed: Some(render.seed),
            sampler: Some(render.sampler),
            fps: settings.image.fps,
        },
        render: RenderStyle {
            shading: Some(render.shading),
            background: Some(
                settings
                    .render
                    .background
                    .unwrap_or(array(render.background)),
            ),
            environment: settings.render.environment.clone(),
            environment_rotation: settings.render.environment_rotation,
            environment_intensity: settings.render.environment_intensity,
            bounces: settings.render.bounces,
            noise_threshold: settings.render.noise_threshold,
        },
        // The rig pins its lights (`pinned_lights`): every default is written out.
        light: settings.light.clone(),
    }
}

fn triple(v: [f64; 3]) -> String {
    format!("{},{},{}", v[0], v[1], v[2])
}

/// A word the shell passes through unchanged: as is when it is plain, else single-quoted.
pub fn shell_word(text: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-./,=:+@%".contains(c);
    if !text.is_empty() && text.chars().all(plain) {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

/// The `lensray render` options (`cli::args::ViewArgs`) for every value `settings` sets, with
/// `--scene-units` for units other than metres.
pub fn render_command(settings: &Settings, scene: Option<&Path>, units: SceneUnits) -> String {
    let mut line = String::from("lensray render");
    let mut option = |name: &str, value: Option<String>| {
        if let Some(value) = value {
            let _ = write!(line, " --{name} {value}");
        }
    };
    option("scene", scene.map(|p| shell_word(&p.display().to_string())));
    option(
        "scene-units",
        (units != SceneUnits::M).then(|| units.to_string()),
    );
    let (c, i, r, l) = (
        &settings.camera,
        &settings.image,
        &settings.render,
        &settings.light,
    );
    option("projection", c.projection.map(|p| p.name().to_string()));
    option("eye", c.eye.map(triple));
    option("target", c.target.map(triple));
    option("up", c.up.map(triple));
    let number = |x: Option<f64>| x.map(|x| x.to_string());
    option("vfov", number(c.vfov_degrees));
    option("ortho-height", number(c.ortho_height));
    option("lens", c.lens.prescription.as_deref().map(shell_word));
    option(
        "dispersion",
        c.lens.dispersion.map(|d| d.name().to_string()),
    );
    option("aperture-radius", number(c.aperture_radius));
    option("focal-length-mm", number(c.focal_length_mm));
    option("f-number", number(c.f_number));
    option("sensor-height-mm", number(c.sensor_height_mm));
    option("focus-distance", number(c.focus_distance));
    option("shift", c.shift.map(|[x, y]| format!("{x},{y}")));
    option("tilt", number(c.tilt));
    option("tilt-direction", number(c.tilt_direction));
    let a = &c.aperture;
    option("aperture-blades", a.blades.map(|x| x.to_string()));
    option("aperture-rotation", number(a.rotation));
    option("aperture-roundness", number(a.roundness));
    option("aperture-aspect", number(a.aspect));
    option(
        "aperture-image",
        a.image
            .as_ref()
            .map(|p| shell_word(&p.display().to_string())),
    );
    let e = &c.exposure;
    option("exposure", number(e.ev));
    option("iso", number(e.iso));
    option("shutter", number(e.shutter));
    option("tonemap", e.tonemap.map(|t| t.name().to_string()));
    option("near", number(c.near));
    option("far", number(c.far));
    option("width", i.width.map(|x| x.to_string()));
    option("height", i.height.map(|x| x.to_string()));
    option("spp", i.spp.map(|x| x.to_string()));
    option("seed", i.seed.map(|x| x.to_string()));
    option("sampler", i.sampler.map(|s| s.name().to_string()));
    option("fps", number(i.fps));
    option("shading", r.shading.map(|s| s.name().to_string()));
    option("background", r.background.map(triple));
    option(
        "environment",
        r.environment.as_ref().map(|e| match e {
            EnvironmentSetting::Sky(c) => triple(*c),
            EnvironmentSetting::Map(path) => shell_word(&path.to_string_lossy()),
        }),
    );
    option("environment-rotation", number(r.environment_rotation));
    option("environment-intensity", number(r.environment_intensity));
    option("bounces", r.bounces.map(|b| b.to_string()));
    // The command line gives one point light; other lights need the scene file's tables.
    if let [light] = l.0.as_slice() {
        if light.kind.unwrap_or_default() == LightType::Point && light.range.is_none() {
            option("light-position", light.position.map(triple));
            option("light-intensity", light.intensity.map(triple));
        }
    }
    if c.exposure.expose_exr == Some(true) {
        line.push_str(" --expose-exr");
    }
    line
}

#[cfg(test)]
mod tests;
