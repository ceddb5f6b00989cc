//! The lights a user gives (a scene file's `[[light]]` tables, the command line's `--light-*`)
//! and what they resolve to: [`Light`]s added to the scene's own, or, where neither the file
//! nor the settings light the scene and there is no environment and no emissive surfaces bright
//! enough to light it, one point light above the eye.

use std::fmt;

use glam::{DVec3, Vec3};
use serde::de::{self, value::MapAccessDeserializer, value::SeqAccessDeserializer};
use serde::{Deserialize, Deserializer, Serialize};

use super::environment::load_environment;
use super::shot::{colour, framing, point, SettingsError};
use super::{EnvironmentSetting, Settings};
use crate::scene::emitters::area_normal;
use crate::scene::environment::luminance;
use crate::scene::{Light, LightKind, Scene};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LightType {
    #[default]
    Point,
    Spot,
    Directional,
}

/// One light, as `KHR_lights_punctual` describes it (its units: W/sr for point and spot, W/m^2
/// for directional). Lengths are in the scene's units.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LightSettings {
    /// point (default), spot or directional.
    #[serde(rename = "type")]
    pub kind: Option<LightType>,
    /// Point and spot; default: above the eye.
    pub position: Option<[f64; 3]>,
    /// The direction the light travels (spot, directional); default: from the light (spot) or
    /// from above the eye (directional) towards the camera's target.
    pub direction: Option<[f64; 3]>,
    /// W/sr (point, spot) or W/m^2 (directional) per channel; default: about 1 W/m^2 at the
    /// camera's target.
    pub intensity: Option<[f64; 3]>,
    /// Spot: the half-angle of full intensity, degrees (default 0).
    pub inner_cone_degrees: Option<f64>,
    /// Spot: the half-angle beyond which there is no light, degrees (default 45).
    pub outer_cone_degrees: Option<f64>,
    /// Point and spot: the distance where the light fades out (default: none).
    pub range: Option<f64>,
}

/// The settings' lights: a scene file writes one `[light]` table or several `[[light]]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Lights(pub Vec<LightSettings>);

impl Lights {
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// These lights with `over`'s: the command line's one light changes the file's one light
    /// field by field (`--light-intensity` alone brightens it), else `over`'s replace these.
    pub fn overridden_by(self, over: &Lights) -> Lights {
        match (self.0.as_slice(), over.0.as_slice()) {
            (_, []) => self,
            ([base], [over]) => {
                let pick = |o: Option<[f64; 3]>, b: Option<[f64; 3]>| o.or(b);
                Lights(vec![LightSettings {
                    kind: over.kind.or(base.kind),
                    position: pick(over.position, base.position),
                    direction: pick(over.direction, base.direction),
                    intensity: pick(over.intensity, base.intensity),
                    inner_cone_degrees: over.inner_cone_degrees.or(base.inner_cone_degrees),
                    outer_cone_degrees: over.outer_cone_degrees.or(base.outer_cone_degrees),
                    range: over.range.or(base.range),
                }])
            }
            _ => over.clone(),
        }
    }
}

impl<'de> Deserialize<'de> for Lights {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct OneOrMany;
        impl<'de> de::Visitor<'de> for OneOrMany {
            type Value = Lights;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a [light] table or [[light]] tables")
            }
            fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<Lights, A::Error> {
                LightSettings::deserialize(MapAccessDeserializer::new(map)).map(|l| Lights(vec![l]))
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, seq: A) -> Result<Lights, A::Error> {
                Vec::deserialize(SeqAccessDeserializer::new(seq)).map(Lights)
            }
        }
        deserializer.deserialize_any(OneOrMany)
    }
}

fn unit(name: &'static str, v: [f64; 3]) -> Result<Vec3, SettingsError> {
    let d = DVec3::from_array(v);
    if d.is_finite() && d.length() > 0.0 {
        Ok(d.normalize().as_vec3())
    } else {
        Err(SettingsError::NotFinite(name, v))
    }
}

fn cone(name: &'static str, degrees: f64) -> Result<f32, SettingsError> {
    if (0.0..=90.0).contains(&degrees) {
        Ok(degrees.to_radians().cos() as f32)
    } else {
        Err(SettingsError::Light(format!(
            "a spot light's {name} must be 0 to 90 degrees, got {degrees}"
        )))
    }
}

/// Where the default lights sit: above the eye, aimed at the target, bright enough to give
/// about 1 W/m^2 there.
struct Placement {
    above_eye: Vec3,
    target: Vec3,
}

fn light(s: &LightSettings, at: &Placement) -> Result<Light, SettingsError> {
    let kind = s.kind.unwrap_or_default();
    let position = match s.position {
        Some(p) => point("light position", p)?,
        None => at.above_eye,
    };
    let direction = match s.direction {
        Some(d) => unit("light direction", d)?,
        None if kind == LightType::Point => Vec3::NEG_Z,
        None => (at.target - position)
            .try_normalize()
            .unwrap_or(Vec3::NEG_Y),
    };
    let intensity = match s.intensity {
        Some(i) => colour("light intensity", i)?,
        None if kind == LightType::Directional => Vec3::ONE,
        // pi d^2 makes the irradiance at the target about 1, so a lit surface shows about Kd.
        None => Vec3::splat(std::f32::consts::PI * (position - at.target).length_squared()),
    };
    let range = s.range.unwrap_or(0.0);
    if !(range.is_finite() && range >= 0.0) {
        return Err(SettingsError::Light(format!(
            "a light's range must be finite and not negative, got {range}"
        )));
    }
    let kind = match kind {
        LightType::Point => LightKind::Point,
        LightType::Directional => LightKind::Directional,
        LightType::Spot => {
            let cos_inner = cone("inner cone", s.inner_cone_degrees.unwrap_or(0.0))?;
            let cos_outer = cone("outer cone", s.outer_cone_degrees.unwrap_or(45.0))?;
            if cos_outer > cos_inner {
                return Err(SettingsError::Light(
                    "a spot light's inner cone must not be wider than its outer cone".into(),
                ));
            }
            LightKind::Spot {
                cos_inner,
                cos_outer,
            }
        }
    };
    Ok(Light {
        kind,
        position,
        direction,
        intensity,
        range: range as f32,
    })
}

/// The share of the default light's irradiance (pi W/m^2 at the target) below which a scene's
/// emitters do not light it by themselves: a room's ceiling patch or a row of glowing cubes is
/// over it (the Cornell box's 0.24, EmissiveStrengthTest's 0.071), glowing labels are not
/// (ClearCoatTest's 0.030), and a model with labels keeps the light that shows the rest of it.
pub const EMITTERS_LIGHT_SHARE: f32 = 0.05;

/// What the emissive surfaces of `scene` give, as a share of the default light's irradiance:
/// their power (pi x the luminance of their emission x their area, one-sided Lambertian
/// emitters) spread over the scene's bounding sphere, Phi / (4 pi R^2), over pi. A textured
/// emission counts at its texture's mean (its 1 x 1 level): a body whose emissive texture
/// lights only its lamps is not a lamp.
pub fn emitters_light_share(scene: &Scene) -> f32 {
    let Some((_, radius)) = scene.bounding_sphere() else {
        return 0.0;
    };
    let emission: Vec<Vec3> = scene
        .materials
        .iter()
        .map(|m| match &m.emission_texture {
            Some(t) => scene
                .textures
                .get(t.texture as usize)
                .map_or(m.emission, |texture| m.emission * texture.mean().truncate()),
            None => m.emission,
        })
        .collect();
    let power: f32 = scene
        .meshes
        .iter()
        .flat_map(|mesh| {
            mesh.triangles
                .iter()
                .zip(&mesh.material_ids)
                .map(|(t, &m)| {
                    let v = t.map(|i| mesh.positions[i as usize]);
                    std::f32::consts::PI * luminance(emission[m as usize]) * area_normal(&v).0
                })
        })
        .filter(|p| p.is_finite())
        .sum();
    power / (4.0 * std::f32::consts::PI * radius * radius) / std::f32::consts::PI
}

/// The lights `settings` add to `scene`: each of theirs, or one point light above the eye when
/// neither they nor the scene's file give one and there is no environment or emissive surfaces
/// to light it (`emitters_light_share` at least [`EMITTERS_LIGHT_SHARE`]).
pub fn settings_lights(settings: &Settings, scene: &Scene) -> Result<Vec<Light>, SettingsError> {
    let environment = settings
        .render
        .environment
        .as_ref()
        .is_some_and(EnvironmentSetting::lights);
    let given = &settings.light.0;
    let emitters_light = emitters_light_share(scene) >= EMITTERS_LIGHT_SHARE;
    if given.is_empty() && (!scene.lights.is_empty() || environment || emitters_light) {
        return Ok(Vec::new());
    }
    let f = framing(settings, scene)?;
    let at = Placement {
        // Everything the camera sees is lit and shadows fall behind objects.
        above_eye: f.eye + f.true_up * (0.5 * f.radius) as f32,
        target: f.target,
    };
    if given.is_empty() {
        return Ok(vec![light(&LightSettings::default(), &at)?]);
    }
    given.iter().map(|s| light(s, &at)).collect()
}

/// The settings' lights with every default filled in (`settings_lights`), so that they light
/// the scene the same wherever the camera moves: the preview pins them at its start.
pub fn pinned_lights(settings: &Settings, scene: &Scene) -> Result<Lights, SettingsError> {
    let given = &settings.light.0;
    let default = LightSettings::default();
    let resolved = settings_lights(settings, scene)?;
    let array = |v: Vec3| v.as_dvec3().to_array();
    Ok(Lights(
        resolved
            .iter()
            .enumerate()
            .map(|(i, light)| {
                let s = given.get(i).unwrap_or(&default);
                let point = light.kind == LightKind::Point;
                let directional = light.kind == LightKind::Directional;
                LightSettings {
                    kind: Some(s.kind.unwrap_or_default()),
                    position: (!directional).then(|| s.position.unwrap_or(array(light.position))),
                    direction: (!point).then(|| s.direction.unwrap_or(array(light.direction))),
                    intensity: Some(s.intensity.unwrap_or(array(light.intensity))),
                    ..s.clone()
                }
            })
            .collect(),
    ))
}

/// Adds the lights of `settings` (`settings_lights`) to `scene`'s, once: a light already there
/// is not added again, so lighting a lit scene changes nothing. The settings' environment map
/// is loaded into the scene (`Scene::environment`). Returns the warnings to print, one line
/// each.
pub fn light_scene(settings: &Settings, scene: &mut Scene) -> Result<Vec<String>, SettingsError> {
    for light in settings_lights(settings, scene)? {
        if !scene.lights.contains(&light) {
            scene.lights.push(light);
        }
    }
    let mut warnings = Vec::new();
    if let Some((environment, warning)) = load_environment(settings)? {
        scene.environment = Some(environment);
        warnings.extend(warning);
    }
    Ok(warnings)
}
