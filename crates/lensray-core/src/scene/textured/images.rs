//! The textured scene's images, made here texel by texel: a checker, a word in a tiny bitmap
//! font, a colour gradient and a leaf whose alpha is its shape. All are sRGB RGBA8 (alpha
//! linear), small enough that loading them costs nothing in a test.

use glam::{Vec2, Vec3};

use super::super::generate::hue;
use super::super::texture::linear_to_srgb;

/// An RGBA8 image, row by row from the top, and the PNG file it is written to.
#[derive(Clone, Debug, PartialEq)]
pub struct ProceduralImage {
    pub file: String,
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl ProceduralImage {
    /// A `width` x `height` image whose texel (x, y) is `texel(x, y)`.
    fn new(file: &str, width: u32, height: u32, texel: impl Fn(u32, u32) -> [u8; 4]) -> Self {
        let rgba = (0..width * height)
            .flat_map(|i| texel(i % width, i / width))
            .collect();
        Self {
            file: file.into(),
            width,
            height,
            rgba,
        }
    }

    /// The PNG file's bytes.
    pub fn png(&self) -> Result<Vec<u8>, image::ImageError> {
        let mut bytes = Vec::new();
        image::write_buffer_with_format(
            &mut std::io::Cursor::new(&mut bytes),
            &self.rgba,
            self.width,
            self.height,
            image::ExtendedColorType::Rgba8,
            image::ImageFormat::Png,
        )?;
        Ok(bytes)
    }
}

/// Linear RGB as sRGB-encoded bytes, opaque.
fn srgb8(c: Vec3) -> [u8; 4] {
    let byte = |l: f32| (linear_to_srgb(l) * 255.0).round() as u8;
    [byte(c.x), byte(c.y), byte(c.z), 255]
}

/// 64 x 64 texels of 8 x 8 squares, cream and dark blue: the checker card and the ground.
pub(super) fn checker() -> ProceduralImage {
    ProceduralImage::new("textured_checker.png", 64, 64, |x, y| {
        if (x / 8 + y / 8) % 2 == 0 {
            [235, 225, 200, 255]
        } else {
            [30, 50, 110, 255]
        }
    })
}

/// The word the text card spells.
const WORD: &str = "LENSRAY";

/// Glyphs of a 5 x 7 bitmap font, one byte per row from the top, bit 4 the leftmost column:
/// just the letters of [`WORD`].
fn glyph(letter: char) -> [u8; 7] {
    match letter {
        'L' => [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1f],
        'E' => [0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x1f],
        'N' => [0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11],
        'S' => [0x0f, 0x10, 0x10, 0x0e, 0x01, 0x01, 0x1e],
        'R' => [0x1e, 0x11, 0x11, 0x1e, 0x14, 0x12, 0x11],
        'A' => [0x0e, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11],
        'Y' => [0x11, 0x11, 0x0a, 0x04, 0x04, 0x04, 0x04],
        _ => [0; 7],
    }
}

/// Texels per font pixel, the gap between letters and the text's margins in [`text`].
const FONT_SCALE: u32 = 3;
const LETTER_GAP: u32 = 3;
const TEXT_LEFT: u32 = 3;
const TEXT_TOP: u32 = 5;

/// Whether texel (x, y) of [`text`] is ink.
fn is_ink(x: u32, y: u32) -> bool {
    let advance = 5 * FONT_SCALE + LETTER_GAP;
    let (Some(x), Some(y)) = (x.checked_sub(TEXT_LEFT), y.checked_sub(TEXT_TOP)) else {
        return false;
    };
    let (column, row) = ((x % advance) / FONT_SCALE, y / FONT_SCALE);
    let letter = WORD.chars().nth((x / advance) as usize);
    match letter {
        Some(letter) if column < 5 && row < 7 => {
            glyph(letter)[row as usize] >> (4 - column) & 1 == 1
        }
        _ => false,
    }
}

/// 128 x 32 texels: [`WORD`] in dark red on white, 15 x 21 texels a letter.
pub(super) fn text() -> ProceduralImage {
    ProceduralImage::new("textured_text.png", 128, 32, |x, y| {
        if is_ink(x, y) {
            [150, 20, 30, 255]
        } else {
            [245, 245, 240, 255]
        }
    })
}

/// 128 x 64 texels: the hues from left to right, darker towards the bottom.
pub(super) fn gradient() -> ProceduralImage {
    ProceduralImage::new("textured_gradient.png", 128, 64, |x, y| {
        let value = 1.0 - 0.7 * y as f32 / 63.0;
        srgb8(hue(x as f32 / 128.0, 0.85, value))
    })
}

/// Whether the point `p` of the leaf's square ([-1, 1]^2, y down) is leaf: a blade pointed at
/// both ends along the vertical, and a stem below it.
fn is_leaf(p: Vec2) -> bool {
    // The blade spans y in [-0.9, 0.6]; its half-width peaks near 0.5 a third of the way down.
    let t = (p.y + 0.9) / 1.5;
    let blade = (0.0..=1.0).contains(&t)
        && p.x.abs() < 0.5 * (std::f32::consts::PI * t).sin().powf(0.8) * (1.3 - 0.5 * t);
    let stem = (0.6..0.95).contains(&p.y) && p.x.abs() < 0.04;
    blade || stem
}

/// 128 x 128 texels: a green leaf with a pale midrib, alpha 255 on the leaf and 0 elsewhere (the
/// colour runs on under alpha 0, so that filtering across the edge brings in no dark fringe).
pub(super) fn leaf() -> ProceduralImage {
    ProceduralImage::new("textured_leaf.png", 128, 128, |x, y| {
        let p = (Vec2::new(x as f32, y as f32) + 0.5) / 64.0 - 1.0;
        let vein = p.x.abs() < 0.025 || (p.y - 0.6 * p.x.abs()).rem_euclid(0.3) < 0.02;
        let [r, g, b, _] = if vein {
            [150, 200, 90, 255]
        } else {
            [40, 130, 35, 255]
        };
        [r, g, b, if is_leaf(p) { 255 } else { 0 }]
    })
}
