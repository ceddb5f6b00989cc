//! Where camera rays aim (after pbrt's exit-pupil bounds): for film points at each distance
//! from the film's centre, a region of the rear vertex's plane holding every point that rays
//! passing the lens cross. Sampling it, instead of the whole rear element, lets most rays
//! through. Regions are found for film points on +x and turned to each film point's angle,
//! the lens being symmetric about its axis (a shaped stop is bounded by its circumscribed
//! circle).
//!
//! - The region at each bin edge (film radius `r_k`) is the bounding rectangle of the passing
//!   points of a grid, grown by one grid step (the edge lies between a passing point and a
//!   failing one). (Ellipses inscribed in the rectangles were tried: off the axis the pupil
//!   is at once cut by a second opening, and the cut shape pokes out of them.)
//! - Between two edges the region's centre and half sides are interpolated (the pupil slides
//!   and narrows smoothly). Each bin checks this at its middle radius: if the points passing
//!   there do not fit the interpolated region, the bin falls back to one rectangle bounding
//!   the regions of both edges and of the middle.
//! - A tilted lens's film is not square to its axis: the film points at one distance r from
//!   the axis lie up to r tan(tilt) nearer or farther along it (`FilmFrame::slope`). Each
//!   search then takes the points that pass from any of three film points at r, at either end
//!   of that span and in its middle (the region moves smoothly with the film point's depth,
//!   as it does with r).

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::lanes::Lanes;
use super::RealLens;
#[cfg(test)]
use crate::optics::trace::{narrow::LensRay, Toward};

/// Distances from the film's centre with their own regions, from 0 to the film's corner.
pub const PUPIL_BINS: usize = 64;
/// Grid points a side of each search (coarse over the rear element, then fine over the
/// coarse bounds).
const GRID: u32 = 80;
/// Grid points traced together: a packet's width (`reference::PACKET_SIZE`).
const GRID_LANES: usize = 16;
/// Side of the grid that integrates the centre's irradiance.
const CENTRE_GRID: u32 = 512;

#[derive(Clone, Debug, PartialEq)]
pub struct ExitPupil {
    /// Lens-space z of the rear vertex's plane, where the regions lie.
    pub rear_z: f32,
    /// The film's half diagonal, mm: the last bin's outer edge (how far a tilted or shifted
    /// film reaches from the axis).
    pub film_radius: f32,
    /// How far the film lies behind the rear plane where it crosses the axis, mm (a film
    /// point's weight has (axis_depth / its own depth)^2, `RealLens::finish`).
    pub axis_depth: f32,
    /// Per bin, for film points on +x, the region the rays are drawn from.
    pub bins: Vec<PupilBin>,
    /// 1 / the integral of T cos^4(theta) over the passing region seen from the film's
    /// centre (mm^-2; see the parent module's radiometry); 0 if nothing passes.
    pub inverse_centre_integral: f32,
}

/// A rectangle of the rear plane, by its centre and half sides (zero: nothing passes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub centre: Vec2,
    pub half: Vec2,
}

impl Region {
    const EMPTY: Region = Region {
        centre: Vec2::ZERO,
        half: Vec2::ZERO,
    };

    fn lo(&self) -> Vec2 {
        self.centre - self.half
    }

    fn hi(&self) -> Vec2 {
        self.centre + self.half
    }

    fn is_empty(&self) -> bool {
        self.half.x <= 0.0 || self.half.y <= 0.0
    }

    fn union(&self, other: &Region) -> Region {
        if self.is_empty() {
            return *other;
        }
        if other.is_empty() {
            return *self;
        }
        let (lo, hi) = (self.lo().min(other.lo()), self.hi().max(other.hi()));
        Region {
            centre: 0.5 * (lo + hi),
            half: 0.5 * (hi - lo),
        }
    }
}

/// One bin's regions: at its inner and outer film radius, interpolated between.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PupilBin {
    pub inner: Region,
    pub outer: Region,
}

impl PupilBin {
    const EMPTY: PupilBin = PupilBin {
        inner: Region::EMPTY,
        outer: Region::EMPTY,
    };

    /// The region at fraction `f` in [0, 1] of the way from the inner to the outer radius.
    pub fn region(&self, f: f32) -> Region {
        Region {
            centre: self.inner.centre + f * (self.outer.centre - self.inner.centre),
            half: self.inner.half + f * (self.outer.half - self.inner.half),
        }
    }

    /// The area of the region at `f`, mm^2.
    pub fn area(&self, f: f32) -> f32 {
        let half = self.region(f).half;
        4.0 * half.x.max(0.0) * half.y.max(0.0)
    }

    /// The point lens sample `u` in [0, 1)^2 picks, uniform over the region at `f`.
    pub fn point(&self, f: f32, u: Vec2) -> Vec2 {
        let region = self.region(f);
        region.centre + region.half * (2.0 * u - Vec2::ONE)
    }

    /// Whether every point lies inside the region at `f`, `margin` inside its edge.
    fn holds(&self, f: f32, points: &[Vec2], margin: Vec2) -> bool {
        let region = self.region(f);
        let inner = region.half - margin;
        if inner.x <= 0.0 || inner.y <= 0.0 {
            return points.is_empty();
        }
        points.iter().all(|&q| {
            let d = (q - region.centre) / inner;
            d.x.abs() <= 1.0 && d.y.abs() <= 1.0
        })
    }
}

impl ExitPupil {
    pub const EMPTY: ExitPupil = ExitPupil {
        rear_z: 0.0,
        film_radius: 0.0,
        axis_depth: 0.0,
        bins: Vec::new(),
        inverse_centre_integral: 0.0,
    };

    /// The regions of `lens` (everything but its `pupil` built) for a film reaching
    /// `film_radius` mm from the centre.
    pub fn bound(lens: &RealLens, film_radius: f32) -> Self {
        let search = Search::of(lens);
        let rear_z = search.rear_z;
        let radius = |k: usize| film_radius * k as f32 / PUPIL_BINS as f32;
        let edges: Vec<Edge> = (0..=PUPIL_BINS)
            .into_par_iter()
            .map(|k| search.edge(radius(k)))
            .collect();
        let bins: Vec<PupilBin> = (0..PUPIL_BINS)
            .into_par_iter()
            .map(|bin| {
                let middle = search.passing(0.5 * (radius(bin) + radius(bin + 1)));
                Edge::bin(&edges[bin], &edges[bin + 1], &middle)
            })
            .collect();
        let mut pupil = ExitPupil {
            rear_z,
            film_radius,
            axis_depth: search.film_z - rear_z,
            bins,
            inverse_centre_integral: 0.0,
        };
        let integral = pupil.centre_integral(lens);
        if integral > 0.0 {
            pupil.inverse_centre_integral = (1.0 / integral) as f32;
        }
        pupil
    }

    /// How far from the axis light reaches the film, mm: the outer edge of the last bin whose
    /// regions pass any ray (the film radius itself if every bin does).
    pub fn image_circle(&self) -> f32 {
        let lit = |r: &Region| !r.is_empty();
        let step = self.film_radius / PUPIL_BINS as f32;
        match self
            .bins
            .iter()
            .rposition(|b| lit(&b.inner) || lit(&b.outer))
        {
            Some(last) if lit(&self.bins[last].outer) => step * (last + 1) as f32,
            Some(last) => step * last as f32,
            None => 0.0,
        }
    }

    /// Whether any ray from film point `film` (lens space) passes `lens`, on a grid over the
    /// rear element 4 times as fine as the search's coarse one (a far corner at f/8 passes
    /// light through a sliver of the rear plane).
    pub fn lights(&self, lens: &RealLens, film: Vec3) -> bool {
        let rear = lens
            .elements()
            .interfaces
            .last()
            .expect("a lens has surfaces");
        let search = Search {
            lens,
            film_z: film.z,
            film_slope: 0.0,
            rear_z: self.rear_z,
            whole: Region {
                centre: Vec2::ZERO,
                half: Vec2::splat(1.5 * rear.aperture_radius),
            },
        };
        !search
            .grid_of(&[film], search.whole, 4 * GRID)
            .points
            .is_empty()
    }

    /// The bin of film points `r` mm from the centre, and how far across it `r` lies.
    pub fn bin_at(&self, r: f32) -> (&PupilBin, f32) {
        let t = r / self.film_radius * PUPIL_BINS as f32;
        let bin = (t as usize).min(PUPIL_BINS - 1);
        (&self.bins[bin], (t - bin as f32).clamp(0.0, 1.0))
    }

    /// The point of the rear plane that lens sample `u` picks for film point `film`, turned
    /// to the film point's angle, and the area of the region it was drawn from (mm^2).
    pub fn sample(&self, film: Vec3, u: Vec2) -> (Vec3, f32) {
        let r = Vec2::new(film.x, film.y).length();
        let (bin, f) = self.bin_at(r);
        let q = bin.point(f, u);
        let (cos, sin) = if r > 0.0 {
            (film.x / r, film.y / r)
        } else {
            (1.0, 0.0)
        };
        let turned = Vec2::new(cos * q.x - sin * q.y, sin * q.x + cos * q.y);
        (turned.extend(self.rear_z), bin.area(f))
    }

    /// The integral of T cos^4(theta) dA over the rear plane, for the film's centre: a
    /// midpoint rule over its region (what `RealLens::generate_ray` averages to, there).
    fn centre_integral(&self, lens: &RealLens) -> f64 {
        let region = self.bins[0].inner;
        if region.is_empty() {
            return 0.0;
        }
        let cell = 2.0 * region.half / CENTRE_GRID as f32;
        let sum: f64 = (0..CENTRE_GRID)
            .into_par_iter()
            .map(|j| self.centre_row(lens, j))
            .sum();
        sum * f64::from(cell.x * cell.y)
    }

    /// Row `j` of the centre integral's grid: the sum of T cos^4(theta) over its cells, the
    /// rays traced `GRID_LANES` at a time and summed in the row's order.
    fn centre_row(&self, lens: &RealLens, j: u32) -> f64 {
        let (film, row) = self.centre_cells(lens, j);
        let mut sum = 0.0;
        for chunk in row.chunks(GRID_LANES) {
            let mut lanes = Lanes::<GRID_LANES>::toward(film, chunk, self.rear_z, 0.0);
            let start_dz = lanes.dz;
            lanes.trace_to_scene(lens);
            let lit = lanes.alive.iter().zip(lanes.transmission).zip(start_dz);
            for ((&alive, t), dz) in lit.take(chunk.len()) {
                if alive {
                    let cos2 = f64::from(dz * dz);
                    sum += f64::from(t) * cos2 * cos2;
                }
            }
        }
        sum
    }

    /// The film's centre and the midpoints of row `j` of the centre integral's grid.
    fn centre_cells(&self, lens: &RealLens, j: u32) -> (Vec3, Vec<Vec2>) {
        let region = self.bins[0].inner;
        let lo = region.lo();
        let cell = 2.0 * region.half / CENTRE_GRID as f32;
        let row = (0..CENTRE_GRID)
            .map(|i| lo + cell * Vec2::new(i as f32 + 0.5, j as f32 + 0.5))
            .collect();
        (Vec3::new(0.0, 0.0, lens.film_z()), row)
    }

    /// [`Self::centre_row`] one ray at a time (`RealLens::trace_to_scene`): the definition
    /// the lanes are checked against.
    #[cfg(test)]
    fn centre_row_one_by_one(&self, lens: &RealLens, j: u32) -> f64 {
        let (film, row) = self.centre_cells(lens, j);
        let mut sum = 0.0;
        for q in row {
            let direction = (q.extend(self.rear_z) - film).normalize();
            let ray = LensRay {
                origin: film,
                direction,
            };
            if let Some((_, t)) = lens.trace_to_scene(ray) {
                let cos2 = f64::from(direction.z * direction.z);
                sum += f64::from(t) * cos2 * cos2;
            }
        }
        sum
    }
}

/// Finds where rays from film points on +x pass.
struct Search<'a> {
    lens: &'a RealLens,
    /// Where the film crosses the axis, and tan(tilt) (`FilmFrame::slope`).
    film_z: f32,
    film_slope: f32,
    rear_z: f32,
    /// Where to look first.
    whole: Region,
}

/// The grid points of a rectangle of the rear plane that rays from one film point pass
/// through, with the grid's spacing.
struct Passing {
    points: Vec<Vec2>,
    step: Vec2,
}

/// The region found at one film radius.
struct Edge {
    passing: Passing,
    /// The passing points' bounds grown by a step.
    rectangle: Region,
}

impl<'a> Search<'a> {
    fn of(lens: &'a RealLens) -> Self {
        let interfaces = &lens.elements().interfaces;
        let rear = interfaces[interfaces.len() - 1];
        let film = lens.film();
        Search {
            lens,
            film_z: film.axis_z,
            film_slope: film.slope(),
            rear_z: rear.z,
            // The rear element's clear aperture, with room for rays that cross its plane
            // beside it (pbrt's 1.5).
            whole: Region {
                centre: Vec2::ZERO,
                half: Vec2::splat(1.5 * rear.aperture_radius),
            },
        }
    }

    /// The passing points for film radius `r`: a coarse grid over the whole search, then a
    /// fine one over the coarse bounds.
    fn passing(&self, r: f32) -> Passing {
        let films = self.films(r);
        let coarse = self.grid(&films, self.whole);
        match coarse.bounds() {
            Some(bounds) => self.grid(&films, bounds),
            None => coarse,
        }
    }

    /// The film points at distance `r` on +x: one, or on a tilted film three, at either end
    /// of the depths it spans there and in the middle.
    fn films(&self, r: f32) -> Vec<Vec3> {
        let at = |k: f32| Vec3::new(r, 0.0, self.film_z + k * r * self.film_slope);
        if self.film_slope == 0.0 {
            vec![at(0.0)]
        } else {
            vec![at(-1.0), at(0.0), at(1.0)]
        }
    }

    fn edge(&self, r: f32) -> Edge {
        let passing = self.passing(r);
        let rectangle = passing.bounds().unwrap_or(Region::EMPTY);
        Edge { passing, rectangle }
    }

    /// The points of a `GRID` x `GRID` grid over `region` that rays from any of `films` pass,
    /// at any of the lens's bounding wavelengths (`RealLens::bounding_offsets`).
    fn grid(&self, films: &[Vec3], region: Region) -> Passing {
        self.grid_of(films, region, GRID)
    }

    /// [`Self::grid`] with `n` points a side. The points are traced `GRID_LANES` at a time
    /// (`Lanes::trace_elements`, bit for bit the one-by-one trace).
    fn grid_of(&self, films: &[Vec3], region: Region, n: u32) -> Passing {
        let (lo, hi) = (region.lo(), region.hi());
        let step = (hi - lo) / (n - 1) as f32;
        let offsets = self.lens.bounding_offsets();
        let elements = self.lens.elements();
        let grid: Vec<Vec2> = (0..n)
            .flat_map(|j| (0..n).map(move |i| lo + step * Vec2::new(i as f32, j as f32)))
            .collect();
        let mut points = Vec::new();
        for chunk in grid.chunks(GRID_LANES) {
            let mut passes = [false; GRID_LANES];
            'rays: for &film in films {
                for &k in &offsets {
                    let mut lanes = Lanes::<GRID_LANES>::toward(film, chunk, self.rear_z, k);
                    lanes.trace_elements(elements);
                    for (pass, alive) in passes.iter_mut().zip(lanes.alive) {
                        *pass |= alive;
                    }
                    if passes[..chunk.len()].iter().all(|&p| p) {
                        break 'rays;
                    }
                }
            }
            points.extend(
                chunk
                    .iter()
                    .zip(passes)
                    .filter(|(_, p)| *p)
                    .map(|(q, _)| *q),
            );
        }
        Passing { points, step }
    }

    /// [`Self::grid_of`] one ray at a time (`Elements::trace_at`): the definition the lanes
    /// are checked against.
    #[cfg(test)]
    fn grid_one_by_one(&self, films: &[Vec3], region: Region, n: u32) -> Passing {
        let (lo, hi) = (region.lo(), region.hi());
        let step = (hi - lo) / (n - 1) as f32;
        let offsets = self.lens.bounding_offsets();
        let elements = self.lens.elements();
        let mut points = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let q = lo + step * Vec2::new(i as f32, j as f32);
                let passes = |&film: &Vec3| {
                    let ray = LensRay {
                        origin: film,
                        direction: (q.extend(self.rear_z) - film).normalize(),
                    };
                    let at = |&k: &f32| elements.trace_at(ray, Toward::Scene, k).is_some();
                    offsets.iter().any(at)
                };
                if films.iter().any(passes) {
                    points.push(q);
                }
            }
        }
        Passing { points, step }
    }
}

impl Passing {
    /// The points' bounds grown by one step; `None` if none passes.
    fn bounds(&self) -> Option<Region> {
        let first = *self.points.first()?;
        let (min, max) = self
            .points
            .iter()
            .fold((first, first), |(lo, hi), &q| (lo.min(q), hi.max(q)));
        let (lo, hi) = (min - self.step, max + self.step);
        Some(Region {
            centre: 0.5 * (lo + hi),
            half: 0.5 * (hi - lo),
        })
    }
}

impl Edge {
    /// The bin between edges `inner` and `outer`, checked against the points `middle` that
    /// pass at its middle radius.
    fn bin(inner: &Edge, outer: &Edge, middle: &Passing) -> PupilBin {
        if inner.rectangle.is_empty() && outer.rectangle.is_empty() && middle.points.is_empty() {
            return PupilBin::EMPTY;
        }
        let both_filled = !inner.rectangle.is_empty() && !outer.rectangle.is_empty();
        let step = inner.passing.step.max(outer.passing.step).max(middle.step);
        let interpolated = PupilBin {
            inner: inner.rectangle,
            outer: outer.rectangle,
        };
        // The middle's region reaches a step past its points.
        if both_filled && interpolated.holds(0.5, &middle.points, step) {
            return interpolated;
        }
        let middle = middle.bounds().unwrap_or(Region::EMPTY);
        let all = inner.rectangle.union(&outer.rectangle).union(&middle);
        PupilBin {
            inner: all,
            outer: all,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::camera::real_lens::RealLensParams;
    use crate::camera::{Aperture, Movements};

    /// The grid traced in lanes passes exactly the points the one-by-one trace passes: at the
    /// d line and across the spectrum, square to the film and tilted, with an asphere, over
    /// the whole search and over a passing region's bounds, at radii from the axis to past
    /// the image circle. The centre integral's rows in lanes are the one-by-one sums.
    #[test]
    fn lanes_pass_the_points_one_by_one_passes() {
        let tilted = Movements {
            shift: [0.0, 0.0],
            tilt_degrees: 6.0,
            tilt_direction_degrees: 0.0,
        };
        let six_blades = Aperture::new(crate::camera::ApertureShape {
            blades: Some(6),
            rotation_degrees: 10.0,
            ..Default::default()
        });
        for (name, dispersion, movements, aperture) in [
            ("double-gauss-50", false, Movements::NONE, Aperture::ROUND),
            ("double-gauss-50", true, tilted, Aperture::ROUND),
            ("aspheric-31", true, Movements::NONE, Aperture::ROUND),
            ("wide-22", true, Movements::NONE, six_blades),
        ] {
            let params = RealLensParams {
                prescription: Arc::new(crate::optics::builtin::lens(name).expect("built in")),
                f_number: None,
                focus_distance: 3.0,
                sensor_height_mm: 24.0,
                dispersion,
                movements,
            };
            let real = RealLens::new(params, 1.5, aperture.clone()).expect("a lens");
            let search = Search::of(&real);
            let corner = real.pupil().film_radius;
            let mut passed = 0;
            for r in [0.0, 0.3, 0.7, 1.0, 1.2].map(|f| f * corner) {
                let films = search.films(r);
                let coarse = search.grid_one_by_one(&films, search.whole, 37);
                let regions = [Some(search.whole), coarse.bounds()];
                for region in regions.into_iter().flatten() {
                    let lanes = search.grid_of(&films, region, 37);
                    let one_by_one = search.grid_one_by_one(&films, region, 37);
                    assert_eq!(lanes.points, one_by_one.points, "{name} at r = {r} mm");
                    assert_eq!(lanes.step, one_by_one.step);
                    passed += lanes.points.len();
                }
            }
            assert!(passed > 1000, "{name}: only {passed} points pass");
            // The centre integral's rows, bit for bit (the stop's shape counts there).
            let pupil = real.pupil();
            for j in [0, CENTRE_GRID / 3, CENTRE_GRID / 2, CENTRE_GRID - 1] {
                let (lanes, one_by_one) = (
                    pupil.centre_row(&real, j),
                    pupil.centre_row_one_by_one(&real, j),
                );
                assert_eq!(lanes.to_bits(), one_by_one.to_bits(), "{name}, row {j}");
            }
        }
    }
}
