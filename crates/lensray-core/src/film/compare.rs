//! How far a render is from a reference, and whether its error has structure: the statistics
//! the sampler's tests and benchmark (`benches/sampler.rs`) report.

use super::Image;

fn check_sizes(a: &Image, b: &Image) {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "images of different sizes"
    );
}

/// Root-mean-square difference over every pixel and channel.
pub fn rmse(image: &Image, reference: &Image) -> f64 {
    check_sizes(image, reference);
    let sum: f64 = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(p, q)| f64::from((*p - *q).length_squared()))
        .sum();
    (sum / (3 * image.pixels.len()) as f64).sqrt()
}

/// The per-pixel error `image - reference`, averaged over the channels.
pub fn error_image(image: &Image, reference: &Image) -> Vec<f64> {
    check_sizes(image, reference);
    image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(p, q)| f64::from((*p - *q).element_sum()) / 3.0)
        .collect()
}

/// The mean of the per-pixel errors and its standard error (pixels' errors taken as
/// independent, which is what the samplers promise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanError {
    pub mean: f64,
    pub standard_error: f64,
}

pub fn mean_error(image: &Image, reference: &Image) -> MeanError {
    let e = error_image(image, reference);
    let n = e.len() as f64;
    let mean = e.iter().sum::<f64>() / n;
    let variance = e.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0).max(1.0);
    MeanError {
        mean,
        standard_error: (variance / n).sqrt(),
    }
}

/// Correlation coefficient of two equally long series (0 when either is constant).
pub fn correlation(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += (x - ma) * (y - mb);
        aa += (x - ma) * (x - ma);
        bb += (y - mb) * (y - mb);
    }
    if aa == 0.0 || bb == 0.0 {
        0.0
    } else {
        ab / (aa * bb).sqrt()
    }
}

/// Correlation of the error of each pixel with that of its right neighbour and of its lower
/// neighbour: about 0 when neighbouring pixels' errors are independent, near 1 when the error
/// forms a visible pattern (the same sample positions in every pixel, say).
pub fn neighbour_correlation(image: &Image, reference: &Image) -> [f64; 2] {
    let e = error_image(image, reference);
    let (w, h) = (image.width as usize, image.height as usize);
    let at = |x: usize, y: usize| e[y * w + x];
    let pairs = |dx: usize, dy: usize| -> (Vec<f64>, Vec<f64>) {
        (0..h - dy)
            .flat_map(|y| (0..w - dx).map(move |x| (x, y)))
            .map(|(x, y)| (at(x, y), at(x + dx, y + dy)))
            .unzip()
    };
    let (a, b) = pairs(1, 0);
    let (c, d) = pairs(0, 1);
    [correlation(&a, &b), correlation(&c, &d)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn image(width: u32, height: u32, f: impl Fn(u32, u32) -> f32) -> Image {
        let mut img = Image::new(width, height);
        for y in 0..height {
            for x in 0..width {
                img.set(x, y, Vec3::splat(f(x, y)));
            }
        }
        img
    }

    #[test]
    fn rmse_and_mean_of_a_known_difference() {
        let a = image(4, 2, |x, _| x as f32);
        let b = image(4, 2, |_, _| 0.0);
        // Errors 0, 1, 2, 3 on both rows.
        assert!((rmse(&a, &b) - (14.0f64 / 4.0).sqrt()).abs() < 1e-12);
        let m = mean_error(&a, &b);
        assert!((m.mean - 1.5).abs() < 1e-12);
        let var = (2.25 + 0.25 + 0.25 + 2.25) * 2.0 / 7.0;
        assert!((m.standard_error - (var / 8.0f64).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn neighbour_correlation_sees_stripes_and_not_noise() {
        let zero = image(64, 64, |_, _| 0.0);
        // Vertical stripes two pixels wide: horizontal neighbours agree half the time, vertical
        // ones always.
        let stripes = image(64, 64, |x, _| if (x / 2) % 2 == 0 { 1.0 } else { -1.0 });
        let [horizontal, vertical] = neighbour_correlation(&stripes, &zero);
        assert!(
            horizontal.abs() < 0.05 && vertical > 0.99,
            "{horizontal} {vertical}"
        );
        let noise = image(64, 64, |x, y| {
            crate::sampler::unit_float(crate::sampler::hash_u32(y * 64 + x)) - 0.5
        });
        let [horizontal, vertical] = neighbour_correlation(&noise, &zero);
        assert!(
            horizontal.abs() < 0.1 && vertical.abs() < 0.1,
            "{horizontal} {vertical}"
        );
    }
}
