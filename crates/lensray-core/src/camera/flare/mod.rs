//! The lens's own light (`--flare`, `--starburst`): ghosts and the aperture's starburst, added
//! to a real lens's rendered image before it is exposed.
//!
//! # What counts as a source
//! - **Bright pixels.** Every pixel brighter than [`SOURCE_LEVEL`] once exposed (exposure's
//!   scale times its luminance): emitters, the environment's sun and their bright mirror
//!   images in view. They are gathered in tiles of [`TILE`] x [`TILE`] pixels, each tile one
//!   source at its light's centroid; the [`MOST_SOURCES`] brightest tiles are kept.
//! - **Punctual lights in view.** A point, spot or directional light inside the field of view
//!   (whether geometry hides it is not asked): the image has no pixels of its own for it, so
//!   its image, traced through the lens as a distant source, is drawn too, with the light it
//!   gives the lens (`PointSource`).
//!
//! # Ghosts
//! Each source's ghosts are those of a source at infinity in its direction ([`ghosts`]):
//! the lens's rotational symmetry turns the pattern along +x to the source's side. The source
//! is far from the lens against its pupil, so its rays are parallel. A ghost's light is the
//! source's as rendered (its pixels' sum) times the ghost's share over the direct path's share
//! (the light the renderer drew), per channel, each channel the mean of two wavelengths of its
//! band. Patterns are kept per field angle (in steps of [`ANGLE_STEP_DEGREES`]).
//!
//! # Starburst
//! The image convolved with the aperture's diffraction ([`starburst`]), after the ghosts.

pub mod ghosts;
pub mod starburst;

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use glam::{DVec2, Vec2, Vec3};

use crate::camera::RealLens;
use crate::film::Image;
use ghosts::{FilmBins, FilmLight, FlareLens};
use starburst::Starburst;

/// Exposed luminance past which a pixel is a source of ghosts: 16 times white. A ghost holds
/// 1e-5 to 1e-3 of its source's light spread over many pixels, so a dimmer pixel's ghosts
/// stay far below a display's last step.
pub const SOURCE_LEVEL: f32 = 16.0;
/// A source tile's side, pixels.
pub const TILE: u32 = 8;
/// The most source tiles kept (the brightest).
pub const MOST_SOURCES: usize = 32;
/// Field angles are traced at multiples of this.
pub const ANGLE_STEP_DEGREES: f64 = 0.25;
/// Rays across the front surface per ghost: each grid cell a quad on the film.
pub const GRID: usize = 64;
/// Each channel's two wavelengths (nm).
const CHANNEL_WAVELENGTHS_NM: [[f64; 2]; 3] = [[640.0, 600.0], [560.0, 530.0], [480.0, 450.0]];
/// The starburst's farthest reach, pixels, at most.
const STARBURST_RADIUS: usize = 256;

/// Traces a pattern as `FlareLens::distant_source` does: the lens, the source's field angle
/// (degrees), the wavelengths (nm), the grid's cells across and the film's bins.
pub type PatternTrace<'a, E> =
    dyn FnMut(&FlareLens, f64, &[f64], usize, FilmBins) -> Result<FilmLight, E> + 'a;

/// What the flare draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FlareSwitches {
    pub ghosts: bool,
    pub starburst: bool,
}

/// A punctual light in view: the unit direction toward it in camera space (+z ahead, +x
/// right, +y up) and the irradiance it gives the lens, W/m^2 per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSource {
    pub direction: Vec3,
    pub irradiance: Vec3,
}

/// One source's pattern: per channel, its ghosts' and its own image's light on the film's
/// bins as a share of the light the renderer draws of it.
#[derive(Debug)]
struct Pattern {
    ghosts: [Vec<f32>; 3],
    direct: [Vec<f32>; 3],
    /// The direct image's distance from the axis (mm, signed along the trace's +x).
    image_mm: f64,
}

/// A source of the image: its field angle (degrees), its turn in the image (the unit vector
/// from the axis toward its image, +y up), its image's distance from the axis (mm) and its
/// light as rendered (summed over its pixels).
#[derive(Clone, Copy, Debug)]
struct Source {
    field: f64,
    turn: Vec2,
    height_mm: f64,
    light: Vec3,
}

/// A shot's flare: the lens, the film's pixels and the patterns traced so far.
#[derive(Debug)]
pub struct Flare {
    switches: FlareSwitches,
    lens: FlareLens,
    width: u32,
    height: u32,
    /// Film mm per pixel.
    pitch_mm: f64,
    /// The raster point on the lens's axis.
    axis: Vec2,
    bins: FilmBins,
    starburst: Option<Starburst>,
    /// The solid angle of a pixel at the centre, sr: a punctual light's light in pixels.
    pixel_sr: f64,
    /// The share of an axial source's light that reaches the film.
    axial_share: f64,
    patterns: Mutex<HashMap<i64, Arc<Pattern>>>,
}

impl Flare {
    /// The flare of `real` on an image of `width` x `height`.
    pub fn new(real: &RealLens, switches: FlareSwitches, width: u32, height: u32) -> Self {
        let pitch_mm = 2.0 * f64::from(real.film_half_height()) / f64::from(height);
        let axis = real.raster_centre(width, height);
        // Bins of one pixel up to 640 across the image, coarser past it; a square around the
        // axis that holds the farthest corner at any turn.
        let bin_pixels = (width.max(height) as f64 / 640.0).ceil().max(1.0);
        let corner = [0.0, width as f32]
            .iter()
            .flat_map(|&x| [0.0, height as f32].map(|y| (Vec2::new(x, y) - axis).length()))
            .fold(0.0f32, f32::max);
        let side = 2 * ((f64::from(corner) / bin_pixels).ceil() as usize + 1);
        let bins = FilmBins {
            columns: side,
            rows: side,
            bin_mm: bin_pixels * pitch_mm,
        };
        let lens = FlareLens::of(real);
        let starburst = switches.starburst.then(|| {
            let (_, _, aperture) = real.stop();
            Starburst::new(aperture, real.f_number, pitch_mm, STARBURST_RADIUS)
        });
        let degree = 1.0f64;
        let focal_mm = lens
            .image_height(degree)
            .map_or(f64::from(real.film_half_height()), |h| {
                h.abs() / degree.to_radians().tan()
            });
        let axial_share = lens.direct_share(0.0, bins);
        Self {
            switches,
            lens,
            width,
            height,
            pitch_mm,
            axis,
            bins,
            starburst,
            pixel_sr: (pitch_mm / focal_mm).powi(2),
            axial_share,
            patterns: Mutex::new(HashMap::new()),
        }
    }

    /// Drops the patterns traced so far: the next `apply` traces its sources' again (a bench
    /// times the whole flare each run).
    pub fn forget_patterns(&self) {
        self.patterns.lock().expect("patterns").clear();
    }

    /// Adds the flare to `image` (linear, before `exposure`'s scale), with `points` the
    /// punctual lights in view, its patterns traced on the CPU.
    pub fn apply(&self, image: &mut Image, exposure: f32, points: &[PointSource]) {
        let mut on_cpu = |lens: &FlareLens, degrees, wavelengths: &[f64], grid, bins| {
            Ok::<_, std::convert::Infallible>(lens.distant_source(degrees, wavelengths, grid, bins))
        };
        let Ok(()) = self.apply_traced(image, exposure, points, &mut on_cpu);
    }

    /// [`Flare::apply`], each pattern traced by `trace` (`FlareLens::distant_source`'s
    /// arguments; a GPU's trace); its first error stops it, the image left as it was.
    pub fn apply_traced<E>(
        &self,
        image: &mut Image,
        exposure: f32,
        points: &[PointSource],
        trace: &mut PatternTrace<'_, E>,
    ) -> Result<(), E> {
        assert_eq!((image.width, image.height), (self.width, self.height));
        let mut added = Image::new(self.width, self.height);
        let mut sources = Vec::new();
        for (at, light) in bright_tiles(image, exposure) {
            let offset = (at - self.axis) * Vec2::new(1.0, -1.0);
            let height_mm = f64::from(offset.length()) * self.pitch_mm;
            if let Some(field) = self.field_for(height_mm) {
                let turn = Vec2::from_angle(offset.y.atan2(offset.x));
                sources.push(Source {
                    field,
                    turn,
                    height_mm,
                    light,
                });
            }
        }
        for point in points {
            let Some((field, turn)) = self.field_of(point.direction) else {
                continue;
            };
            let Some(height_mm) = self.lens.image_height(field) else {
                continue;
            };
            // Only a light whose image lies on the film is in view.
            let height_mm = height_mm.abs();
            let at = self.axis + turn * Vec2::new(1.0, -1.0) * (height_mm / self.pitch_mm) as f32;
            let on_film = at.x >= 0.0 && at.y >= 0.0;
            if !(on_film && at.x < self.width as f32 && at.y < self.height as f32) {
                continue;
            }
            let vignetting = match self.axial_share > 0.0 {
                true => {
                    let share = self.lens.direct_share(field, self.bins);
                    share / self.axial_share * field.to_radians().cos()
                }
                false => 0.0,
            };
            let light = point.irradiance / self.pixel_sr as f32 * vignetting as f32;
            let source = Source {
                field,
                turn,
                height_mm,
                light,
            };
            if let Some(pattern) = self.pattern(field, trace)? {
                self.gather(&mut added, &pattern.direct, &source, pattern.image_mm);
            }
            sources.push(source);
        }
        if self.switches.ghosts {
            for source in &sources {
                if let Some(pattern) = self.pattern(source.field, trace)? {
                    self.gather(&mut added, &pattern.ghosts, source, pattern.image_mm);
                }
            }
        }
        for (pixel, more) in image.pixels.iter_mut().zip(&added.pixels) {
            *pixel += *more;
        }
        if let Some(starburst) = &self.starburst {
            starburst.apply(image);
        }
        Ok(())
    }

    /// A camera-space direction's field angle (degrees) and its turn in the image (the unit
    /// vector from the axis toward its image, +y up); `None` behind the lens.
    fn field_of(&self, direction: Vec3) -> Option<(f64, Vec2)> {
        let d = direction.normalize_or_zero();
        if d.z <= 0.0 {
            return None;
        }
        let side = Vec2::new(d.x, d.y);
        let turn = match side.length() > 0.0 {
            true => side.normalize(),
            false => Vec2::X,
        };
        Some((f64::from(side.length().atan2(d.z)).to_degrees(), turn))
    }

    /// The field angle (degrees) whose image lies `height_mm` from the axis: bisection on
    /// the direct image's height, which grows with the angle.
    fn field_for(&self, height_mm: f64) -> Option<f64> {
        let (mut low, mut high) = (0.0f64, 89.0f64);
        for _ in 0..24 {
            let mid = 0.5 * (low + high);
            match self.lens.image_height(mid) {
                Some(h) if h.abs() < height_mm => low = mid,
                _ => high = mid,
            }
        }
        (high < 89.0).then_some(0.5 * (low + high))
    }

    /// The pattern of a source `field` degrees off the axis (the nearest step's), traced once.
    fn pattern<E>(
        &self,
        field: f64,
        trace: &mut PatternTrace<'_, E>,
    ) -> Result<Option<Arc<Pattern>>, E> {
        let step = (field / ANGLE_STEP_DEGREES).round() as i64;
        if let Some(pattern) = self.patterns.lock().expect("patterns").get(&step) {
            return Ok(Some(pattern.clone()));
        }
        let degrees = step as f64 * ANGLE_STEP_DEGREES;
        let wavelengths: Vec<f64> = CHANNEL_WAVELENGTHS_NM.iter().flatten().copied().collect();
        let light = trace(&self.lens, degrees, &wavelengths, GRID, self.bins)?;
        let shares: Vec<f64> = light.direct.iter().map(|d| d.iter().sum()).collect();
        if shares.iter().any(|&s| s <= 0.0) {
            return Ok(None);
        }
        let per_channel = |maps: &[Vec<f64>]| -> [Vec<f32>; 3] {
            std::array::from_fn(|c| {
                (0..maps[0].len())
                    .map(|b| {
                        (0.5 * (maps[2 * c][b] / shares[2 * c]
                            + maps[2 * c + 1][b] / shares[2 * c + 1]))
                            as f32
                    })
                    .collect()
            })
        };
        let Some(image_mm) = self.lens.image_height(degrees) else {
            return Ok(None);
        };
        let pattern = Arc::new(Pattern {
            ghosts: per_channel(&light.ghosts),
            direct: per_channel(&light.direct),
            image_mm,
        });
        self.patterns
            .lock()
            .expect("patterns")
            .insert(step, pattern.clone());
        Ok(Some(pattern))
    }

    /// Adds `maps` (a pattern's per-channel bins, its source imaged `image_mm` along the
    /// trace's +x), turned to `source`'s side and moved along it from the pattern's field
    /// angle to the source's own, scaled by its light, to `image` pixel by pixel.
    fn gather(&self, image: &mut Image, maps: &[Vec<f32>; 3], source: &Source, image_mm: f64) {
        // The trace's source images on the side of `image_mm`'s sign; the image shows the film
        // inverted, so a pattern point f mm off the axis shows at -f: turned, sign * f.
        let sign = if image_mm < 0.0 { -1.0 } else { 1.0 };
        let shift_mm = source.height_mm - image_mm.abs();
        let bin_pixels = self.bins.bin_mm / self.pitch_mm;
        let per_pixel = 1.0 / (bin_pixels * bin_pixels) as f32;
        let half = DVec2::new(0.5 * self.bins.columns as f64, 0.5 * self.bins.rows as f64);
        let width = self.width as usize;
        let turn = source.turn;
        for (index, pixel) in image.pixels.iter_mut().enumerate() {
            let raster = Vec2::new((index % width) as f32 + 0.5, (index / width) as f32 + 0.5);
            // Image offset (+y up) turned back onto the trace's +x, in mm.
            let q = (raster - self.axis) * Vec2::new(1.0, -1.0);
            let back = Vec2::new(q.x * turn.x + q.y * turn.y, q.y * turn.x - q.x * turn.y);
            let film = back.as_dvec2() * self.pitch_mm - DVec2::new(shift_mm, 0.0);
            let at = film * sign / self.bins.bin_mm + half - DVec2::splat(0.5);
            let value =
                Vec3::from_array(std::array::from_fn(|c| bilinear(&maps[c], self.bins, at)));
            *pixel += value * source.light * per_pixel;
        }
    }
}

/// The value of `map` (`bins`) at bin coordinates `at` (bin centres at integers), read
/// bilinearly, 0 off the bins.
fn bilinear(map: &[f32], bins: FilmBins, at: DVec2) -> f32 {
    let (x0, y0) = (at.x.floor(), at.y.floor());
    if x0 < -1.0 || y0 < -1.0 || x0 >= bins.columns as f64 || y0 >= bins.rows as f64 {
        return 0.0;
    }
    let (fx, fy) = ((at.x - x0) as f32, (at.y - y0) as f32);
    let value = |c: f64, r: f64| {
        let inside =
            c >= 0.0 && r >= 0.0 && (c as usize) < bins.columns && (r as usize) < bins.rows;
        match inside {
            true => map[r as usize * bins.columns + c as usize],
            false => 0.0,
        }
    };
    (value(x0, y0) * (1.0 - fx) + value(x0 + 1.0, y0) * fx) * (1.0 - fy)
        + (value(x0, y0 + 1.0) * (1.0 - fx) + value(x0 + 1.0, y0 + 1.0) * fx) * fy
}

/// The image's sources: tiles holding pixels past [`SOURCE_LEVEL`] once exposed, each its
/// bright pixels' light (summed) at their centroid (raster), the brightest first.
fn bright_tiles(image: &Image, exposure: f32) -> Vec<(Vec2, Vec3)> {
    let luminance = |v: Vec3| v.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    let tiles_x = image.width.div_ceil(TILE);
    let tiles_y = image.height.div_ceil(TILE);
    let mut tiles = Vec::new();
    for ty in 0..tiles_y {
        for tx in 0..tiles_x {
            let (mut light, mut at, mut weight) = (Vec3::ZERO, Vec2::ZERO, 0.0f32);
            for y in ty * TILE..((ty + 1) * TILE).min(image.height) {
                for x in tx * TILE..((tx + 1) * TILE).min(image.width) {
                    let v = image.get(x, y);
                    let l = luminance(v);
                    if l * exposure > SOURCE_LEVEL {
                        light += v;
                        at += Vec2::new(x as f32 + 0.5, y as f32 + 0.5) * l;
                        weight += l;
                    }
                }
            }
            if weight > 0.0 {
                tiles.push((at / weight, light));
            }
        }
    }
    tiles.sort_by(|a, b| luminance(b.1).total_cmp(&luminance(a.1)));
    tiles.truncate(MOST_SOURCES);
    tiles
}
