//! The film every render path fills: the image (linear RGB), the per-pixel sums it is
//! accumulated in, comparisons of images, and the progressive schedule that decides which
//! samples to add next.

pub mod accumulation;
pub mod compare;
pub mod image;
pub mod progressive;

pub use accumulation::Accumulation;
pub use image::Image;
