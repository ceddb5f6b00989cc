//! The scene's textures in the one texel array the shaders read (shaders/include/texture.glsl):
//! each texture's mip levels, with a table entry per texture. A storage buffer is bounded by
//! the device's `maxStorageBufferRange` (128 MiB on lavapipe, two 4096 x 4096 textures and
//! their levels pass it), so where the array would pass it the finest level of the largest
//! texture is left out, again until it fits: that texture reads from its next level, as if
//! it had half the texels.

use lensray_core::interface::GpuTexture;
use lensray_core::scene::texture::{Encoding, MAX_LEVELS};
use lensray_core::scene::Texture;

use crate::core::error::GpuError;

/// The table and the texels, and what was left out to fit.
#[derive(Clone, Debug, Default)]
pub(crate) struct FlatTextures {
    pub textures: Vec<GpuTexture>,
    pub texels: Vec<u32>,
    /// Per texture that lost levels: its name, its size and the size it is read at.
    pub coarsened: Vec<(String, [u32; 2], [u32; 2])>,
}

/// Bytes of `texture`'s texels from level `skip` on.
fn bytes_from(texture: &Texture, skip: usize) -> u64 {
    (texture.texels.len() - texture.levels[skip].first as usize) as u64 * 4
}

/// Flattens `textures` into at most `limit` bytes of texels, leaving out the finest levels of
/// the largest textures where they would not fit; an error when even their coarsest do not.
pub(crate) fn flatten(textures: &[Texture], limit: u64) -> Result<FlatTextures, GpuError> {
    let mut skip = vec![0usize; textures.len()];
    let mut total: u64 = textures.iter().map(|t| bytes_from(t, 0)).sum();
    while total > limit {
        let largest = (0..textures.len())
            .filter(|&i| skip[i] + 1 < textures[i].levels.len())
            .max_by_key(|&i| (bytes_from(&textures[i], skip[i]), std::cmp::Reverse(i)));
        let Some(i) = largest else {
            return Err(GpuError::Invalid(format!(
                "the scene's textures need {total} bytes even at their coarsest levels, more \
                 than the device's maximum storage buffer range ({limit} bytes)"
            )));
        };
        total -= bytes_from(&textures[i], skip[i]) - bytes_from(&textures[i], skip[i] + 1);
        skip[i] += 1;
    }
    let mut flat = FlatTextures::default();
    for (texture, &skip) in textures.iter().zip(&skip) {
        flat.textures
            .push(gpu_texture(texture, skip, flat.texels.len())?);
        let first = texture.levels[skip].first as usize;
        flat.texels.extend_from_slice(&texture.texels[first..]);
        if skip > 0 {
            let (whole, read) = (&texture.levels[0], &texture.levels[skip]);
            flat.coarsened.push((
                texture.name.clone(),
                [whole.width, whole.height],
                [read.width, read.height],
            ));
        }
    }
    Ok(flat)
}

/// A texture's table entry from level `skip` on, its texels starting at `first_texel` of the
/// texel array.
fn gpu_texture(texture: &Texture, skip: usize, first_texel: usize) -> Result<GpuTexture, GpuError> {
    let levels = &texture.levels[skip..];
    let end = first_texel + bytes_from(texture, skip) as usize / 4;
    if levels.len() > MAX_LEVELS || u32::try_from(end).is_err() {
        return Err(GpuError::Invalid(format!(
            "texture {} does not fit the GPU's texture table ({} levels, texels up to {end})",
            texture.name,
            levels.len()
        )));
    }
    let base = levels[0].first;
    let mut level_first = [[0; 4]; 4];
    for (i, level) in levels.iter().enumerate() {
        level_first[i / 4][i % 4] = first_texel as u32 + level.first - base;
    }
    Ok(GpuTexture {
        level_first,
        width: levels[0].width,
        height: levels[0].height,
        levels: levels.len() as u32,
        srgb: u32::from(texture.encoding == Encoding::Srgb),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use lensray_core::scene::texture::Level;

    /// A texture of `size` x `size` texels (a power of two) and its levels, each texel its
    /// level's index, so that a read shows which level it came from.
    fn texture(name: &str, size: u32) -> Texture {
        let (mut levels, mut texels) = (Vec::new(), Vec::new());
        let mut s = size;
        loop {
            levels.push(Level {
                width: s,
                height: s,
                first: texels.len() as u32,
            });
            texels.extend(std::iter::repeat_n(
                levels.len() as u32 - 1,
                (s * s) as usize,
            ));
            if s == 1 {
                break;
            }
            s /= 2;
        }
        Texture {
            name: name.into(),
            encoding: Encoding::Srgb,
            levels,
            texels,
        }
    }

    #[test]
    fn textures_that_fit_are_flattened_whole() {
        let textures = [texture("a", 64), texture("b", 16)];
        let flat = flatten(&textures, u64::MAX).unwrap();
        assert!(flat.coarsened.is_empty());
        assert_eq!(
            flat.texels.len(),
            textures[0].texels.len() + textures[1].texels.len()
        );
        assert_eq!(
            flat.textures[1].level_first[0][0],
            textures[0].texels.len() as u32
        );
        assert_eq!((flat.textures[0].width, flat.textures[0].levels), (64, 7));
    }

    #[test]
    fn the_largest_texture_loses_its_finest_levels_until_the_texels_fit() {
        let textures = [texture("small", 64), texture("large", 256)];
        let whole: u64 = textures.iter().map(|t| bytes_from(t, 0)).sum();
        // Room for the small texture whole and the large one from its 64 x 64 level on.
        let limit = bytes_from(&textures[0], 0) + bytes_from(&textures[1], 2);
        assert!(limit < whole);
        let flat = flatten(&textures, limit).unwrap();
        assert_eq!(flat.texels.len() as u64 * 4, limit);
        assert_eq!(
            flat.coarsened,
            vec![("large".to_string(), [256, 256], [64, 64])]
        );
        let large = flat.textures[1];
        assert_eq!((large.width, large.height, large.levels), (64, 64, 7));
        // Each level of the entry starts at the texels of that level of the texture.
        for k in 0..large.levels as usize {
            let at = large.level_first[k / 4][k % 4] as usize;
            assert_eq!(flat.texels[at], (k + 2) as u32, "level {k}");
        }
        let small = flat.textures[0];
        assert_eq!(
            (small.width, small.levels, small.level_first[0][0]),
            (64, 7, 0)
        );
        // Two 1 x 1 levels need 8 bytes.
        let too_small = flatten(&textures, 7).unwrap_err().to_string();
        assert!(
            too_small.contains("even at their coarsest levels"),
            "{too_small}"
        );
    }
}
