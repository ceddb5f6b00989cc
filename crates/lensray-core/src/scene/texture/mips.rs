//! Mip levels: each level a 2 x 2 box filter of the one above, in linear values.

use glam::Vec4;
use rayon::prelude::*;

use super::{decode_texel, linear_to_srgb, Encoding, Level, Texture};

/// Most levels a texture has on the GPU (`Texture.level_first` holds 16), so the largest side
/// is 2^15.
pub const MAX_LEVELS: usize = 16;
pub const MAX_SIZE: u32 = 1 << (MAX_LEVELS - 1);

/// Linear RGBA -> a texel of `encoding`, rounded to the nearest byte.
fn encode_texel(v: Vec4, encoding: Encoding) -> u32 {
    let colour = |c: f32| match encoding {
        Encoding::Srgb => linear_to_srgb(c),
        Encoding::Linear => c.clamp(0.0, 1.0),
    };
    let byte = |c: f32| (c * 255.0).round() as u32;
    byte(colour(v.x))
        | byte(colour(v.y)) << 8
        | byte(colour(v.z)) << 16
        | byte(v.w.clamp(0.0, 1.0)) << 24
}

impl Texture {
    /// A texture of `width` x `height` RGBA8 pixels (row by row, 4 bytes each) with its mip
    /// levels. The caller keeps the sizes within [`MAX_SIZE`] and non-zero.
    pub fn from_rgba8(
        name: &str,
        width: u32,
        height: u32,
        rgba: &[u8],
        encoding: Encoding,
    ) -> Self {
        debug_assert_eq!(rgba.len(), 4 * (width * height) as usize);
        let mut texels: Vec<u32> = rgba
            .chunks_exact(4)
            .map(|p| u32::from_le_bytes([p[0], p[1], p[2], p[3]]))
            .collect();
        let mut levels = vec![Level {
            width,
            height,
            first: 0,
        }];
        loop {
            let above = *levels.last().expect("level 0");
            if above.width == 1 && above.height == 1 {
                break;
            }
            let next = Level {
                width: (above.width / 2).max(1),
                height: (above.height / 2).max(1),
                first: texels.len() as u32,
            };
            let reduced = downsample(&texels, &above, &next, encoding);
            texels.extend(reduced);
            levels.push(next);
        }
        Self {
            name: name.into(),
            encoding,
            levels,
            texels,
        }
    }

    /// Bytes of the texels, every level.
    pub fn bytes(&self) -> u64 {
        4 * self.texels.len() as u64
    }
}

/// Level `next` from level `above`: each texel the mean of the 2 x 2 texels it covers (the last
/// row or column of an odd side is left out; a side of 1 repeats its texel).
fn downsample(texels: &[u32], above: &Level, next: &Level, encoding: Encoding) -> Vec<u32> {
    let read = |x: u32, y: u32| {
        let x = x.min(above.width - 1);
        let y = y.min(above.height - 1);
        decode_texel(
            texels[(above.first + y * above.width + x) as usize],
            encoding,
        )
    };
    (0..next.height)
        .into_par_iter()
        .flat_map_iter(|y| {
            (0..next.width).map(move |x| {
                let sum = read(2 * x, 2 * y)
                    + read(2 * x + 1, 2 * y)
                    + read(2 * x, 2 * y + 1)
                    + read(2 * x + 1, 2 * y + 1);
                encode_texel(0.25 * sum, encoding)
            })
        })
        .collect()
}
