//! What lights a scene from afar (`--environment`, the scene file's `render.environment`): a
//! uniform sky's radiance or an equirectangular HDR map, turned by `environment_rotation`
//! degrees about +Y and scaled by `environment_intensity`. The map is loaded once a shot is
//! lit (`settings::light_scene`) into `Scene::environment`.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::{Settings, SettingsError};
use crate::scene::environment::EnvironmentMap;
use crate::scene::EnvironmentLight;

/// A uniform sky (linear RGB radiance) or an equirectangular map (`.hdr`, `.exr`).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum EnvironmentSetting {
    Sky([f64; 3]),
    Map(PathBuf),
}

impl EnvironmentSetting {
    /// Whether it gives light (a black sky does not).
    pub fn lights(&self) -> bool {
        match self {
            Self::Sky(c) => *c != [0.0; 3],
            Self::Map(_) => true,
        }
    }
}

/// The settings' `environment_intensity`, checked (default 1).
pub fn environment_intensity(settings: &Settings) -> Result<f32, SettingsError> {
    match settings.render.environment_intensity {
        None => Ok(1.0),
        Some(x) if x.is_finite() && x >= 0.0 => Ok(x as f32),
        Some(x) => Err(SettingsError::Environment(format!(
            "environment intensity must be finite and not negative, got {x}"
        ))),
    }
}

/// The settings' `environment_rotation` in degrees, checked (default 0).
fn environment_rotation(settings: &Settings) -> Result<f32, SettingsError> {
    match settings.render.environment_rotation {
        None => Ok(0.0),
        Some(x) if x.is_finite() => Ok(x as f32),
        Some(x) => Err(SettingsError::Environment(format!(
            "environment rotation must be finite, got {x}"
        ))),
    }
}

/// A map loaded for a scene, with what loading mended as one warning line.
pub type LoadedEnvironment = (Arc<EnvironmentLight>, Option<String>);

/// The map the settings name, loaded, turned and scaled; `None` without a map.
pub fn load_environment(settings: &Settings) -> Result<Option<LoadedEnvironment>, SettingsError> {
    let Some(EnvironmentSetting::Map(path)) = &settings.render.environment else {
        return Ok(None);
    };
    let intensity = environment_intensity(settings)?;
    let rotation = environment_rotation(settings)?;
    let (map, mended) =
        EnvironmentMap::load(path).map_err(|e| SettingsError::Environment(e.to_string()))?;
    let warning = (mended.texels > 0).then(|| {
        format!(
            "environment {}: {} texels were not finite or had a negative channel; they read as 0",
            path.display(),
            mended.texels
        )
    });
    let light = EnvironmentLight::new(map.turned(rotation, intensity));
    Ok(Some((Arc::new(light), warning)))
}

/// The uniform sky's radiance the settings give, scaled by their intensity (zero: none, or a
/// map instead).
pub fn sky_radiance(settings: &Settings) -> Result<Option<Vec3>, SettingsError> {
    let Some(EnvironmentSetting::Sky(c)) = &settings.render.environment else {
        return Ok(None);
    };
    let sky = super::shot::colour("environment", *c)?;
    Ok(Some(sky * environment_intensity(settings)?))
}
