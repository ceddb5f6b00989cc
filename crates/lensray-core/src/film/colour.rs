//! Colour encoding for display and 8-bit files: the sRGB transfer function and its inverse, and
//! the 8-bit values of an image for each shading (what PNG files and the preview show).

use rayon::prelude::*;

use crate::film::tonemap::Display;
use crate::film::Image;
use crate::settings::Shading;

/// 8-bit display values as lensray wrote them before exposure and tone maps
/// ([`Display::LINEAR`]): see [`to_display_bytes_with`].
pub fn to_display_bytes(image: &Image, shading: Shading) -> Vec<u8> {
    to_display_bytes_with(image, shading, Display::LINEAR)
}

/// 8-bit display values: traced colours (lit, unlit) exposed and tone mapped by `display`,
/// then sRGB-encoded; albedo sRGB-encoded as it is (a reflectance, not light); normals as
/// 0.5 n + 0.5; depth scaled so the farthest visible point is white (EXR keeps the raw values).
pub fn to_display_bytes_with(image: &Image, shading: Shading, display: Display) -> Vec<u8> {
    if matches!(shading, Shading::Lit | Shading::Unlit) && display != Display::LINEAR {
        // Pixels are independent: the tone map and the sRGB curve run on every thread, which
        // keeps a sequence's per-frame cost beyond its render small.
        return image
            .pixels
            .par_iter()
            .flat_map_iter(|&p| {
                let shown = display.map(p);
                [shown.x, shown.y, shown.z].map(|c| byte(linear_to_srgb(c)))
            })
            .collect();
    }
    let max_depth =
        image
            .pixels
            .iter()
            .map(|p| p.x)
            .fold(0.0f32, |a, b| if b.is_finite() { a.max(b) } else { a });
    let encode = |c: f32| -> u8 {
        let v = match shading {
            Shading::Depth => {
                if max_depth > 0.0 {
                    c / max_depth
                } else {
                    0.0
                }
            }
            Shading::Normal => 0.5 * c + 0.5,
            Shading::Unlit | Shading::Lit | Shading::Albedo => linear_to_srgb(c),
        };
        byte(v)
    };
    image
        .pixels
        .par_iter()
        .flat_map_iter(|p| [encode(p.x), encode(p.y), encode(p.z)])
        .collect()
}

/// An encoded value in [0, 1] (clamped) as a byte, rounded.
fn byte(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// The sRGB transfer function (IEC 61966-2-1).
pub fn linear_to_srgb(c: f32) -> f32 {
    if c.is_nan() || c <= 0.0 {
        0.0
    } else if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`linear_to_srgb`]: an sRGB-encoded value in [0, 1] to linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v.is_nan() || v <= 0.0 {
        0.0
    } else if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}
