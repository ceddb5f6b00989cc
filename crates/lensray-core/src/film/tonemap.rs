//! Exposure and tone mapping: from the light that reaches the film (the renders' linear RGB) to
//! what a PNG file and the preview show. The GLSL mirror is shaders/include/tonemap.glsl
//! (lensray-vulkan), checked against these functions on the device (tests/tonemap.rs there);
//! the constants both read are lensray-interface's (`TONEMAP_*`, `NEUTRAL_*`, `AGX_*`).
//!
//! Exposure is a linear scale of the image. Physically (Lagarde & de Rousiers, "Moving
//! Frostbite to PBR", 2014, section 5.1; Filament's documentation, "Physically based camera"):
//!
//! - `EV100 = log2(N^2 / t * 100 / S)` for f-number N, shutter time t (seconds) and ISO S;
//! - `exposure = 1 / (1.2 * 2^EV100)`: the scale that takes a luminance in cd/m^2 (the
//!   renders' units under glTF's photometric lights) to the sensor's saturation at 1.0, with
//!   the ISO 12232 saturation-based speed's factor 78 / (100 * 0.65) = 1.2.
//!
//! Sunny 16 (ISO 100, 1/125 s, f/16) gives EV100 = log2(256 * 125) = 14.97, and a white
//! diffuse surface under 100,000 lux (radiance 100,000 / pi) 0.83 after exposure.
//!
//! The tone maps take exposed linear sRGB (Rec. 709) to display-linear sRGB in [0, 1], which
//! [`linear_to_srgb`](super::colour::linear_to_srgb) then encodes:
//! - [`ToneMap::None`]: the values as they are (the encoding clamps at 1: what lensray wrote
//!   before tone maps);
//! - [`ToneMap::Neutral`]: Khronos PBR Neutral ([`pbr_neutral`]);
//! - [`ToneMap::Agx`]: AgX as three.js writes it ([`agx`]).

use glam::{Mat3, Vec3};
use serde::{Deserialize, Serialize};

use crate::interface::{
    AGX_INSET, AGX_MAX_EV, AGX_MIN_EV, AGX_OUTSET, AGX_REC2020_TO_SRGB, AGX_SIGMOID,
    AGX_SRGB_TO_REC2020, NEUTRAL_DESATURATION, NEUTRAL_START_COMPRESSION, TONEMAP_AGX,
    TONEMAP_NEUTRAL, TONEMAP_NONE,
};

/// The tone map of PNG files and the preview (`--tonemap`, `tonemap`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ToneMap {
    /// Linear values clamped to [0, 1] by the encoding: everything above 1 is white (what
    /// lensray wrote before tone maps).
    None,
    /// Khronos PBR Neutral: colours below 0.76 kept but for an offset of up to 0.04 (which
    /// cancels a dielectric's 4 % Fresnel reflection) and a quadratic toe below 0.08, highlights
    /// compressed towards 1 and desaturated. The default, as in the glTF viewers: base colours
    /// come out as they show them (docs/cli.md, "Exposure and tone maps", has the measurements).
    #[default]
    Neutral,
    /// AgX: a log encoding over 16.5 stops around mid grey and a sigmoid, in a widened gamut
    /// (film-like: highlights keep gradations up to 16 times a diffuse white's 1 and bright
    /// colours desaturate smoothly to white), for light sources and bright skies in the frame.
    Agx,
}

impl ToneMap {
    pub const ALL: [ToneMap; 3] = [Self::None, Self::Neutral, Self::Agx];

    /// The name `--tonemap` and `tonemap` take.
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Neutral => "neutral",
            Self::Agx => "agx",
        }
    }

    /// `TONEMAP_*`, what the preview's shader reads.
    pub fn code(self) -> u32 {
        match self {
            Self::None => TONEMAP_NONE,
            Self::Neutral => TONEMAP_NEUTRAL,
            Self::Agx => TONEMAP_AGX,
        }
    }

    /// The tone map of an exposed linear colour.
    pub fn apply(self, c: Vec3) -> Vec3 {
        match self {
            Self::None => c,
            Self::Neutral => pbr_neutral(c),
            Self::Agx => agx(c),
        }
    }
}

/// How a PNG and the preview turn linear RGB into display values: a scale, then a tone map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Display {
    /// The linear scale ([`exposure_scale`]); 1 unless exposure is asked for.
    pub exposure: f32,
    pub tonemap: ToneMap,
}

impl Display {
    /// What lensray showed before exposure and tone maps: the values as they are, clamped.
    pub const LINEAR: Display = Display {
        exposure: 1.0,
        tonemap: ToneMap::None,
    };

    /// The display value of a linear colour (display-linear, before the sRGB encoding).
    pub fn map(&self, c: Vec3) -> Vec3 {
        self.tonemap.apply(c * self.exposure)
    }
}

/// The exposure value at ISO 100 of f-number `f_number`, shutter time `shutter_seconds` and
/// ISO `iso`: `log2(N^2 / t * 100 / S)`.
pub fn ev100(f_number: f64, shutter_seconds: f64, iso: f64) -> f64 {
    (f_number * f_number / shutter_seconds * 100.0 / iso).log2()
}

/// The linear scale of exposure value `ev100`: `1 / (1.2 * 2^EV100)` (Filament's
/// `exposure(ev100)`).
pub fn exposure_of_ev100(ev100: f64) -> f64 {
    1.0 / (1.2 * ev100.exp2())
}

/// The whole linear scale: `2^ev` (the plain offset `--exposure`) times the physical exposure
/// of `physical` = (f-number, shutter seconds, ISO) where given.
pub fn exposure_scale(ev: f64, physical: Option<(f64, f64, f64)>) -> f64 {
    let camera = physical.map_or(1.0, |(n, t, s)| exposure_of_ev100(ev100(n, t, s)));
    ev.exp2() * camera
}

/// Negative and NaN channels read as 0 (the sRGB encoding treats them so too).
fn non_negative(c: Vec3) -> Vec3 {
    Vec3::new(c.x.max(0.0), c.y.max(0.0), c.z.max(0.0))
}

/// Khronos PBR Neutral, linear sRGB in and out: the Khronos specification "PBR Neutral Tone
/// Mapping" and its reference code, github.com/KhronosGroup/ToneMapping,
/// PBR_Neutral/pbrNeutral.glsl (`PBRNeutralToneMapping`), statement by statement. Outputs lie
/// in [0, 1) for every finite input; each channel grows with the input's scale.
pub fn pbr_neutral(color: Vec3) -> Vec3 {
    let mut color = non_negative(color);
    let start_compression = NEUTRAL_START_COMPRESSION;
    let desaturation = NEUTRAL_DESATURATION;

    let x = color.x.min(color.y.min(color.z));
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    color -= Vec3::splat(offset);

    let peak = color.x.max(color.y.max(color.z));
    if peak < start_compression {
        return color;
    }

    let d = 1.0 - start_compression;
    let new_peak = 1.0 - d * d / (peak + d - start_compression);
    color *= new_peak / peak;

    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    // GLSL's mix(x, y, a): x * (1 - a) + y * a.
    color * (1.0 - g) + Vec3::splat(new_peak) * g
}

/// GLSL's `mat3` of nine floats, column by column.
fn mat3(cols: [f32; 9]) -> Mat3 {
    Mat3::from_cols_array(&cols)
}

/// AgX's sigmoid, the polynomial fit of three.js's `agxDefaultContrastApprox`, evaluated as
/// it writes it.
fn agx_sigmoid(x: f32) -> f32 {
    let [c6, c5, c4, c3, c2, c1, c0] = AGX_SIGMOID;
    let x2 = x * x;
    let x4 = x2 * x2;
    c6 * x4 * x2 + c5 * x4 * x + c4 * x4 + c3 * x2 * x + c2 * x2 + c1 * x + c0
}

/// AgX, linear sRGB in and out, as three.js writes it: `AgXToneMapping` in
/// src/renderers/shaders/ShaderChunk/tonemapping_pars_fragment.glsl.js (r160 on), which follows
/// Filament's port (google/filament pull request 7236) of Blender's AgX (Troy Sobotka's
/// configuration, sigmoid fitted by Benjamin Wrensch), without a look. Linear sRGB goes to
/// Rec. 2020, through the inset matrix, is log2-encoded from AGX_MIN_EV to AGX_MAX_EV (16.5
/// stops, mid grey 0.18 at 10 stops), shaped by the sigmoid, taken out by the outset matrix,
/// raised to 2.2 and brought back to sRGB, then clamped. Channels past the encoding's top
/// (2^4.03 = 16.3 after the matrices: a grey of about 16) all map to its white.
pub fn agx(color: Vec3) -> Vec3 {
    let mut color = mat3(AGX_SRGB_TO_REC2020) * non_negative(color);
    color = mat3(AGX_INSET) * color;
    // Log2 encoding (1e-10 keeps log2 away from 0).
    color = color.max(Vec3::splat(1e-10));
    color = Vec3::new(color.x.log2(), color.y.log2(), color.z.log2());
    color = (color - Vec3::splat(AGX_MIN_EV)) / (AGX_MAX_EV - AGX_MIN_EV);
    color = color.clamp(Vec3::ZERO, Vec3::ONE);
    color = Vec3::new(
        agx_sigmoid(color.x),
        agx_sigmoid(color.y),
        agx_sigmoid(color.z),
    );
    color = mat3(AGX_OUTSET) * color;
    // Linearize.
    color = color.max(Vec3::ZERO);
    color = Vec3::new(color.x.powf(2.2), color.y.powf(2.2), color.z.powf(2.2));
    color = mat3(AGX_REC2020_TO_SRGB) * color;
    color.clamp(Vec3::ZERO, Vec3::ONE)
}

#[cfg(test)]
mod tests;
