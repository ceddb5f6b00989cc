//! The length unit of a scene's files (`--scene-units`, a scene file's `units`). lensray works in
//! metres, the unit its physical lens data (focal length, sensor height, in millimetres) is
//! converted against, so a mesh modelled in millimetres seen through a 50 mm f/1.4 lens blurs as
//! a real one would only once it is scaled to metres. Every world length the user gives for a
//! scene is in its units: the mesh's positions, a glTF's cameras, the scene file's positions and
//! distances, and the command line's; they are all scaled to metres on loading. Directions,
//! angles, f-numbers, millimetre lens data and the light's intensity (W/sr, a per-steradian
//! quantity) do not depend on the unit of length and stay as given.

use std::fmt;

use serde::{Deserialize, Deserializer};

use super::file_camera::{FileCamera, FileProjection};
use super::Scene;
use crate::settings::Settings;

/// A unit of length for a scene's files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SceneUnits {
    /// Metres: lensray's own unit, and glTF's by its specification.
    #[default]
    M,
    Cm,
    Mm,
    /// Inches (25.4 mm).
    In,
}

impl SceneUnits {
    pub const ALL: [SceneUnits; 4] = [Self::M, Self::Cm, Self::Mm, Self::In];

    /// The length of one unit in metres.
    pub fn metres(self) -> f64 {
        match self {
            Self::M => 1.0,
            Self::Cm => 0.01,
            Self::Mm => 0.001,
            Self::In => 0.0254,
        }
    }

    /// The name `--scene-units` and `units` take.
    pub fn name(self) -> &'static str {
        match self {
            Self::M => "m",
            Self::Cm => "cm",
            Self::Mm => "mm",
            Self::In => "in",
        }
    }

    /// A unit by its name, in any case; the error names the accepted ones. (Not `FromStr`: its
    /// associated `Err` type would be a second type of that name in the workspace.)
    pub fn parse(text: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|u| u.name().eq_ignore_ascii_case(text.trim()))
            .ok_or_else(|| format!("`{text}` is not a unit of length: use m, cm, mm or in"))
    }
}

impl fmt::Display for SceneUnits {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl<'de> Deserialize<'de> for SceneUnits {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        Self::parse(&text).map_err(serde::de::Error::custom)
    }
}

impl Scene {
    /// Multiplies every position by `factor`. Normals stay: a uniform scale leaves every
    /// direction as it is.
    pub fn scale(&mut self, factor: f64) {
        let factor = factor as f32;
        for mesh in &mut self.meshes {
            for p in &mut mesh.positions {
                *p *= factor;
            }
        }
        for light in &mut self.lights {
            light.position *= factor;
            light.range *= factor;
        }
    }
}

impl FileCamera {
    /// This camera in a world scaled by `factor`: the same view of the scaled scene.
    pub fn scaled(&self, factor: f64) -> FileCamera {
        let projection = match self.projection {
            FileProjection::Perspective {
                yfov,
                aspect_ratio,
                znear,
                zfar,
            } => FileProjection::Perspective {
                yfov,
                aspect_ratio,
                znear: znear * factor,
                zfar: zfar.map(|z| z * factor),
            },
            FileProjection::Orthographic {
                xmag,
                ymag,
                znear,
                zfar,
            } => FileProjection::Orthographic {
                xmag: xmag * factor,
                ymag: ymag * factor,
                znear: znear * factor,
                zfar: zfar * factor,
            },
        };
        FileCamera {
            eye: self.eye * factor,
            projection,
            animation: self.animation.as_ref().map(|a| a.scaled(factor)),
            ..self.clone()
        }
    }
}

impl Settings {
    /// These settings with every world length multiplied by `factor`: the camera's eye, target,
    /// orthographic height, thin-lens aperture radius, focus distance and clip planes, and the
    /// light's position. The rest is not a world length (directions, angles, f-numbers, lens
    /// data in millimetres, the image, the light's intensity in W/sr) and stays.
    pub fn scaled(mut self, factor: f64) -> Settings {
        let c = &mut self.camera;
        let point = |p: &mut Option<[f64; 3]>| *p = p.map(|p| p.map(|x| x * factor));
        let length = |x: &mut Option<f64>| *x = x.map(|x| x * factor);
        point(&mut c.eye);
        point(&mut c.target);
        for light in &mut self.light.0 {
            point(&mut light.position);
            length(&mut light.range);
        }
        for x in [
            &mut c.ortho_height,
            &mut c.aperture_radius,
            &mut c.focus_distance,
            &mut c.near,
            &mut c.far,
        ] {
            length(x);
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, Vec3};

    use super::*;
    use crate::scene::Mesh;
    use crate::settings::{CameraSettings, LightSettings, Lights};

    #[test]
    fn units_parse_by_name_and_refuse_others_naming_the_accepted_ones() {
        for (text, units, metres) in [
            ("m", SceneUnits::M, 1.0),
            ("cm", SceneUnits::Cm, 0.01),
            ("MM", SceneUnits::Mm, 0.001),
            ("in", SceneUnits::In, 0.0254),
        ] {
            assert_eq!(SceneUnits::parse(text), Ok(units));
            assert_eq!(units.metres(), metres);
            assert_eq!(SceneUnits::parse(&units.to_string()), Ok(units));
        }
        let err = SceneUnits::parse("furlong").unwrap_err();
        assert!(!err.contains('\n'), "{err}");
        for name in ["furlong", "m,", "cm", "mm", "in"] {
            assert!(err.contains(name), "{err}");
        }
    }

    #[test]
    fn scaling_moves_positions_and_world_lengths_only() {
        let normal = Vec3::new(0.0, 0.6, 0.8);
        let mut scene = Scene::default();
        scene.meshes.push(Mesh {
            colours: Vec::new(),
            tangents: Vec::new(),
            positions: vec![Vec3::new(300.0, -20.0, 5.0), Vec3::ZERO, Vec3::X],
            normals: vec![normal; 3],
            triangles: vec![[0, 1, 2]],
            material_ids: vec![0],
            ..Mesh::default()
        });
        scene.scale(SceneUnits::Mm.metres());
        let mesh = &scene.meshes[0];
        assert!((mesh.positions[0] - Vec3::new(0.3, -0.02, 0.005)).length() < 1e-7);
        assert_eq!(mesh.positions[2], Vec3::new(0.001, 0.0, 0.0));
        assert_eq!(
            mesh.normals,
            vec![normal; 3],
            "a uniform scale keeps normals"
        );

        let settings = Settings {
            camera: CameraSettings {
                eye: Some([0.0, 100.0, 800.0]),
                target: Some([0.0, 100.0, 0.0]),
                up: Some([0.0, 1.0, 0.0]),
                vfov_degrees: Some(30.0),
                focus_distance: Some(800.0),
                aperture_radius: Some(10.0),
                near: Some(1.0),
                far: Some(5000.0),
                focal_length_mm: Some(50.0),
                f_number: Some(1.4),
                sensor_height_mm: Some(24.0),
                ..CameraSettings::default()
            },
            light: Lights(vec![LightSettings {
                position: Some([0.0, 1000.0, 0.0]),
                intensity: Some([5.0; 3]),
                range: Some(2000.0),
                ..LightSettings::default()
            }]),
            ..Settings::default()
        }
        .scaled(0.001);
        let c = &settings.camera;
        let close = |a: Option<f64>, b: f64| (a.unwrap() - b).abs() < 1e-12 * b.abs().max(1.0);
        let close3 =
            |a: Option<[f64; 3]>, b: [f64; 3]| (0..3).all(|i| close(a.map(|a| a[i]), b[i]));
        assert!(close3(c.eye, [0.0, 0.1, 0.8]), "{:?}", c.eye);
        assert!(close3(c.target, [0.0, 0.1, 0.0]), "{:?}", c.target);
        let light = &settings.light.0[0];
        assert!(close3(light.position, [0.0, 1.0, 0.0]) && close(light.range, 2.0));
        assert!(close(c.focus_distance, 0.8) && close(c.aperture_radius, 0.01));
        assert!(close(c.near, 0.001) && close(c.far, 5.0));
        // Not lengths of the world: as given.
        assert_eq!(c.up, Some([0.0, 1.0, 0.0]));
        assert_eq!(c.vfov_degrees, Some(30.0));
        assert_eq!(
            (c.focal_length_mm, c.f_number, c.sensor_height_mm),
            (Some(50.0), Some(1.4), Some(24.0))
        );
        assert_eq!(light.intensity, Some([5.0; 3]));
    }

    #[test]
    fn a_scaled_file_camera_frames_the_scaled_scene_alike() {
        let camera = FileCamera {
            name: "hero".into(),
            eye: DVec3::new(0.0, 50.0, 200.0),
            forward: DVec3::NEG_Z,
            up: DVec3::Y,
            projection: FileProjection::Orthographic {
                xmag: 40.0,
                ymag: 30.0,
                znear: 1.0,
                zfar: 400.0,
            },
            animation: None,
        };
        let scaled = camera.scaled(0.01);
        assert_eq!(scaled.eye, DVec3::new(0.0, 0.5, 2.0));
        assert_eq!((scaled.forward, scaled.up), (camera.forward, camera.up));
        assert_eq!(
            scaled.projection,
            FileProjection::Orthographic {
                xmag: 0.4,
                ymag: 0.3,
                znear: 0.01,
                zfar: 4.0
            }
        );
    }
}
