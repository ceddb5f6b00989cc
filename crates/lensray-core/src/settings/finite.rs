//! Every number of the settings is finite: one check over all of them, from the command line,
//! a scene file or a keyframe alike, rather than one per option. The settings are walked as the
//! TOML a scene file would hold, so a key added later is checked without naming it here.

use super::Settings;

/// The first number of `settings` that is NaN or infinite: its key as a scene file writes it
/// (`render.environment_rotation`, `camera.eye[1]`) and its value.
pub fn first_not_finite(settings: &Settings) -> Option<(String, f64)> {
    // Serializing plain data to a TOML value cannot fail; if it ever did, no number is named.
    let value = toml::Value::try_from(settings).ok()?;
    not_finite_in(&value, String::new())
}

fn not_finite_in(value: &toml::Value, key: String) -> Option<(String, f64)> {
    match value {
        toml::Value::Float(x) if !x.is_finite() => Some((key, *x)),
        toml::Value::Table(table) => table.iter().find_map(|(name, v)| {
            let key = if key.is_empty() {
                name.clone()
            } else {
                format!("{key}.{name}")
            };
            not_finite_in(v, key)
        }),
        toml::Value::Array(items) => items
            .iter()
            .enumerate()
            .find_map(|(i, v)| not_finite_in(v, format!("{key}[{i}]"))),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::{EnvironmentSetting, LightSettings, Lights};

    /// Each kind of place a number sits is found and named: a plain key, an element of a
    /// triple, a nested table, a light of several; finite settings pass.
    #[test]
    fn the_first_number_not_finite_is_named_by_its_key() {
        let mut s = Settings::default();
        assert_eq!(first_not_finite(&s), None);
        s.camera.eye = Some([0.0, 1.0, 5.0]);
        s.render.environment = Some(EnvironmentSetting::Sky([0.5, 0.5, 0.5]));
        assert_eq!(first_not_finite(&s), None);

        s.render.environment_rotation = Some(f64::NAN);
        let (key, value) = first_not_finite(&s).expect("NaN is found");
        assert_eq!(key, "render.environment_rotation");
        assert!(value.is_nan());

        s.render.environment_rotation = None;
        s.camera.eye = Some([0.0, f64::INFINITY, 5.0]);
        assert_eq!(
            first_not_finite(&s),
            Some(("camera.eye[1]".into(), f64::INFINITY))
        );

        s.camera.eye = None;
        s.camera.exposure.shutter = Some(f64::NEG_INFINITY);
        assert_eq!(
            first_not_finite(&s),
            Some(("camera.exposure.shutter".into(), f64::NEG_INFINITY))
        );

        s.camera.exposure.shutter = None;
        let light = |range| LightSettings {
            range,
            ..LightSettings::default()
        };
        s.light = Lights(vec![light(Some(2.0)), light(Some(f64::NAN))]);
        let (key, _) = first_not_finite(&s).expect("the second light's NaN is found");
        assert!(key.starts_with("light") && key.ends_with("range"), "{key}");
    }
}
