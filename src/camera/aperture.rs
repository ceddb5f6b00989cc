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
//! - Exposure does not change with the shape: the image is the average over the opening.
//!
//! # Sampling
//! Uniform over the shape and stratified as the sampler's lens dimensions are: the square's
//! concentric rings (Shirley and Chiu) go to the shape's scaled copies, and the position along
//! a ring to the same fraction of the shape's area, swept from vertex 0. The shape is a fan of
//! triangles of equal area around the centre, so that fraction picks a triangle and a point on
//! its outer edge by one multiplication, with no search, loop or rejection. The arithmetic is
//! additions, multiplications and one division: the GLSL mirror (`shaders/include/camera.glsl`)
//! gives the same bits.

use glam::{DVec2, Vec2};

use super::thin_lens::concentric_sample_disk;

/// Most triangles of a fan (the GPU's camera block holds them, two vertices per vec4).
pub const MAX_FAN: usize = crate::interface::APERTURE_MAX_FAN as usize;
/// Most blades of an iris.
pub const MAX_BLADES: u32 = 32;

/// What a user says of the aperture's shape (`[camera.aperture]`, `--aperture-*`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApertureShape {
    /// `None`: round.
    pub blades: Option<u32>,
    pub rotation_degrees: f32,
    pub roundness: f32,
    pub aspect: f32,
}

impl ApertureShape {
    pub const ROUND: ApertureShape = ApertureShape {
        blades: None,
        rotation_degrees: 0.0,
        roundness: 0.0,
        aspect: 1.0,
    };
}

impl Default for ApertureShape {
    fn default() -> Self {
        Self::ROUND
    }
}

/// The aperture as sampled: the fan of the unit shape (circumscribed radius 1, before the
/// aspect), or none for a disk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aperture {
    pub shape: ApertureShape,
    /// `fan_len` vertices counter-clockwise from vertex 0 (at the rotation angle); triangle
    /// (centre, fan[i], fan[(i + 1) % fan_len]) has the same area for every i.
    fan: [Vec2; MAX_FAN],
    fan_len: u32,
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
    };

    /// The aperture of `shape` (checked by `CameraParams::build`: 3..=MAX_BLADES blades,
    /// roundness in [0, 1], a positive aspect).
    pub fn new(shape: ApertureShape) -> Self {
        let mut aperture = Aperture {
            shape,
            ..Self::ROUND
        };
        let Some(blades) = shape.blades.filter(|_| shape.roundness < 1.0) else {
            return aperture;
        };
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

    /// The fan's vertices (empty: a disk).
    pub fn fan(&self) -> &[Vec2] {
        &self.fan[..self.fan_len as usize]
    }

    /// The point of the unit shape (circumscribed radius 1, aspect applied) that the uniform
    /// sample `u` in [0, 1)^2 picks.
    pub fn unit_point(&self, u: Vec2) -> Vec2 {
        let p = if self.fan_len == 0 {
            concentric_sample_disk(u)
        } else {
            sample_fan(self.fan(), u)
        };
        Vec2::new(p.x, p.y * self.shape.aspect)
    }

    /// How far the shape reaches from the centre, in units of the aperture radius: the
    /// radius of the circle that holds it (the aspect stretches it vertically).
    pub fn reach(&self) -> f32 {
        self.shape.aspect.max(1.0)
    }
}

/// Uniform [0, 1)^2 -> uniform over the fan `fan` (equal-area triangles around the origin):
/// concentric ring r in [0, 1], fraction `a` of the way around it, then the point at `a` of
/// the fan's outer boundary (triangle floor(a n), a linear position on its outer edge) scaled
/// by r. Scaled copies of the fan have area proportional to r^2, as the square's rings do, and
/// each triangle holds 1/n of every ring: the map preserves area.
pub fn sample_fan(fan: &[Vec2], u: Vec2) -> Vec2 {
    let offset = 2.0 * u - Vec2::ONE;
    if offset.x == 0.0 && offset.y == 0.0 {
        return Vec2::ZERO;
    }
    // The concentric map's ring and angle (in turns: its theta / 2 pi).
    let (mut r, mut a) = if offset.x.abs() > offset.y.abs() {
        (offset.x, 0.125 * (offset.y / offset.x))
    } else {
        (offset.y, 0.25 - 0.125 * (offset.x / offset.y))
    };
    if r < 0.0 {
        r = -r;
        a += 0.5;
    }
    if a < 0.0 {
        a += 1.0;
    }
    let n = fan.len() as u32;
    let s = a * n as f32;
    let i = (s as u32).min(n - 1);
    let t = s - i as f32;
    let (p0, p1) = (fan[i as usize], fan[((i + 1) % n) as usize]);
    r * (p0 + t * (p1 - p0))
}

/// The fan of an iris of `blades` blades of roundness `roundness`, vertex 0 at angle
/// `rotation` (radians): per blade, the blade's first vertex and points on its arc chosen so
/// that every triangle of the fan has the same area.
fn blade_fan(blades: u32, rotation: f64, roundness: f64) -> Vec<DVec2> {
    let per_blade = if roundness > 0.0 {
        MAX_FAN / blades as usize
    } else {
        1
    };
    let half = std::f64::consts::PI / f64::from(blades);
    let mut fan = Vec::with_capacity(per_blade * blades as usize);
    // One blade along +x (vertices at -half and +half), then turned into place.
    let arc = BladeArc::new(half, roundness);
    let steps = arc.equal_area_steps(per_blade);
    for k in 0..blades {
        let turn = rotation + half + 2.0 * half * f64::from(k);
        let (sin, cos) = turn.sin_cos();
        for &p in &steps {
            fan.push(DVec2::new(cos * p.x - sin * p.y, sin * p.x + cos * p.y));
        }
    }
    fan
}

/// One blade's arc through (cos half, -+sin half): a circle of radius `radius` centred on the
/// x axis at `centre_x`, from angle -`span` to +`span` about that centre; straight (no arc)
/// when `radius` is infinite.
struct BladeArc {
    half: f64,
    centre_x: f64,
    radius: f64,
    span: f64,
}

impl BladeArc {
    fn new(half: f64, roundness: f64) -> Self {
        let (chord_half, chord_x) = (half.sin(), half.cos());
        let sagitta = roundness * (1.0 - chord_x);
        if sagitta <= 0.0 {
            return BladeArc {
                half,
                centre_x: 0.0,
                radius: f64::INFINITY,
                span: 0.0,
            };
        }
        let radius = (chord_half * chord_half + sagitta * sagitta) / (2.0 * sagitta);
        BladeArc {
            half,
            centre_x: chord_x + sagitta - radius,
            radius,
            span: (chord_half / radius).asin(),
        }
    }

    /// The point at parameter `t` in [0, 1] from the first vertex to the second.
    fn point(&self, t: f64) -> DVec2 {
        if self.radius.is_infinite() {
            let y = (2.0 * t - 1.0) * self.half.sin();
            return DVec2::new(self.half.cos(), y);
        }
        let angle = (2.0 * t - 1.0) * self.span;
        DVec2::new(
            self.centre_x + self.radius * angle.cos(),
            self.radius * angle.sin(),
        )
    }

    /// `n` points from the first vertex (included) towards the second (excluded) such that
    /// the n triangles (origin, point i, point i + 1), the last ending at the second vertex,
    /// have equal areas: the area per triangle is found by bisection so that the n-th step
    /// lands on the second vertex.
    fn equal_area_steps(&self, n: usize) -> Vec<DVec2> {
        let area = |a: DVec2, b: DVec2| 0.5 * a.perp_dot(b);
        // The parameter after `from` whose triangle has `target` area (area grows with it).
        let step = |from: f64, target: f64| -> f64 {
            let (mut lo, mut hi) = (from, 1.0 + 1.0);
            let a = self.point(from);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if area(a, self.point(mid.min(1.0))) + (mid - 1.0).max(0.0) < target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        };
        let whole = area(self.point(0.0), self.point(1.0));
        let (mut lo, mut hi) = (0.0, whole);
        for _ in 0..100 {
            let target = 0.5 * (lo + hi);
            let mut t = 0.0;
            for _ in 0..n {
                t = step(t, target);
            }
            if t < 1.0 {
                lo = target;
            } else {
                hi = target;
            }
        }
        let target = 0.5 * (lo + hi);
        let mut t = 0.0;
        let mut points = Vec::with_capacity(n);
        for _ in 0..n {
            points.push(self.point(t));
            t = step(t, target).min(1.0);
        }
        points
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
                    aspect: 1.0,
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
            aspect: 1.0,
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
        let mut state = 0x853c_49e6_748f_ea9bu64;
        let mut next = || {
            // PCG-style LCG, the top 24 bits.
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
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
            let (chi2, cells) = chi_square(&Aperture::new(shape), 400_000);
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
