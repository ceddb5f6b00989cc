//! The shape of the lens opening (slide "Non-Linear Models: Depth of Field", step 3: "a random
//! point on the aperture"): round, or an iris of N blades, straight or curved, squeezed
//! anamorphically. A point off the focal plane images as this shape scaled by its circle of
//! confusion: as the aperture itself beyond the focal plane, turned by 180 degrees in front of
//! it (the lens rays cross at the focal plane).
//!
//! # Conventions
//! - The shape is drawn in the lens plane with camera-space axes: +x to the image's right, +y
//!   up. Its circumscribed circle has radius `aperture_radius` (so the f-number names that
//!   circle, as in Cycles): the blades' vertices lie on it.
//! - Vertex k of N sits at angle `rotation + 360 k / N` degrees, counter-clockwise from +x.
//! - Roundness R in [0, 1] curves each blade into an arc through its two vertices, bulging
//!   outwards by R times the bulge of the circumscribed circle's arc (its sagitta): 0 is the
//!   straight-bladed polygon, 1 the circle itself (sampled exactly as the round aperture).
//!   Between, each arc is drawn as `MAX_FAN / N` chords whose vertices lie on it.
//! - The aspect (anamorphic squeeze) is the shape's height over its width: y is scaled by it
//!   about the lens centre after everything else, x is not.
//! - An aperture image (`image`) fills the square circumscribing the circle, its top row at
//!   the image's top, as a transmission map in [0, 1]: the opening and its brightness profile
//!   (an apodised or soap-bubble lens is an image). The rotation turns it about the centre,
//!   the aspect stretches it as it does the blades. Blades and an image exclude each other.
//! - Exposure does not change with the shape: the image is the average over the opening,
//!   weighted by its transmission.
//!
//! # Sampling
//! Uniform over the shape and stratified as the sampler's lens dimensions are: the square's
//! concentric rings (Shirley and Chiu) go to the shape's scaled copies, and the position along
//! a ring to the same fraction of the shape's area, swept from vertex 0. The shape is a fan of
//! triangles of equal area around the centre, so that fraction picks a triangle and a point on
//! its outer edge by one multiplication, with no search, loop or rejection. The arithmetic is
//! additions, multiplications and one division: the GLSL mirror (`shaders/include/camera.glsl`)
//! gives the same bits. Images: a piecewise-constant 2D distribution ([`image`]).

pub mod diffraction;
mod fan;
pub mod image;

use std::sync::Arc;

use glam::Vec2;

use super::thin_lens::concentric_sample_disk;
use fan::blade_fan;
pub use fan::sample_fan;
pub use image::{ApertureImage, ApertureImageError};

/// Most triangles of a fan (the GPU's camera block holds them, two vertices per vec4).
pub const MAX_FAN: usize = crate::interface::APERTURE_MAX_FAN as usize;
/// Most blades of an iris.
pub const MAX_BLADES: u32 = 32;

/// What a user says of the aperture's shape (`[camera.aperture]`, `--aperture-*`).
#[derive(Clone, Debug, PartialEq)]
pub struct ApertureShape {
    /// `None`: round (or the image's shape).
    pub blades: Option<u32>,
    pub rotation_degrees: f32,
    pub roundness: f32,
    pub aspect: f32,
    /// A transmission map over the circumscribed square (`--aperture-image`).
    pub image: Option<Arc<ApertureImage>>,
}

impl ApertureShape {
    pub const ROUND: ApertureShape = ApertureShape {
        blades: None,
        rotation_degrees: 0.0,
        roundness: 0.0,
        aspect: 1.0,
        image: None,
    };
}

impl Default for ApertureShape {
    fn default() -> Self {
        Self::ROUND
    }
}

/// The aperture as sampled: the fan of the unit shape (circumscribed radius 1, before the
/// aspect), an image's tables, or neither for a disk.
#[derive(Clone, Debug, PartialEq)]
pub struct Aperture {
    pub shape: ApertureShape,
    /// `fan_len` vertices counter-clockwise from vertex 0 (at the rotation angle); triangle
    /// (centre, fan[i], fan[(i + 1) % fan_len]) has the same area for every i.
    fan: [Vec2; MAX_FAN],
    fan_len: u32,
    /// (cos, sin) of the rotation, which turns an image (a fan has it built in).
    turn: Vec2,
    /// See `reach`.
    reach: f32,
}

impl Default for Aperture {
    fn default() -> Self {
        Self::ROUND
    }
}

impl Aperture {
    pub const ROUND: Aperture = Aperture {
        shape: ApertureShape::ROUND,
        fan: [Vec2::ZERO; MAX_FAN],
        fan_len: 0,
        turn: Vec2::X,
        reach: 1.0,
    };

    /// The aperture of `shape` (checked by `ApertureShape::build`: 3..=MAX_BLADES blades,
    /// roundness in [0, 1], a positive aspect, not both blades and an image).
    pub fn new(shape: ApertureShape) -> Self {
        let rotation = f64::from(shape.rotation_degrees).to_radians();
        let turn = Vec2::new(rotation.cos() as f32, rotation.sin() as f32);
        let reach = match &shape.image {
            Some(image) => image.reach(turn, shape.aspect),
            None => shape.aspect.max(1.0),
        };
        let mut aperture = Aperture {
            turn,
            reach,
            ..Self::ROUND
        };
        let blades = shape.blades.filter(|_| shape.roundness < 1.0);
        aperture.shape = shape;
        let Some(blades) = blades.filter(|_| aperture.shape.image.is_none()) else {
            return aperture;
        };
        let shape = &aperture.shape;
        let fan = blade_fan(
            blades,
            f64::from(shape.rotation_degrees).to_radians(),
            f64::from(shape.roundness),
        );
        for (slot, v) in aperture.fan.iter_mut().zip(&fan) {
            *slot = v.as_vec2();
        }
        aperture.fan_len = fan.len() as u32;
        aperture
    }

    /// The fan's vertices (empty: a disk or an image).
    pub fn fan(&self) -> &[Vec2] {
        &self.fan[..self.fan_len as usize]
    }

    /// The aperture image, if the shape is one.
    pub fn image(&self) -> Option<&ApertureImage> {
        self.shape.image.as_deref()
    }

    /// (cos, sin) of the rotation: what turns an image.
    pub fn turn(&self) -> Vec2 {
        self.turn
    }

    /// The point of the unit shape (circumscribed radius 1, aspect applied) that the uniform
    /// sample `u` in [0, 1)^2 picks.
    pub fn unit_point(&self, u: Vec2) -> Vec2 {
        let p = if let Some(image) = self.image() {
            let q = image.sample(u);
            let c = self.turn;
            Vec2::new(c.x * q.x - c.y * q.y, c.y * q.x + c.x * q.y)
        } else if self.fan_len == 0 {
            concentric_sample_disk(u)
        } else {
            sample_fan(self.fan(), u)
        };
        Vec2::new(p.x, p.y * self.shape.aspect)
    }

    /// [`Self::unit_point`] of every sample of a packet, bit for bit: the shape is decided once,
    /// so that the round aperture's map runs in vector code across the lanes.
    pub fn unit_points<const N: usize>(&self, u: &[Vec2; N]) -> [Vec2; N] {
        if self.image().is_some() || self.fan_len != 0 {
            return u.map(|u| self.unit_point(u));
        }
        let aspect = self.shape.aspect;
        u.map(|u| {
            let p = concentric_sample_disk(u);
            Vec2::new(p.x, p.y * aspect)
        })
    }

    /// How much light passes at point `p` of the unit shape's plane (circumscribed radius 1,
    /// aspect applied, as `unit_point` gives them): 1 inside a disk or an iris, the cell's
    /// value for an image, 0 outside. A real lens's stop is this opening (`real_lens`).
    pub fn transmission(&self, p: Vec2) -> f32 {
        let q = Vec2::new(p.x, p.y / self.shape.aspect);
        if let Some(image) = self.image() {
            // Turn back by the rotation, then read the cell (outside the square: nothing).
            let c = self.turn;
            let r = Vec2::new(c.x * q.x + c.y * q.y, c.x * q.y - c.y * q.x);
            if r.x.abs() > 1.0 || r.y.abs() > 1.0 {
                return 0.0;
            }
            let (column, row) = image.cell_of(r);
            return image.transmission()[(row * image.columns() + column) as usize];
        }
        let fan = self.fan();
        let inside = if fan.is_empty() {
            q.length_squared() <= 1.0
        } else {
            // The fan is convex and counter-clockwise: inside every edge's left side.
            (0..fan.len()).all(|i| (fan[(i + 1) % fan.len()] - fan[i]).perp_dot(q - fan[i]) >= 0.0)
        };
        if inside {
            1.0
        } else {
            0.0
        }
    }

    /// How far the shape reaches from the centre, in units of the aperture radius: the
    /// radius of the circle that holds it (the aspect stretches it vertically; an image's
    /// corners may reach past the circle).
    pub fn reach(&self) -> f32 {
        self.reach
    }
}

/// The aperture tests' uniform numbers in [0, 1): a PCG-style LCG, its top 24 bits.
#[cfg(test)]
fn uniform_stream() -> impl FnMut() -> f32 {
    let mut state = 0x853c_49e6_748f_ea9bu64;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle_areas(fan: &[Vec2]) -> Vec<f32> {
        (0..fan.len())
            .map(|i| 0.5 * fan[i].perp_dot(fan[(i + 1) % fan.len()]))
            .collect()
    }

    #[test]
    fn fan_triangles_have_equal_areas() {
        for blades in [3, 5, 6, 9, 32] {
            for roundness in [0.0, 0.3, 0.9] {
                let aperture = Aperture::new(ApertureShape {
                    blades: Some(blades),
                    rotation_degrees: 15.0,
                    roundness,
                    ..ApertureShape::ROUND
                });
                let areas = triangle_areas(aperture.fan());
                let mean = areas.iter().sum::<f32>() / areas.len() as f32;
                for a in &areas {
                    assert!(
                        (a - mean).abs() <= 1e-4 * mean,
                        "{blades} blades, roundness {roundness}: {areas:?}"
                    );
                }
                // Every vertex within the circumscribed circle, the blades' on it.
                for v in aperture.fan() {
                    assert!(v.length() <= 1.0 + 1e-6, "{v}");
                }
                let per_blade = aperture.fan().len() / blades as usize;
                for k in 0..blades as usize {
                    let v = aperture.fan()[k * per_blade];
                    let angle = (15.0f32 + 360.0 * k as f32 / blades as f32).to_radians();
                    assert!((v - Vec2::new(angle.cos(), angle.sin())).length() < 1e-5);
                }
            }
        }
    }

    #[test]
    fn the_polygon_has_the_polygon_s_area() {
        // A regular N-gon inscribed in the unit circle: N/2 sin(2 pi / N).
        for blades in [3u32, 6, 9] {
            let aperture = Aperture::new(ApertureShape {
                blades: Some(blades),
                ..ApertureShape::ROUND
            });
            let area: f32 = triangle_areas(aperture.fan()).iter().sum();
            let n = blades as f32;
            let expected = 0.5 * n * (std::f32::consts::TAU / n).sin();
            assert!(
                (area - expected).abs() < 1e-5,
                "{blades}: {area} vs {expected}"
            );
        }
    }

    #[test]
    fn roundness_one_is_the_round_aperture() {
        let round = Aperture::new(ApertureShape {
            blades: Some(6),
            rotation_degrees: 20.0,
            roundness: 1.0,
            ..ApertureShape::ROUND
        });
        for u in [
            Vec2::new(0.1, 0.7),
            Vec2::new(0.9, 0.2),
            Vec2::new(0.5, 0.5),
        ] {
            assert_eq!(round.unit_point(u), concentric_sample_disk(u));
        }
    }

    /// Inside the shape as sampled (the fan's polygon, or the disk), aspect applied.
    fn inside(aperture: &Aperture, p: Vec2) -> bool {
        let q = Vec2::new(p.x, p.y / aperture.shape.aspect);
        let fan = aperture.fan();
        if fan.is_empty() {
            return q.length() <= 1.0;
        }
        (0..fan.len()).all(|i| (fan[(i + 1) % fan.len()] - fan[i]).perp_dot(q - fan[i]) >= 0.0)
    }

    /// Chi-square over a grid's cells that lie wholly inside the shape, plus one cell for the
    /// rest: each inside cell expects its share of the shape's area.
    fn chi_square(aperture: &Aperture, samples: u32) -> (f64, usize) {
        const GRID: usize = 16;
        let aspect = aperture.shape.aspect;
        let area = match aperture.fan() {
            [] => std::f64::consts::PI,
            fan => triangle_areas(fan).iter().map(|&a| f64::from(a)).sum(),
        } * f64::from(aspect);
        let cell = Vec2::new(2.0 / GRID as f32, 2.0 * aspect / GRID as f32);
        let corner =
            |i: usize, j: usize| Vec2::new(-1.0, -aspect) + cell * Vec2::new(i as f32, j as f32);
        let mut counts = vec![0u32; GRID * GRID + 1];
        let mut next = uniform_stream();
        let whole: Vec<bool> = (0..GRID * GRID)
            .map(|c| {
                let (i, j) = (c % GRID, c / GRID);
                [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .iter()
                    .all(|&(di, dj)| inside(aperture, corner(i + di, j + dj)))
            })
            .collect();
        for _ in 0..samples {
            let p = aperture.unit_point(Vec2::new(next(), next()));
            assert!(inside(aperture, p * 0.99999), "{p} is outside");
            let q = (p - Vec2::new(-1.0, -aspect)) / cell;
            let (i, j) = (q.x.floor() as usize, q.y.floor() as usize);
            let c = j.min(GRID - 1) * GRID + i.min(GRID - 1);
            counts[if whole[c] { c } else { GRID * GRID }] += 1;
        }
        let cell_share = f64::from(cell.x * cell.y) / area;
        let inside_cells = whole.iter().filter(|&&w| w).count();
        let mut chi2 = 0.0;
        for (c, &count) in counts.iter().enumerate() {
            let share = if c == GRID * GRID {
                1.0 - cell_share * inside_cells as f64
            } else if whole[c] {
                cell_share
            } else {
                continue;
            };
            let expected = share * f64::from(samples);
            chi2 += (f64::from(count) - expected).powi(2) / expected;
        }
        (chi2, inside_cells)
    }

    /// Uniform over every kind of shape: round, straight blades (odd and even), curved blades,
    /// squeezed. Chi-square within 5 standard deviations of its degrees of freedom.
    #[test]
    fn samples_are_uniform_over_every_shape() {
        let shapes = [
            ApertureShape::ROUND,
            ApertureShape {
                blades: Some(5),
                rotation_degrees: 15.0,
                ..ApertureShape::ROUND
            },
            ApertureShape {
                blades: Some(6),
                ..ApertureShape::ROUND
            },
            ApertureShape {
                blades: Some(9),
                roundness: 0.5,
                ..ApertureShape::ROUND
            },
            ApertureShape {
                aspect: 2.0,
                ..ApertureShape::ROUND
            },
            ApertureShape {
                blades: Some(7),
                aspect: 0.5,
                roundness: 0.2,
                ..ApertureShape::ROUND
            },
        ];
        for shape in shapes {
            let (chi2, cells) = chi_square(&Aperture::new(shape.clone()), 400_000);
            let dof = cells as f64;
            let bound = dof + 5.0 * (2.0 * dof).sqrt();
            assert!(cells > 100, "{shape:?}: {cells} cells");
            assert!(
                chi2 < bound,
                "{shape:?}: chi-square {chi2:.1} over {cells} cells (bound {bound:.1})"
            );
        }
    }
}
