//! The aperture's far-field (Fraunhofer) diffraction pattern: the starburst a lens draws around
//! a bright source. For a lens focused on the source, the image of a point is |F{A}|^2, the
//! squared magnitude of the pupil function A's Fourier transform, at the spatial frequency
//! x / (lambda f) (Goodman, "Introduction to Fourier Optics", section 6.2). A round opening gives
//! the Airy pattern (its first dark ring at 1.22 lambda N); straight blades spread light
//! perpendicular to each edge, so N blades give N spikes when N is even (opposite edges are
//! parallel) and 2N when odd.
//!
//! The pupil is sampled on a grid (each cell the mean transmission of 4 x 4 points of the
//! aperture's shape, `Aperture::transmission`), its circumscribed diameter spanning
//! `size / oversample` cells, and transformed by rustfft. A bin of the pattern is then
//! lambda N / oversample on the film ([`DiffractionPattern::bin_mm`]): the spikes scale with
//! the wavelength and the f-number.

use rayon::prelude::*;
use rustfft::num_complex::Complex32;
use rustfft::FftPlanner;

use super::Aperture;
use glam::Vec2;

/// Points per cell side averaged into a cell's transmission.
const SUBSAMPLES: usize = 4;

/// The pattern on a square grid, the zero frequency at (size / 2, size / 2), summing to 1.
#[derive(Clone, Debug, PartialEq)]
pub struct DiffractionPattern {
    pub size: usize,
    /// Grid cells across the aperture's circumscribed diameter: `size / oversample`.
    pub oversample: usize,
    /// Row by row, +y up (the film's up once it is imaged), as the aperture's plane.
    pub values: Vec<f32>,
}

impl DiffractionPattern {
    /// The Fraunhofer pattern of `aperture` on a `size` x `size` grid, its diameter spanning
    /// `size / oversample` cells (`size` a multiple of `oversample`; more oversampling spreads
    /// the pattern over more bins).
    pub fn of(aperture: &Aperture, size: usize, oversample: usize) -> Self {
        assert!(size > 0 && oversample > 0 && size % oversample == 0);
        let cells = (size / oversample) as f32;
        let half = size / 2;
        let mut grid = vec![Complex32::new(0.0, 0.0); size * size];
        // Cells wholly past the shape's reach (and a cell's diagonal) let nothing through.
        let reach = aperture.reach() + 3.0 / cells;
        for row in 0..size {
            for column in 0..size {
                // The cell's sample in the unit shape's plane (radius 1 = half the diameter's
                // cells).
                let offset = |i: usize, s: f32| (i as f32 - half as f32 + s) * 2.0 / cells;
                if Vec2::new(offset(column, 0.5), offset(row, 0.5)).length() > reach {
                    continue;
                }
                let mut sum = 0.0;
                for sy in 0..SUBSAMPLES {
                    for sx in 0..SUBSAMPLES {
                        let sub = |s: usize| (s as f32 + 0.5) / SUBSAMPLES as f32;
                        let p = Vec2::new(offset(column, sub(sx)), offset(row, sub(sy)));
                        sum += aperture.transmission(p);
                    }
                }
                grid[row * size + column].re = sum / (SUBSAMPLES * SUBSAMPLES) as f32;
            }
        }
        fft2(&mut grid, size, size, false);
        // |F|^2, its zero frequency moved to the centre.
        let mut values = vec![0.0f32; size * size];
        for r in 0..size {
            for c in 0..size {
                let (rr, cc) = ((r + half) % size, (c + half) % size);
                values[rr * size + cc] = grid[r * size + c].norm_sqr();
            }
        }
        let total: f64 = values.iter().map(|&v| f64::from(v)).sum();
        for v in &mut values {
            *v = (f64::from(*v) / total) as f32;
        }
        Self {
            size,
            oversample,
            values,
        }
    }

    /// The film distance between neighbouring bins (mm) at wavelength `lambda_nm` through a
    /// lens at f-number `f_number`: lambda N / oversample.
    pub fn bin_mm(&self, lambda_nm: f64, f_number: f64) -> f64 {
        lambda_nm * 1e-6 * f_number / self.oversample as f64
    }

    /// The value at `p` bins from the centre, read bilinearly (0 off the grid).
    pub fn at(&self, p: Vec2) -> f32 {
        let half = (self.size / 2) as f32;
        let (x, y) = (p.x + half, p.y + half);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let value = |c: f32, r: f32| {
            let inside =
                c >= 0.0 && r >= 0.0 && (c as usize) < self.size && (r as usize) < self.size;
            if inside {
                self.values[r as usize * self.size + c as usize]
            } else {
                0.0
            }
        };
        (value(x0, y0) * (1.0 - fx) + value(x0 + 1.0, y0) * fx) * (1.0 - fy)
            + (value(x0, y0 + 1.0) * (1.0 - fx) + value(x0 + 1.0, y0 + 1.0) * fx) * fy
    }
}

/// The 2D discrete Fourier transform of `grid` (`columns` x `rows`, row by row) in place:
/// forward, or inverse (unscaled: the inverse of the forward times columns x rows).
pub(crate) fn fft2(grid: &mut [Complex32], columns: usize, rows: usize, inverse: bool) {
    assert_eq!(grid.len(), columns * rows);
    let mut planner = FftPlanner::<f32>::new();
    let plan = |planner: &mut FftPlanner<f32>, n| match inverse {
        false => planner.plan_fft_forward(n),
        true => planner.plan_fft_inverse(n),
    };
    let along_rows = plan(&mut planner, columns);
    let along_columns = plan(&mut planner, rows);
    grid.par_chunks_exact_mut(columns)
        .for_each(|row| along_rows.process(row));
    let mut transposed = vec![Complex32::new(0.0, 0.0); columns * rows];
    for r in 0..rows {
        for c in 0..columns {
            transposed[c * rows + r] = grid[r * columns + c];
        }
    }
    transposed
        .par_chunks_exact_mut(rows)
        .for_each(|column| along_columns.process(column));
    for c in 0..columns {
        for r in 0..rows {
            grid[r * columns + c] = transposed[c * rows + r];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::aperture::ApertureShape;

    fn iris(blades: Option<u32>) -> Aperture {
        Aperture::new(ApertureShape {
            blades,
            ..ApertureShape::ROUND
        })
    }

    /// A round opening's pattern is Airy's: its first dark ring at 1.2197 lambda N, which is
    /// 1.2197 oversample bins: along the x axis the bins are the pattern's own samples, and a
    /// parabola through the three around the least places the zero within 1 %.
    #[test]
    fn a_round_aperture_gives_the_airy_pattern() {
        let pattern = DiffractionPattern::of(&iris(None), 512, 16);
        let half = pattern.size / 2;
        let axis = |k: usize| f64::from(pattern.values[half * pattern.size + half + k]);
        let k = (12..28)
            .min_by(|&a, &b| axis(a).total_cmp(&axis(b)))
            .unwrap();
        let (a, b, c) = (axis(k - 1), axis(k), axis(k + 1));
        let first = k as f64 + 0.5 * (a - c) / (a - 2.0 * b + c);
        let airy = 1.2197 * 16.0;
        assert!(
            (first - airy).abs() < 0.01 * airy,
            "first dark ring at {first:.3} bins, Airy's at {airy:.3}"
        );
        // 550 nm at f/8 with 16 bins to lambda N: a bin is 0.275 um.
        assert!((pattern.bin_mm(550.0, 8.0) - 2.75e-4).abs() < 1e-12);
    }

    /// The pattern's spikes, from its angular spectrum: the rings of radius 30 to 90 bins
    /// (each's Fourier series in the angle, their magnitudes summed) repeat every 360 / m
    /// degrees for the fewest spikes m whose term is strong (a quarter of the strongest); the
    /// phase of that term puts a spike at its direction (degrees, in [0, 360 / m)).
    fn spikes(pattern: &DiffractionPattern) -> (usize, f32) {
        let n = 1440;
        let mut terms = vec![rustfft::num_complex::Complex64::new(0.0, 0.0); 61];
        for radius in (30..=90).step_by(10) {
            let ring: Vec<f64> = (0..n)
                .map(|k| {
                    let a = std::f32::consts::TAU * k as f32 / n as f32;
                    f64::from(pattern.at(Vec2::new(a.cos(), a.sin()) * radius as f32))
                })
                .collect();
            let mean = ring.iter().sum::<f64>() / n as f64;
            for (m, term) in terms.iter_mut().enumerate().skip(1) {
                let c: rustfft::num_complex::Complex64 = (0..n)
                    .map(|k| {
                        let a = std::f64::consts::TAU * (m * k) as f64 / n as f64;
                        rustfft::num_complex::Complex64::from_polar(ring[k] / mean, -a)
                    })
                    .sum();
                // Each ring's term, its phase kept: the rings' spikes point the same way.
                *term += c;
            }
        }
        let strongest = terms.iter().skip(1).map(|c| c.norm()).fold(0.0, f64::max);
        let m = (1..terms.len())
            .find(|&m| terms[m].norm() > 0.25 * strongest)
            .expect("a strong term");
        let step = 360.0 / m as f32;
        // A ring like cos(m (a - a0)) has the term's phase -m a0.
        let direction = (-terms[m].arg().to_degrees() as f32 / m as f32).rem_euclid(step);
        (m, direction)
    }

    /// N straight blades give N spikes when N is even and 2N when it is odd, each along an
    /// edge's normal, both ways: blades turned by 10 degrees have edge normals at
    /// 10 + 360 (k + 1/2) / N degrees, so the spikes lie at 10 + 180 / N + 360 j / N (N even)
    /// or 10 + 180 j / N (N odd, where each normal's opposite points at a vertex).
    #[test]
    fn blades_give_their_spikes() {
        for (blades, expected) in [(5u32, 10usize), (6, 6), (7, 14), (8, 8)] {
            let aperture = Aperture::new(ApertureShape {
                blades: Some(blades),
                rotation_degrees: 10.0,
                ..ApertureShape::ROUND
            });
            let pattern = DiffractionPattern::of(&aperture, 512, 4);
            let (count, direction) = spikes(&pattern);
            assert_eq!(count, expected, "{blades} blades: {count} spikes");
            let step = 360.0 / count as f32;
            let first = match blades % 2 {
                0 => 10.0 + 180.0 / blades as f32,
                _ => 10.0,
            };
            let off = (direction - first).rem_euclid(step);
            let off = off.min(step - off);
            assert!(
                off < 1.0,
                "{blades} blades: a spike at {direction} degrees, not {first} (mod {step})"
            );
        }
    }
}
