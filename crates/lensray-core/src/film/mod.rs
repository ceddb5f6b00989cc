//! The film every render path fills: the image (linear RGB), the per-pixel sums it is
//! accumulated in, comparisons of images, the progressive schedule that decides which
//! samples to add next, adaptive sampling's rounds and error estimate (`adaptive`), the weighting of a sample of one wavelength (`spectral`), and the
//! exposure and tone map of what is shown (`tonemap`).

pub mod accumulation;
pub mod adaptive;
pub mod colour;
pub mod compare;
pub mod image;
pub mod progressive;
pub mod spectral;
pub mod tonemap;

pub use accumulation::{Accumulation, Holder, OnDevice, Sums};
pub use image::Image;

use std::ops::Range;

use crate::settings::Shot;

/// What renderers report progress through: `(done, total)`.
pub type Progress<'a> = dyn FnMut(u64, u64) + 'a;

/// The whole image of `shot`, the one rule every renderer (the CPU reference, the Vulkan
/// renderer, each path) follows: an AOV is one pass (`aov`); a traced shading is samples
/// `0..spp` added to a new accumulation of the camera's size (`accumulate`), its sums brought
/// to the host once (`read`: a device keeps them while it adds), then averaged. Whichever runs
/// gets `renderer` and `progress`; `T` is what it reports besides the image.
pub fn whole_image<R: ?Sized, T, E: From<OnDevice>>(
    renderer: &mut R,
    progress: &mut Progress<'_>,
    shot: &Shot,
    aov: impl FnOnce(&mut R, &mut Progress<'_>) -> Result<(Image, T), E>,
    accumulate: impl FnOnce(&mut R, Range<u32>, &mut Accumulation, &mut Progress<'_>) -> Result<T, E>,
    read: impl FnOnce(&mut R, &mut Accumulation) -> Result<(), E>,
) -> Result<(Image, T), E> {
    if shot.render.shading.is_aov() {
        return aov(renderer, progress);
    }
    let mut accumulation = Accumulation::new(shot.camera.width, shot.camera.height);
    let report = accumulate(renderer, 0..shot.render.spp, &mut accumulation, progress)?;
    read(renderer, &mut accumulation)?;
    Ok((accumulation.image()?, report))
}

/// An image made in one pass (a G-buffer AOV), its progress 0 of 1, then 1 of 1.
pub fn one_pass<E>(
    progress: &mut Progress<'_>,
    pass: impl FnOnce() -> Result<Image, E>,
) -> Result<(Image, ()), E> {
    progress(0, 1);
    let image = pass()?;
    progress(1, 1);
    Ok((image, ()))
}
