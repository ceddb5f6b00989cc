//! The starburst: the aperture's Fraunhofer diffraction (`aperture::diffraction`) as the film
//! sees it. A lens focused on a point images it as |F{A}|^2 scaled by lambda N on the film,
//! so the pattern of one aperture serves every wavelength and f-number: its bins are
//! lambda N / oversample mm. Each colour channel's kernel gathers the pattern at a few
//! wavelengths of its band into pixels (the pixel integrates the fine rings; the spikes'
//! envelope is what shows). The image is convolved with it (by FFT): every point of the image
//! is diffracted, and only the brightest show their spikes. Stopping down by a stop doubles
//! the spikes' length on the film; blades turn them with the aperture.

use glam::Vec3;
use rustfft::num_complex::Complex32;

use crate::camera::aperture::diffraction::{fft2, DiffractionPattern};
use crate::camera::aperture::Aperture;
use crate::film::Image;

/// Each channel's wavelengths (nm): red, green and blue bands, even weights.
pub const CHANNEL_WAVELENGTHS_NM: [[f64; 4]; 3] = [
    [590.0, 615.0, 640.0, 665.0],
    [505.0, 530.0, 555.0, 580.0],
    [430.0, 450.0, 470.0, 490.0],
];
/// Pattern bins to lambda N: enough that a pixel holds many of the rings' samples.
const OVERSAMPLE: usize = 2;
/// The largest pattern grid (its side): 2048^2 complex values, 32 MiB.
const LARGEST_PATTERN: usize = 2048;

/// Per colour channel, the share of a point's light each pixel around its image receives.
#[derive(Clone, Debug, PartialEq)]
pub struct Starburst {
    /// Pixels from the centre to the kernel's edge.
    pub radius: usize,
    /// (2 radius + 1)^2 per channel, row by row, the image's top row first; each sums to 1.
    pub kernels: [Vec<f32>; 3],
}

impl Starburst {
    /// The kernel of `aperture` at f-number `f_number` on a film of `pitch_mm` per pixel,
    /// reaching at most `largest_radius` pixels (less where the pattern's grid ends first).
    pub fn new(aperture: &Aperture, f_number: f64, pitch_mm: f64, largest_radius: usize) -> Self {
        let shortest = CHANNEL_WAVELENGTHS_NM[2][0];
        // The pattern reaches size / 2 bins of lambda N / OVERSAMPLE each.
        let bins_needed = 2.0 * largest_radius as f64 * pitch_mm * OVERSAMPLE as f64
            / (shortest * 1e-6 * f_number);
        let size = (bins_needed.ceil() as usize)
            .next_power_of_two()
            .clamp(64, LARGEST_PATTERN);
        let pattern = DiffractionPattern::of(aperture, size, OVERSAMPLE);
        let reach_mm = 0.5 * size as f64 * pattern.bin_mm(shortest, f_number);
        let radius = ((reach_mm / pitch_mm).floor() as usize).clamp(1, largest_radius.max(1));
        let side = 2 * radius + 1;
        let kernels = CHANNEL_WAVELENGTHS_NM.map(|band| {
            let mut kernel = vec![0.0f64; side * side];
            for &lambda in &band {
                let to_pixels = pattern.bin_mm(lambda, f_number) / pitch_mm;
                let half = (size / 2) as f64;
                for row in 0..size {
                    // The pattern's +y is up; the kernel's rows run down.
                    let dy = (row as f64 - half) * to_pixels;
                    let kernel_row = radius as f64 - dy;
                    if !(0.0..side as f64).contains(&(kernel_row + 0.5)) {
                        continue;
                    }
                    for column in 0..size {
                        let dx = (column as f64 - half) * to_pixels;
                        let kernel_column = radius as f64 + dx;
                        let (r, c) = ((kernel_row + 0.5).floor(), (kernel_column + 0.5).floor());
                        if c < 0.0 || c >= side as f64 || r < 0.0 || r >= side as f64 {
                            continue;
                        }
                        kernel[r as usize * side + c as usize] +=
                            f64::from(pattern.values[row * size + column]);
                    }
                }
            }
            // The pattern ends at the kernel's radius: a window (1 to half the radius, then a
            // cosine to 0 at it) keeps its square edge from showing around a very bright
            // source.
            for (i, k) in kernel.iter_mut().enumerate() {
                let (x, y) = (
                    (i % side) as f64 - radius as f64,
                    (i / side) as f64 - radius as f64,
                );
                let r = x.hypot(y) / radius as f64;
                *k *= match r {
                    r if r <= 0.5 => 1.0,
                    r if r >= 1.0 => 0.0,
                    r => (0.5 * std::f64::consts::PI * (r - 0.5) / 0.5).cos().powi(2),
                };
            }
            let total: f64 = kernel.iter().sum();
            kernel.iter().map(|&k| (k / total) as f32).collect()
        });
        Self { radius, kernels }
    }

    /// `image` convolved with the kernel, channel by channel (light past the image's edges
    /// is lost, and none comes in from outside).
    pub fn apply(&self, image: &mut Image) {
        let (width, height) = (image.width as usize, image.height as usize);
        let side = 2 * self.radius + 1;
        let (columns, rows) = (smooth(width + side - 1), smooth(height + side - 1));
        for (channel, kernel) in self.kernels.iter().enumerate() {
            let mut grid = vec![Complex32::new(0.0, 0.0); columns * rows];
            for y in 0..height {
                for x in 0..width {
                    grid[y * columns + x].re = image.pixels[y * width + x][channel];
                }
            }
            let mut spread = vec![Complex32::new(0.0, 0.0); columns * rows];
            for y in 0..side {
                for x in 0..side {
                    spread[y * columns + x].re = kernel[y * side + x];
                }
            }
            fft2(&mut grid, columns, rows, false);
            fft2(&mut spread, columns, rows, false);
            for (g, s) in grid.iter_mut().zip(&spread) {
                *g *= *s;
            }
            fft2(&mut grid, columns, rows, true);
            let scale = 1.0 / (columns * rows) as f32;
            for y in 0..height {
                for x in 0..width {
                    let value = grid[(y + self.radius) * columns + x + self.radius].re * scale;
                    let pixel: &mut Vec3 = &mut image.pixels[y * width + x];
                    pixel[channel] = value.max(0.0);
                }
            }
        }
    }
}

/// The least number at or above `n` with no prime factor above 5 (the FFT's quick sizes).
fn smooth(n: usize) -> usize {
    (n..)
        .find(|&m| {
            let mut m = m;
            for p in [2, 3, 5] {
                while m % p == 0 {
                    m /= p;
                }
            }
            m == 1
        })
        .expect("a smooth number")
}
