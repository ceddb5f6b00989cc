//! The exposure and tone map a shot's settings ask for (`[camera.exposure]`, `--exposure`,
//! `--iso`, `--shutter`, `--tonemap`, `--expose-exr`), checked, with the f-number of the shot's
//! lens. The formulas are `film::tonemap`'s.
//!
//! - No option: the image's values as rendered (scale 1); PNGs and the preview tone mapped by
//!   the default tone map ([`ToneMap::Neutral`]).
//! - `ev` alone: the image scaled by 2^ev.
//! - `shutter` (with `iso`, default 100): the physical exposure 1 / (1.2 * 2^EV100), EV100 =
//!   log2(N^2 / shutter * 100 / ISO); `ev` is then an offset on top (exposure compensation).
//! - N is the lens's: a real lens's f-number as set (its widest by default), a focal length's
//!   `f_number` (default 2.8). A pinhole or a thin lens given by its aperture radius has no
//!   f-number of its own: `f_number` (allowed there only with a shutter time, and then for the
//!   exposure alone) or f/16 ([`UNSET_F_NUMBER`], the f-number of the sunny-16 rule).
//! - EXR files keep the rendered values unless `expose_exr`; tone maps are for display only and
//!   never reach an EXR.

use crate::camera::Camera;
#[cfg(doc)]
use crate::film::tonemap::ToneMap;
use crate::film::tonemap::{ev100, exposure_scale, Display};
use crate::settings::{Settings, SettingsError, DEFAULT_F_NUMBER};

/// The f-number exposure assumes for a lens without one (a pinhole, a thin lens given by its
/// aperture radius): sunny 16's.
pub const UNSET_F_NUMBER: f64 = 16.0;
/// The ISO of a shutter time given without one.
pub const DEFAULT_ISO: f64 = 100.0;

/// A shot's exposure: what PNGs and the preview show, and what EXR files get.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exposure {
    pub display: Display,
    /// The scale EXR pixels are written with: 1 unless `expose_exr`.
    pub exr_scale: f32,
    /// The physical exposure's f-number, shutter time, ISO and EV100, where one was asked for.
    pub physical: Option<Physical>,
}

/// The settings of a physical exposure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Physical {
    pub f_number: f64,
    pub shutter: f64,
    pub iso: f64,
    pub ev100: f64,
}

impl Exposure {
    /// "f/16 1/125 s ISO 100: EV100 14.97, +1 EV, scale 5.2083e-5, tone map agx" (the render's
    /// summary).
    pub fn summary(&self, ev: f64) -> String {
        let mut parts = Vec::new();
        if let Some(p) = self.physical {
            let shutter = if p.shutter < 1.0 && (1.0 / p.shutter).fract().abs() < 1e-6 {
                format!("1/{} s", (1.0 / p.shutter).round())
            } else {
                format!("{} s", p.shutter)
            };
            parts.push(format!(
                "f/{} {shutter} ISO {}: EV100 {:.2}",
                p.f_number, p.iso, p.ev100
            ));
        }
        if ev != 0.0 {
            parts.push(format!("{ev:+} EV"));
        }
        parts.push(format!("scale {:.4e}", self.display.exposure));
        parts.push(format!("tone map {}", self.display.tonemap.name()));
        parts.join(", ")
    }
}

fn positive(what: &'static str, v: Option<f64>) -> Result<Option<f64>, SettingsError> {
    match v {
        Some(x) if !(x.is_finite() && x > 0.0) => Err(SettingsError::Exposure(format!(
            "{what} must be a positive number, got {x}"
        ))),
        _ => Ok(v),
    }
}

/// The f-number exposure uses for `camera`, built from `settings`.
pub fn f_number(settings: &Settings, camera: &Camera) -> f64 {
    let c = &settings.camera;
    if let Some(real) = camera.lens.real() {
        real.f_number
    } else if c.focal_length_mm.is_some() && c.aperture_radius.is_none() {
        c.f_number.unwrap_or(DEFAULT_F_NUMBER)
    } else {
        c.f_number.unwrap_or(UNSET_F_NUMBER)
    }
}

/// The exposure `settings` ask for, for `camera` (the shot they resolve to).
pub fn exposure(settings: &Settings, camera: &Camera) -> Result<Exposure, SettingsError> {
    let e = &settings.camera.exposure;
    let ev = e.ev.unwrap_or(0.0);
    if !ev.is_finite() {
        return Err(SettingsError::Exposure(format!(
            "exposure must be a finite number of stops, got {ev}"
        )));
    }
    let iso = positive("ISO", e.iso)?;
    let shutter = positive("shutter time (seconds)", e.shutter)?;
    if iso.is_some() && shutter.is_none() {
        return Err(SettingsError::Exposure(
            "an ISO needs a shutter time too (--shutter SECONDS)".into(),
        ));
    }
    let physical = shutter.map(|shutter| {
        let iso = iso.unwrap_or(DEFAULT_ISO);
        let f_number = f_number(settings, camera);
        Physical {
            f_number,
            shutter,
            iso,
            ev100: ev100(f_number, shutter, iso),
        }
    });
    let scale = exposure_scale(ev, physical.map(|p| (p.f_number, p.shutter, p.iso))) as f32;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(SettingsError::Exposure(format!(
            "the exposure's scale is out of range ({scale}): check exposure, ISO and shutter"
        )));
    }
    Ok(Exposure {
        display: Display {
            exposure: scale,
            tonemap: e.tonemap.unwrap_or_default(),
        },
        exr_scale: if e.expose_exr == Some(true) {
            scale
        } else {
            1.0
        },
        physical,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::tonemap::ToneMap;
    use crate::scene::builtin::default_scene;
    use crate::settings::{shot, ExposureSettings};

    fn resolve(mut settings: Settings, e: ExposureSettings) -> Result<Exposure, SettingsError> {
        settings.camera.exposure = e;
        let scene = default_scene().scene;
        let camera = shot(&settings, &scene)?.camera;
        exposure(&settings, &camera)
    }

    fn sunny() -> ExposureSettings {
        ExposureSettings {
            iso: Some(100.0),
            shutter: Some(1.0 / 125.0),
            ..ExposureSettings::default()
        }
    }

    #[test]
    fn no_option_leaves_the_values_as_rendered() {
        let e = resolve(Settings::default(), ExposureSettings::default()).unwrap();
        assert_eq!(e.display.exposure, 1.0);
        assert_eq!(e.display.tonemap, ToneMap::Neutral);
        assert_eq!(e.exr_scale, 1.0);
        assert_eq!(e.physical, None);
    }

    #[test]
    fn a_pinhole_exposes_at_f16_or_its_given_f_number() {
        let e = resolve(Settings::default(), sunny()).unwrap();
        let p = e.physical.unwrap();
        assert_eq!(p.f_number, UNSET_F_NUMBER);
        assert!((p.ev100 - 32000f64.log2()).abs() < 1e-12);
        assert!((f64::from(e.display.exposure) - 1.0 / 38400.0).abs() < 1e-9);
        assert_eq!(e.exr_scale, 1.0, "EXR stays linear unless asked");
        let mut settings = Settings::default();
        settings.camera.f_number = Some(8.0);
        let e8 = resolve(settings.clone(), sunny()).unwrap();
        assert_eq!(e8.physical.unwrap().f_number, 8.0);
        assert!((e8.display.exposure / e.display.exposure - 4.0).abs() < 1e-5);
        // Without a shutter time, a pinhole's f-number is still refused.
        assert!(resolve(settings, ExposureSettings::default()).is_err());
    }

    #[test]
    fn a_lens_exposes_at_its_own_f_number() {
        let mut settings = Settings::default();
        settings.camera.focal_length_mm = Some(50.0);
        let e = resolve(settings.clone(), sunny()).unwrap();
        assert_eq!(e.physical.unwrap().f_number, DEFAULT_F_NUMBER);
        settings.camera.f_number = Some(5.6);
        let e = resolve(settings, sunny()).unwrap();
        assert_eq!(e.physical.unwrap().f_number, 5.6);
        let mut real = Settings::default();
        real.camera.lens.prescription = Some("double-gauss-50".into());
        real.camera.f_number = Some(4.0);
        let e = resolve(real, sunny()).unwrap();
        assert!((e.physical.unwrap().f_number - 4.0).abs() < 1e-9);
    }

    #[test]
    fn ev_is_an_offset_on_top_and_exr_is_exposed_when_asked() {
        let base = resolve(Settings::default(), sunny()).unwrap();
        let e = resolve(
            Settings::default(),
            ExposureSettings {
                ev: Some(1.5),
                expose_exr: Some(true),
                tonemap: Some(ToneMap::Neutral),
                ..sunny()
            },
        )
        .unwrap();
        let ratio = e.display.exposure / base.display.exposure;
        assert!((ratio - 2f32.powf(1.5)).abs() < 1e-5, "{ratio}");
        assert_eq!(e.exr_scale, e.display.exposure);
        assert_eq!(e.display.tonemap, ToneMap::Neutral);
    }

    #[test]
    fn bad_values_are_refused() {
        let bad = |e: ExposureSettings, needle: &str| {
            let err = resolve(Settings::default(), e).unwrap_err().to_string();
            assert!(err.contains(needle), "{err}");
        };
        bad(
            ExposureSettings {
                iso: Some(-100.0),
                ..sunny()
            },
            "ISO",
        );
        bad(
            ExposureSettings {
                shutter: Some(0.0),
                ..sunny()
            },
            "shutter",
        );
        bad(
            ExposureSettings {
                shutter: Some(f64::NAN),
                ..sunny()
            },
            "shutter",
        );
        bad(
            ExposureSettings {
                ev: Some(f64::INFINITY),
                ..sunny()
            },
            "exposure",
        );
        bad(
            ExposureSettings {
                iso: Some(400.0),
                ..ExposureSettings::default()
            },
            "shutter",
        );
    }
}
