//! The ghosts of a distant point source (a sun, or any source far from the lens against its
//! pupil) on a real lens's film, as Hullin, Eisemann, Seidel and Lee (2011) draw them: a grid
//! of parallel rays over the front surface's clear aperture, traced along every ghost's path
//! (two reflections, `optics::ghost`) without clipping; each grid cell's four rays make a
//! quad on the film, drawn as two triangles that spread the cell's power evenly over the bins
//! whose centres they cover. Across a triangle the stop's crossings and the rims' reach are
//! interpolated from its corners and the bins past them are dropped, so a ghost takes the
//! stop's exact shape (blades, roundness) whatever the grid. The direct path, traced the same
//! way without coatings, is the source's own image: the share of the light a renderer draws.
//!
//! Film coordinates are lens space's x and y (mm) on the film's plane; the source lies along
//! +x off the axis, and a lens that is rotationally symmetric turns the result to any other
//! direction.

use glam::{DVec2, DVec3, Vec2};
use rayon::prelude::*;

use crate::camera::aperture::Aperture;
use crate::camera::RealLens;
use crate::optics::coating::Coating;
use crate::optics::ghost::{ghost_vertex, GhostVertex};
use crate::optics::glass::LAMBDA_D_NM;
use crate::optics::prescription::Prescription;
use crate::optics::trace::wide::{Elements, LensRay};

/// A triangle whose box holds more than this share of the film's bins spreads its light too
/// thin to show (a grid cell of a ghost far out of focus); it is left out.
const LARGEST_TRIANGLE_SHARE: f64 = 0.25;
/// Pairs of surfaces each of a task's film copies gathers: the tasks' copies are summed in
/// order, so a result does not depend on how the threads shared the work.
const PAIRS_PER_TASK: usize = 8;
/// The grid of the direct path's image heights.
const DIRECT_GRID: usize = 64;
/// The grid of the direct path's shares: fine, since at f/8 the stop passes a beam of a
/// quarter of the front surface's width (160 cells: within 0.2 % of 400 x 400 rays' count).
const SHARE_GRID: usize = 160;

/// A real lens as its flare sees it: its surfaces (the stop opened to the shot's f-number),
/// their coatings, the stop's shape and the film's plane.
#[derive(Clone, Debug)]
pub struct FlareLens {
    elements: Elements,
    coatings: Vec<Coating>,
    stop: usize,
    /// The shape's unit circle at the stop, mm.
    stop_radius: f64,
    aperture: Aperture,
    /// Lens-space z of the film's plane.
    film_z: f64,
    /// The ghosts: every pair of surfaces that reflect (the stop reflects nothing).
    pairs: Vec<(usize, usize)>,
}

/// The usual coatings of `lens`: each surface between air and glass under a quarter-wave MgF2
/// layer (`Coating::default`), cemented surfaces bare.
pub fn default_coatings(lens: &Prescription) -> Vec<Coating> {
    (0..lens.surfaces().len())
        .map(|s| {
            let to_air = lens.index_before(s) == 1.0 || lens.surfaces()[s].index == 1.0;
            let glass = lens.index_before(s) != lens.surfaces()[s].index;
            match to_air && glass {
                true => Coating::default(),
                false => Coating::Uncoated,
            }
        })
        .collect()
}

impl FlareLens {
    /// `lens` as prescribed (its stop's row is the aperture's unit circle, shaped as
    /// `aperture`), its film at lens-space `film_z`, each surface under `coatings`.
    pub fn new(
        lens: &Prescription,
        aperture: Aperture,
        film_z: f64,
        coatings: Vec<Coating>,
    ) -> Self {
        assert_eq!(
            coatings.len(),
            lens.surfaces().len(),
            "one coating per surface"
        );
        let elements = Elements::new(lens);
        let stop = lens.stop();
        let n = elements.interfaces.len();
        let reflects = |s: usize| s != stop && elements.interfaces[s].radius != 0.0;
        let pairs = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .filter(|&(i, j)| reflects(i) && reflects(j))
            .collect();
        Self {
            stop_radius: 0.5 * lens.surfaces()[stop].diameter,
            elements,
            coatings,
            stop,
            aperture,
            film_z,
            pairs,
        }
    }

    /// The flare of a lens built for a shot: stopped down, focused, its stop shaped.
    pub fn of(real: &RealLens) -> Self {
        let (_, _, aperture) = real.stop();
        let coatings = default_coatings(&real.stopped);
        Self::new(
            &real.stopped,
            aperture.clone(),
            f64::from(real.film_z()),
            coatings,
        )
    }

    /// The pairs of surfaces (i, j) whose ghosts are traced.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// Each surface's coating.
    pub fn coatings(&self) -> &[Coating] {
        &self.coatings
    }

    /// Half the front surface's clear aperture, mm: the grid's reach.
    pub fn front_radius(&self) -> f64 {
        self.elements.interfaces[0].aperture_radius
    }

    /// The light on the film of a point source at infinity `degrees` off the axis along +x, at
    /// `wavelengths_nm`: `grid` x `grid` cells over the front surface's clear aperture,
    /// gathered into `bins`.
    pub fn distant_source(
        &self,
        degrees: f64,
        wavelengths_nm: &[f64],
        grid: usize,
        bins: FilmBins,
    ) -> FilmLight {
        let mut light = FilmLight {
            bins,
            direct: Vec::new(),
            ghosts: Vec::new(),
        };
        for &lambda in wavelengths_nm {
            light
                .direct
                .push(self.path_light(None, degrees, lambda, grid, bins));
            let tasks: Vec<Vec<f64>> = self
                .pairs
                .par_chunks(PAIRS_PER_TASK)
                .map(|pairs| {
                    let mut film = vec![0.0; bins.columns * bins.rows];
                    for &pair in pairs {
                        self.draw_path(Some(pair), (degrees, lambda), grid, bins, &mut film);
                    }
                    film
                })
                .collect();
            let mut ghosts = vec![0.0; bins.columns * bins.rows];
            for task in tasks {
                for (sum, value) in ghosts.iter_mut().zip(task) {
                    *sum += value;
                }
            }
            light.ghosts.push(ghosts);
        }
        light
    }

    /// One path's light on the film (ghost `(i, j)`, or the direct path for `None`) from a
    /// source `degrees` off the axis at `lambda_nm`, as [`Self::distant_source`] gathers it.
    pub fn path_light(
        &self,
        path: Option<(usize, usize)>,
        degrees: f64,
        lambda_nm: f64,
        grid: usize,
        bins: FilmBins,
    ) -> Vec<f64> {
        let mut film = vec![0.0; bins.columns * bins.rows];
        self.draw_path(path, (degrees, lambda_nm), grid, bins, &mut film);
        film
    }

    /// Where the source's own image lies `degrees` off the axis, at the d line: its light's
    /// centroid on the film (mm along +x, signed). Its rays, `DIRECT_GRID` across, each weigh
    /// what the stop and the rims let through where they cross; `None` where none reaches the
    /// film.
    pub fn image_height(&self, degrees: f64) -> Option<f64> {
        let vertices = self.trace_grid(None, (degrees, LAMBDA_D_NM), DIRECT_GRID);
        let (mut weight, mut moment) = (0.0, 0.0);
        for v in vertices.iter().flatten() {
            let d = v.out.direction;
            if d.z <= 0.0 {
                continue;
            }
            let corner = Corner {
                at: DVec2::ZERO,
                vertex: *v,
            };
            let clear = self.clear(&[corner; 3], [1.0, 0.0, 0.0]);
            weight += clear;
            moment += clear * (v.out.origin.x + (self.film_z - v.out.origin.z) / d.z * d.x);
        }
        (weight > 0.0).then(|| moment / weight)
    }

    /// The share of the light entering the lens from a source `degrees` off the axis that
    /// reaches the film's `bins` directly, at the d line, drawn as the ghosts are (each cell's
    /// clipping interpolated): with the axis's share, the lens's vignetting.
    pub fn direct_share(&self, degrees: f64, bins: FilmBins) -> f64 {
        let light = self.path_light(None, degrees, LAMBDA_D_NM, SHARE_GRID, bins);
        light.iter().sum()
    }

    /// The share of the light entering the front surface one of `grid` x `grid` cells over
    /// its clear aperture carries, and the grid's rays' origins for `degrees` off the axis.
    fn grid_cell(&self, grid: usize) -> (f64, f64) {
        let radius = self.elements.interfaces[0].aperture_radius;
        let cell = 2.0 * radius / grid as f64;
        (
            cell * cell / (std::f64::consts::PI * radius * radius),
            radius,
        )
    }

    /// The (grid + 1)^2 rays of a grid over the front surface, row by row, traced along
    /// `path` at `(degrees, lambda_nm)`.
    fn trace_grid(
        &self,
        path: Option<(usize, usize)>,
        (degrees, lambda_nm): (f64, f64),
        grid: usize,
    ) -> Vec<Option<GhostVertex>> {
        let (_, radius) = self.grid_cell(grid);
        let (sin, cos) = degrees.to_radians().sin_cos();
        let direction = DVec3::new(sin, 0.0, cos);
        // Symmetric about both axes to the last bit: (2 g - grid) / grid.
        let at = |g: usize| (2.0 * g as f64 - grid as f64) / grid as f64 * radius;
        (0..=grid)
            .flat_map(|gy| (0..=grid).map(move |gx| (gx, gy)))
            .map(|(gx, gy)| {
                // 1 mm in front of the first vertex, through the grid point in its plane.
                let ray = LensRay {
                    origin: DVec3::new(at(gx), at(gy), 0.0) - direction / direction.z,
                    direction,
                };
                ghost_vertex(
                    &self.elements,
                    &self.coatings,
                    ray,
                    path,
                    (lambda_nm, self.stop),
                )
            })
            .collect()
    }

    /// Draws `path`'s light into `film`.
    fn draw_path(
        &self,
        path: Option<(usize, usize)>,
        source: (f64, f64),
        grid: usize,
        bins: FilmBins,
        film: &mut [f64],
    ) {
        let vertices = self.trace_grid(path, source, grid);
        let (share, _) = self.grid_cell(grid);
        self.draw_grid(&vertices, grid, share, bins, film);
    }

    /// Draws one path's grid of `grid` x `grid` cells (their corners `vertices`, row by row),
    /// each carrying `share` of the power entering the lens, into `film`.
    fn draw_grid(
        &self,
        vertices: &[Option<GhostVertex>],
        grid: usize,
        share: f64,
        bins: FilmBins,
        film: &mut [f64],
    ) {
        let corner = |v: &GhostVertex| -> Option<Corner> {
            let d = v.out.direction;
            if d.z <= 0.0 {
                return None;
            }
            let t = (self.film_z - v.out.origin.z) / d.z;
            let p = v.out.origin + t * d;
            Some(Corner {
                at: DVec2::new(p.x, p.y) / bins.bin_mm,
                vertex: *v,
            })
        };
        let corners: Vec<Option<Corner>> = vertices
            .iter()
            .map(|v| v.as_ref().and_then(corner))
            .collect();
        for gy in 0..grid {
            for gx in 0..grid {
                let quad = cell_corners(grid, gx, gy).map(|i| corners[i]);
                let [Some(a), Some(b), Some(c), Some(d)] = quad else {
                    continue;
                };
                let middle = Corner::mean([a, b, c, d]);
                let power = 0.25 * share * middle.vertex.share;
                if power <= 0.0 {
                    continue;
                }
                // Four triangles around the cell's middle: a mirrored grid draws mirrored
                // triangles (two about a diagonal would not be).
                for (p, q) in [(a, b), (b, c), (c, d), (d, a)] {
                    self.draw_triangle([p, q, middle], power, bins, film);
                }
            }
        }
    }

    /// Spreads `power` evenly over the bins whose centres `triangle` covers, less what the
    /// stop and the rims clip there; a triangle that covers no centre gives it to the bin
    /// under its centroid.
    fn draw_triangle(&self, triangle: [Corner; 3], power: f64, bins: FilmBins, film: &mut [f64]) {
        let [a, b, c] = triangle.map(|corner| corner.at);
        let area = (b - a).perp_dot(c - a);
        let half = DVec2::new(0.5 * bins.columns as f64, 0.5 * bins.rows as f64);
        let low = a.min(b).min(c) + half;
        let high = a.max(b).max(c) + half;
        let span = (high - low).max(DVec2::ZERO);
        if span.x * span.y > LARGEST_TRIANGLE_SHARE * (bins.columns * bins.rows) as f64 {
            return;
        }
        // Bins whose centres (column + 0.5 - columns / 2, ...) may lie inside.
        let first = |v: f64| (v - 0.5).ceil().max(0.0) as usize;
        let last = |v: f64, n: usize| ((v - 0.5).floor() as i64).min(n as i64 - 1);
        let (c0, r0) = (first(low.x), first(low.y));
        let (c1, r1) = (last(high.x, bins.columns), last(high.y, bins.rows));
        let weights = |p: DVec2| -> Option<[f64; 3]> {
            if area == 0.0 {
                return None;
            }
            let w = [
                (c - b).perp_dot(p - b) / area,
                (a - c).perp_dot(p - c) / area,
                (b - a).perp_dot(p - a) / area,
            ];
            w.iter().all(|&w| w >= 0.0).then_some(w)
        };
        let centre =
            |column: usize, row: usize| DVec2::new(column as f64 + 0.5, row as f64 + 0.5) - half;
        let mut covered = 0usize;
        if c1 >= c0 as i64 && r1 >= r0 as i64 {
            for row in r0..=r1 as usize {
                for column in c0..=c1 as usize {
                    covered += usize::from(weights(centre(column, row)).is_some());
                }
            }
        }
        if covered == 0 {
            let p = (a + b + c) / 3.0 + half;
            let (column, row) = (p.x.floor(), p.y.floor());
            if column >= 0.0 && row >= 0.0 {
                let (column, row) = (column as usize, row as usize);
                if column < bins.columns && row < bins.rows {
                    let clear = self.clear(&triangle, [1.0 / 3.0; 3]);
                    film[row * bins.columns + column] += power * clear;
                }
            }
            return;
        }
        let each = power / covered as f64;
        for row in r0..=r1 as usize {
            for column in c0..=c1 as usize {
                if let Some(w) = weights(centre(column, row)) {
                    film[row * bins.columns + column] += each * self.clear(&triangle, w);
                }
            }
        }
    }

    /// What passes at the point of `triangle` with barycentric weights `w`: the stop's
    /// transmission at each crossing, 0 past a rim.
    fn clear(&self, triangle: &[Corner; 3], w: [f64; 3]) -> f64 {
        let rim: f64 = (0..3).map(|k| w[k] * triangle[k].vertex.rim).sum();
        if rim > 1.0 {
            return 0.0;
        }
        let crossings = triangle[0].vertex.crossings.min(3);
        (0..crossings)
            .map(|crossing| {
                let [x, y] = [0, 1].map(|axis| {
                    (0..3)
                        .map(|k| w[k] * triangle[k].vertex.stops[crossing][axis])
                        .sum::<f64>()
                });
                let unit = Vec2::new((x / self.stop_radius) as f32, (y / self.stop_radius) as f32);
                f64::from(self.aperture.transmission(unit))
            })
            .product()
    }
}

/// The rays at the corners of cell (`gx`, `gy`) of a `grid` x `grid` grid whose
/// (grid + 1)^2 rays run row by row, counter-clockwise from its lower left.
pub fn cell_corners(grid: usize, gx: usize, gy: usize) -> [usize; 4] {
    let row = grid + 1;
    [
        gy * row + gx,
        gy * row + gx + 1,
        (gy + 1) * row + gx + 1,
        (gy + 1) * row + gx,
    ]
}

/// One corner of a grid cell: where its ray meets the film (in bins from the axis) and what
/// it carries.
#[derive(Clone, Copy, Debug)]
struct Corner {
    at: DVec2,
    vertex: GhostVertex,
}

impl Corner {
    /// The mean of four corners, each quantity averaged.
    fn mean(corners: [Corner; 4]) -> Corner {
        let mut vertex = corners[0].vertex;
        let mean = |f: &dyn Fn(&Corner) -> f64| 0.25 * corners.iter().map(f).sum::<f64>();
        vertex.share = mean(&|c| c.vertex.share);
        vertex.rim = mean(&|c| c.vertex.rim);
        for crossing in 0..vertex.crossings.min(3) {
            for axis in 0..2 {
                vertex.stops[crossing][axis] = mean(&|c| c.vertex.stops[crossing][axis]);
            }
        }
        Corner {
            at: DVec2::new(mean(&|c| c.at.x), mean(&|c| c.at.y)),
            vertex,
        }
    }
}

/// The film divided into square bins, centred on the lens's axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmBins {
    pub columns: usize,
    pub rows: usize,
    /// A bin's side, mm.
    pub bin_mm: f64,
}

impl FilmBins {
    /// The film point (mm, from the axis) of bin `(column, row)`'s centre; row 0 is the
    /// lowest (-y).
    pub fn centre(&self, column: usize, row: usize) -> (f64, f64) {
        (
            (column as f64 + 0.5 - 0.5 * self.columns as f64) * self.bin_mm,
            (row as f64 + 0.5 - 0.5 * self.rows as f64) * self.bin_mm,
        )
    }
}

/// Where a source's light lands on the film, bin by bin, per wavelength (in the order asked),
/// as a share of the power entering the front surface's clear aperture: directly (the
/// source's image) and along the ghosts' paths.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmLight {
    pub bins: FilmBins,
    pub direct: Vec<Vec<f64>>,
    pub ghosts: Vec<Vec<f64>>,
}
