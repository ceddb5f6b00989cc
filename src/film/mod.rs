//! The film every render path fills: the image (linear RGB), the per-pixel sums it is
//! accumulated in, comparisons of images, and the progressive schedule that decides which
//! samples to add next.

pub mod accumulation;
pub mod compare;
pub mod image;
pub mod progressive;

pub use accumulation::Accumulation;
pub use image::Image;

use std::ops::Range;

use crate::settings::RenderSettings;

/// The whole image of `settings`, the one rule every renderer (the CPU reference, the Vulkan
/// renderer, each path) follows: an AOV is one pass (`aov`); a traced shading is samples
/// `0..spp` added to a new accumulation of `width` x `height` (`accumulate`), then averaged.
/// `renderer` is handed to whichever runs; `T` is what it reports besides the image.
pub fn whole_image<R, T, E>(
    renderer: &mut R,
    (width, height): (u32, u32),
    settings: &RenderSettings,
    aov: impl FnOnce(&mut R) -> Result<(Image, T), E>,
    accumulate: impl FnOnce(&mut R, Range<u32>, &mut Accumulation) -> Result<T, E>,
) -> Result<(Image, T), E> {
    if settings.shading.is_aov() {
        return aov(renderer);
    }
    let mut accumulation = Accumulation::new(width, height);
    let report = accumulate(renderer, 0..settings.spp, &mut accumulation)?;
    Ok((accumulation.image(), report))
}
