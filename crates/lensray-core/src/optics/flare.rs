//! The ghosts of a distant point source (a sun) on the film of a lens focused at infinity: a
//! grid of parallel rays over the front surface's clear aperture, each traced along every
//! ghost's path (`ghost::ghost_throughput`) and directly, the power each carries gathered
//! into the film's bins. What reaches the paraxial focal plane directly is the source's own
//! image; the ghosts are light reflected twice inside the lens, shaped by the stop (the
//! aperture's shape, as Hullin et al. 2011 trace them), coloured by the coatings' and glasses'
//! dependence on wavelength.

use glam::DVec3;

use super::coating::Coating;
use super::ghost::ghost_throughput;
use super::glass::dispersion_offset;
use super::paraxial::FirstOrder;
use super::prescription::Prescription;
use super::trace::wide::{Elements, LensRay};
use super::trace::Toward;

/// Where the light of a source lands on the film, gathered into square bins.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmLight {
    /// Bins across and down, centred on the axis: bin (0, 0) is the film's lower left.
    pub bins: (usize, usize),
    /// A bin's side, mm.
    pub bin_mm: f64,
    /// Power per bin, per wavelength (in the order asked), as a share of the power entering
    /// the front surface's clear aperture.
    pub direct: Vec<Vec<f64>>,
    pub ghosts: Vec<Vec<f64>>,
}

impl FilmLight {
    /// The film point (mm, from the axis) of bin `(column, row)`'s centre.
    pub fn centre(&self, column: usize, row: usize) -> (f64, f64) {
        let (w, h) = self.bins;
        (
            (column as f64 + 0.5 - 0.5 * w as f64) * self.bin_mm,
            (row as f64 + 0.5 - 0.5 * h as f64) * self.bin_mm,
        )
    }
}

/// The light on the film of `lens` (focused at infinity) from a point source at infinity
/// `degrees` off the axis along +x, at `wavelengths_nm`: `grid` x `grid` rays over the front
/// surface's clear aperture, each surface under `coatings`, gathered into `bins` of
/// `bin_mm`.
pub fn distant_source(
    lens: &Prescription,
    coatings: &[Coating],
    degrees: f64,
    wavelengths_nm: &[f64],
    (grid, bins, bin_mm): (usize, (usize, usize), f64),
) -> FilmLight {
    let elements = Elements::new(lens);
    let n = elements.interfaces.len();
    let film_z = lens.length() + FirstOrder::of(lens).bfl;
    let radius = 0.5 * lens.surfaces()[0].diameter;
    let direction = DVec3::new(degrees.to_radians().sin(), 0.0, degrees.to_radians().cos());
    let cell = 2.0 * radius / grid as f64;
    let share = 1.0 / (std::f64::consts::PI * radius * radius) * cell * cell;
    let mut light = FilmLight {
        bins,
        bin_mm,
        direct: vec![vec![0.0; bins.0 * bins.1]; wavelengths_nm.len()],
        ghosts: vec![vec![0.0; bins.0 * bins.1]; wavelengths_nm.len()],
    };
    let bin_of = |ray: LensRay| -> Option<usize> {
        let t = (film_z - ray.origin.z) / ray.direction.z;
        let p = ray.origin + t * ray.direction;
        let column = (p.x / bin_mm + 0.5 * bins.0 as f64).floor();
        let row = (p.y / bin_mm + 0.5 * bins.1 as f64).floor();
        let inside = column >= 0.0 && row >= 0.0;
        let (column, row) = (column as usize, row as usize);
        (inside && column < bins.0 && row < bins.1).then_some(row * bins.0 + column)
    };
    for gy in 0..grid {
        for gx in 0..grid {
            let x = (gx as f64 + 0.5) * cell - radius;
            let y = (gy as f64 + 0.5) * cell - radius;
            if x * x + y * y > radius * radius {
                continue;
            }
            // 1 mm in front of the first vertex, through the grid point in its plane.
            let ray = LensRay {
                origin: DVec3::new(x, y, 0.0) - direction / direction.z,
                direction,
            };
            for (w, &lambda) in wavelengths_nm.iter().enumerate() {
                let k = dispersion_offset(lambda);
                if let Some(bin) = elements.trace_at(ray, Toward::Film, k).and_then(bin_of) {
                    light.direct[w][bin] += share;
                }
                for i in 0..n {
                    for j in i + 1..n {
                        let Some((out, carried)) =
                            ghost_throughput(&elements, coatings, ray, (i, j), lambda)
                        else {
                            continue;
                        };
                        if let Some(bin) = bin_of(out) {
                            light.ghosts[w][bin] += share * carried;
                        }
                    }
                }
            }
        }
    }
    light
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::builtin;

    /// A sun 10 degrees off the axis through double-gauss-50 (coated air-glass surfaces) at
    /// three wavelengths, as the checks ask of the flare:
    /// - the ghosts are mirror-symmetric about the line through the film's centre and the
    ///   source's image (the x axis: the lens is rotationally symmetric);
    /// - ghost light outside the source's neighbourhood (1 mm) is between 1e-5 and 5e-2 of the
    ///   source's;
    /// - part of it falls on the far side of the centre;
    /// - without coatings the ghosts are much brighter.
    #[test]
    fn a_distant_source_s_ghosts_are_symmetric_faint_and_spread() {
        let lens = builtin::lens("double-gauss-50").unwrap();
        let coatings: Vec<Coating> = (0..lens.surfaces().len())
            .map(
                |s| match lens.index_before(s) == 1.0 || lens.surfaces()[s].index == 1.0 {
                    true => Coating::default(),
                    false => Coating::Uncoated,
                },
            )
            .collect();
        let bins = (72, 48);
        let light = distant_source(
            &lens,
            &coatings,
            10.0,
            &[610.0, 550.0, 465.0],
            (120, bins, 0.5),
        );
        let (w, h) = bins;
        for band in 0..3 {
            let (direct, ghosts) = (&light.direct[band], &light.ghosts[band]);
            // The source's image: the brightest direct bin.
            let brightest = (0..w * h)
                .max_by(|&a, &b| direct[a].total_cmp(&direct[b]))
                .unwrap();
            let (sx, sy) = light.centre(brightest % w, brightest / w);
            assert!(
                sy.abs() < light.bin_mm,
                "the source images on the x axis, at {sy} mm"
            );
            let source: f64 = direct.iter().sum();
            let (mut away, mut far_side, mut total) = (0.0, 0.0, 0.0);
            for row in 0..h {
                for column in 0..w {
                    let value = ghosts[row * w + column];
                    let mirrored = ghosts[(h - 1 - row) * w + column];
                    assert!(
                        (value - mirrored).abs() <= 1e-9 * value.max(mirrored).max(1e-30),
                        "band {band}: bin ({column}, {row}) {value} against its mirror {mirrored}"
                    );
                    let (x, y) = light.centre(column, row);
                    total += value;
                    if (x - sx).hypot(y - sy) > 1.0 {
                        away += value;
                    }
                    if x * sx < 0.0 {
                        far_side += value;
                    }
                }
            }
            let ratio = away / source;
            println!(
                "band {band}: the source at {sx:.2} mm; ghost light away from it {ratio:.3e} of the source's, {:.1} % of it past the centre",
                100.0 * far_side / total
            );
            assert!(
                (1e-5..5e-2).contains(&ratio),
                "band {band}: ghosts {ratio:.3e} of the source"
            );
            assert!(
                far_side > 0.01 * total,
                "band {band}: {far_side} of {total} past the centre"
            );
        }
        // Bare air-glass surfaces reflect 4 to 7 % each, coated ones about 1 % or less near
        // 550 nm: a ghost of two is tens of times brighter bare (measured: 100 times).
        let bare = vec![Coating::Uncoated; coatings.len()];
        let uncoated = distant_source(&lens, &bare, 10.0, &[550.0], (120, bins, 0.5));
        let ghosts = |l: &FilmLight, band: usize| l.ghosts[band].iter().sum::<f64>();
        let gain = ghosts(&uncoated, 0) / ghosts(&light, 1);
        println!("uncoated, the ghosts are {gain:.1} times brighter at 550 nm");
        assert!(gain > 5.0, "uncoated ghosts only {gain} times the coated");
    }
}
