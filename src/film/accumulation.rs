//! Per-pixel sums of samples: the state every render path adds samples to, so a render can be
//! continued (samples 0..8, then 8..16, give the image of 0..16 exactly).

use glam::Vec3;

use super::Image;

/// Row-major, one `[r, g, b, n]` per pixel: the sum of the pixel's samples and how many there
/// are (a float, as the GPU keeps it: exact up to 2^24 samples).
#[derive(Clone, Debug, PartialEq)]
pub struct Accumulation {
    pub width: u32,
    pub height: u32,
    pub sums: Vec<[f32; 4]>,
}

impl Accumulation {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            sums: vec![[0.0; 4]; width as usize * height as usize],
        }
    }

    /// The samples every pixel has (0 for an empty image).
    pub fn samples(&self) -> u32 {
        self.sums.iter().map(|s| s[3] as u32).min().unwrap_or(0)
    }

    /// The mean of each pixel's samples (black where there are none).
    pub fn image(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: self
                .sums
                .iter()
                .map(|&[r, g, b, n]| {
                    if n > 0.0 {
                        Vec3::new(r, g, b) / n
                    } else {
                        Vec3::ZERO
                    }
                })
                .collect(),
        }
    }
}
