//! A real lens in the camera (where the course says "in practice, the ray will
//! refract twice when passing through the lens"): each camera ray leaves a film point, aims at
//! a point of the exit pupil's bounds and is refracted exactly through every surface of a lens
//! prescription (`optics::trace::narrow`), the stop's opening shaped as `aperture` says.
//!
//! # Spaces
//! - **Lens space** (mm): z along the axis from the first vertex, + toward the film; x, y are
//!   camera space's x, y. The film is the plane z = `film_z`.
//! - **Camera space** (world units, metres) has its origin at the **entrance pupil**'s centre
//!   and +z toward the scene: `camera = ((x, y, entrance_pupil_z - z) / 1000)`. The pinhole at
//!   the entrance pupil that the raster G-buffer, the hybrid and the raster path use (the
//!   lens's first-order model, `Lens::first_order`) sits at the same origin, so depths agree.
//! - The image on the film is inverted: raster (column, row) maps to the film point
//!   `-(u, v)`, with (u, v) the raster point's offset from the image centre in film mm (+u to
//!   the image's right, +v up).
//!
//! # Radiometry (stated; tested in `tests/real_lens.rs` against an integration over the
//! exit pupil)
//! A film point's irradiance is E = integral over the rear plane of L cos^4(theta) / d^2 dA
//! (theta from the axis, d the film's distance to that plane). A sample drawn uniformly over
//! the bounds (area A) weighs `T cos^4(theta) A / I0`, T the stop's transmission at the ray
//! (0 when a surface blocks it), and I0 the integral of T cos^4(theta) over the passing region
//! seen from the film's centre. So the image's centre shows the scene's radiance at every
//! f-number (lensray's exposure convention: the f-number changes depth of field, not
//! brightness), and toward the corners the image darkens as the real lens does: cos^4 (natural
//! vignetting) times the share of the pupil the clear apertures let through (optical
//! vignetting, the cat-eye). The estimate is the physical pbrt one up to the constant 1 / E0.

mod film;
mod focus;
mod lanes;
mod pupil;
mod recent;

use std::sync::Arc;

use glam::{Mat3, Vec2, Vec3};
use thiserror::Error;

use super::physical::MM_PER_WORLD_UNIT;
use super::{Aperture, Movements, Ray};
use crate::optics::paraxial::FirstOrder;
use crate::optics::trace::narrow::{Elements, Interface, LensRay};
use crate::optics::trace::Toward;
use crate::optics::Prescription;
pub use film::{FilmFrame, Tilt};
use lanes::Lanes;
pub use pupil::{ExitPupil, PupilBin, Region, PUPIL_BINS};

/// Lenses are marked with f-numbers rounded to a scale of third stops (an f/2.03 design is
/// sold as f/2): asking for an f-number at most a sixth of a stop (2^(1/12)) wider than the
/// widest opens the lens fully, and the summary names the real f-number. Wider is an error.
pub const MARKING_TOLERANCE: f64 = 1.059_463_094_359_295_3;

/// What a user gives for a real lens (`--lens`, `--f-number`, `--focus-distance`,
/// `--sensor-height-mm`).
#[derive(Clone, Debug, PartialEq)]
pub struct RealLensParams {
    pub prescription: Arc<Prescription>,
    /// `None`: wide open.
    pub f_number: Option<f64>,
    /// World units from the entrance pupil along the axis.
    pub focus_distance: f64,
    pub sensor_height_mm: f64,
    /// Whether camera rays carry a wavelength through a dispersive lens (`--dispersion`);
    /// a lens without Abbe numbers has none either way.
    pub dispersion: bool,
    /// The film window's shift off the axis in mm (`Movements::shift`: +x right, +y up in the
    /// image), and the lens's tilt about its entrance pupil (`film`).
    pub movements: Movements,
}

#[derive(Debug, Error, PartialEq)]
pub enum RealLensError {
    #[error(
        "lens {lens} opens to f/{widest:.3} at most (its stop's full diameter); f/{asked} is wider"
    )]
    PastFullStop {
        lens: String,
        asked: f64,
        widest: f64,
    },
    #[error("lens {lens} cannot focus at {focus} m: the subject must lie beyond its front focal point, more than {nearest:.4} m from the entrance pupil")]
    CannotFocus {
        lens: String,
        focus: f64,
        nearest: f64,
    },
    #[error("lens {lens} at f/{f_number:.3}: no ray from the film's centre passes the lens")]
    NoLight { lens: String, f_number: f64 },
    #[error("a real lens (--lens) needs the perspective projection")]
    Orthographic,
    #[error("the shifted film reaches {corner_mm:.2} mm from the axis of lens {lens}, past its image circle: light reaches {circle_mm:.2} mm at most (the film's half diagonal plus the shift must stay within it)")]
    ShiftPastImageCircle {
        lens: String,
        corner_mm: f64,
        circle_mm: f64,
    },
    #[error("the tilted film's corner {corner_mm:.2} mm from the axis of lens {lens} gets no light: the tilt swings it past the lens's image circle (tilt less, or take a lens that covers more)")]
    TiltPastImageCircle { lens: String, corner_mm: f64 },
}

/// A real lens focused and stopped down, ready to trace camera rays.
#[derive(Clone, Debug, PartialEq)]
pub struct RealLens {
    pub params: RealLensParams,
    /// The prescription with the stop opened to the f-number.
    pub stopped: Prescription,
    /// First-order data of `stopped`.
    pub first_order: FirstOrder,
    pub f_number: f64,
    /// Last vertex to the film, mm.
    pub film_distance_mm: f64,
    elements: Elements,
    stop: usize,
    /// The opening's circumscribed radius at the stop, mm (the shape's unit circle).
    stop_radius: f32,
    aperture: Aperture,
    /// The film in lens space (square to the axis unless the lens tilts).
    film: FilmFrame,
    /// Camera space from lens space unflipped: the tilt's turn (`film`).
    camera_from_lens: Mat3,
    /// Lens-space z of the entrance pupil (camera space's origin).
    entrance_pupil_z: f32,
    /// Half the film's height, mm; the film's width follows the image's aspect.
    film_half_height: f32,
    /// The film window's shift, mm (+x right, +y up in the image).
    film_shift: Vec2,
    /// The image's width over its height.
    aspect: f32,
    pupil: ExitPupil,
}

impl RealLens {
    /// The lens of `params` for an image of aspect `aspect` (width / height), its stop shaped
    /// as `aperture`: stopped down, focused, its exit pupil bounded.
    ///
    /// Bounding the exit pupil traces millions of rays (about half a second on two cores), and
    /// the preview resolves its camera every frame, mostly with the lens unchanged: the last
    /// few lenses built are kept and returned again for the same arguments (the build is a
    /// function of them, so the copy is the lens a new build would make).
    pub fn new(
        params: RealLensParams,
        aspect: f32,
        aperture: Aperture,
    ) -> Result<Self, RealLensError> {
        if let Some(real) = recent::find(&params, aspect, &aperture) {
            return Ok(real);
        }
        let real = Self::build(params, aspect, aperture)?;
        recent::keep(&real);
        Ok(real)
    }

    fn build(
        params: RealLensParams,
        aspect: f32,
        aperture: Aperture,
    ) -> Result<Self, RealLensError> {
        let lens = &params.prescription;
        let full = FirstOrder::of(lens);
        let asked = params.f_number.unwrap_or(full.f_number);
        if asked < full.f_number / MARKING_TOLERANCE {
            return Err(RealLensError::PastFullStop {
                lens: lens.name.clone(),
                asked,
                widest: full.f_number,
            });
        }
        let f_number = asked.max(full.f_number);
        let stop = lens.stop();
        let stop_diameter = lens.surfaces()[stop].diameter * full.f_number / f_number;
        let stopped = lens.with_stop_diameter(stop_diameter);
        let first_order = FirstOrder::of(&stopped);
        let tilt = Tilt::of(&params.movements);
        let entrance_pupil_z = first_order.entrance_pupil.position_mm;
        let film = if tilt.is_square() {
            FilmFrame::square(focus::film_z(
                &stopped,
                &first_order,
                params.focus_distance,
            )?)
        } else {
            let distance = tilt.film_distance(&stopped, &first_order, params.focus_distance)?;
            tilt.film(distance, entrance_pupil_z)
        };
        let stop_radius = 0.5 * stop_diameter as f32;
        // The tracer's own check at the stop bounds every shape; `trace` applies the shape.
        let mut elements = Elements::new(&stopped);
        elements.interfaces[stop].aperture_radius = stop_radius * aperture.reach();
        let film_half_height = 0.5 * params.sensor_height_mm as f32;
        let film_half = Vec2::new(film_half_height * aspect, film_half_height);
        let film_shift = params.movements.shift().as_vec2();
        let mut real = RealLens {
            film_distance_mm: f64::from(film.axis_z) - stopped.length(),
            entrance_pupil_z: entrance_pupil_z as f32,
            camera_from_lens: tilt.camera_from_lens(),
            params,
            stopped,
            first_order,
            f_number,
            elements,
            stop,
            stop_radius,
            aperture,
            film,
            film_half_height,
            film_shift,
            aspect,
            pupil: ExitPupil::EMPTY,
        };
        // A shifted window's farthest corner lies its shift farther from the axis; a tilted
        // film's corners are found one by one.
        let corners = film.corners(film_half, film_shift);
        let film_radius = if tilt.is_square() {
            film_half.length() + film_shift.length()
        } else {
            FilmFrame::reach(&corners)
        };
        real.pupil = ExitPupil::bound(&real, film_radius);
        // A moved film must stay in the image circle (the lens's own film may darken to 0).
        // Square to the axis the circle is the pupil's; a tilted film's corners lie at
        // different depths behind the lens, and each is asked whether light reaches it.
        if tilt.is_square() && film_shift != Vec2::ZERO {
            let circle = real.pupil.image_circle();
            if circle < film_radius {
                return Err(RealLensError::ShiftPastImageCircle {
                    lens: real.name().into(),
                    corner_mm: f64::from(film_radius),
                    circle_mm: f64::from(circle),
                });
            }
        }
        if let Some(dark) = corners
            .iter()
            .find(|&&c| !tilt.is_square() && !real.lights(c))
        {
            return Err(RealLensError::TiltPastImageCircle {
                lens: real.name().into(),
                corner_mm: f64::from(Vec2::new(dark.x, dark.y).length()),
            });
        }
        if real.pupil.inverse_centre_integral <= 0.0 {
            return Err(RealLensError::NoLight {
                lens: real.name().into(),
                f_number,
            });
        }
        Ok(real)
    }

    /// Whether any ray from film point `film` (lens space) passes the lens: a grid over the
    /// rear element, as the exit pupil's search starts.
    fn lights(&self, film: Vec3) -> bool {
        self.pupil.lights(self, film)
    }

    /// The same lens with the stop shaped as `aperture` (or the same lens if it already is).
    pub fn with_aperture(&self, aperture: Aperture, aspect: f32) -> Result<Self, RealLensError> {
        if aperture == self.aperture && aspect == self.aspect() {
            return Ok(self.clone());
        }
        Self::new(self.params.clone(), aspect, aperture)
    }

    pub fn name(&self) -> &str {
        &self.params.prescription.name
    }

    /// The film's width over its height.
    pub fn aspect(&self) -> f32 {
        self.aspect
    }

    pub fn elements(&self) -> &Elements {
        &self.elements
    }

    pub fn pupil(&self) -> &ExitPupil {
        &self.pupil
    }

    /// The stop's row, its opening's circumscribed radius (mm) and shape.
    pub fn stop(&self) -> (usize, f32, &Aperture) {
        (self.stop, self.stop_radius, &self.aperture)
    }

    /// Lens-space z where the film crosses the lens's axis (the film's plane, untilted).
    pub fn film_z(&self) -> f32 {
        self.film.axis_z
    }

    pub fn film(&self) -> &FilmFrame {
        &self.film
    }

    /// Camera space from lens space unflipped ((x, y, entrance_pupil_z - z)): the tilt's
    /// turn, the identity untilted.
    pub fn camera_from_lens_turn(&self) -> Mat3 {
        self.camera_from_lens
    }

    pub fn entrance_pupil_z(&self) -> f32 {
        self.entrance_pupil_z
    }

    pub fn film_half_height(&self) -> f32 {
        self.film_half_height
    }

    /// The vertical field of view (radians) of the pinhole at the entrance pupil that images
    /// the film as the lens does to first order: a film height h behind the exit pupil by
    /// d_xp leaves it at slope h / d_xp, and the pupils' Lagrange invariant turns that into
    /// h / d_xp * D_xp / D_ep in the scene (no distortion, which the traced rays add).
    pub fn pinhole_vfov(&self) -> f64 {
        let fo = &self.first_order;
        let exit_pupil_z = self.stopped.length() + fo.exit_pupil.position_mm;
        // The exit pupil's distance from the film's plane.
        let (origin, n) = (self.film.origin.as_dvec3(), self.film.normal.as_dvec3());
        let d_xp = n.x * origin.x + n.y * origin.y + n.z * (origin.z - exit_pupil_z);
        let slope = f64::from(self.film_half_height) / d_xp * fo.exit_pupil.diameter_mm
            / fo.entrance_pupil.diameter_mm;
        2.0 * slope.atan()
    }

    /// Screen units (the first-order pinhole's plane z = 1) per mm on the film: the slope of
    /// [`Self::pinhole_vfov`] per mm of film height.
    pub fn pinhole_shift_scale(&self) -> f64 {
        let half = (0.5 * self.pinhole_vfov()).tan();
        half / f64::from(self.film_half_height)
    }

    /// The film window's shift, mm (+x right, +y up in the image).
    pub fn film_shift(&self) -> Vec2 {
        self.film_shift
    }

    /// The raster point whose film point lies on the axis (the image's centre moved against
    /// the shift): `film_point`'s origin, which the GPU receives as it is.
    pub fn raster_centre(&self, width: u32, height: u32) -> Vec2 {
        let mm_per_pixel = 2.0 * self.film_half_height / height as f32;
        Vec2::new(
            0.5 * width as f32 - self.film_shift.x / mm_per_pixel,
            0.5 * height as f32 + self.film_shift.y / mm_per_pixel,
        )
    }

    /// The entrance pupil's radius, world units: the first-order thin lens's aperture.
    pub fn entrance_pupil_radius(&self) -> f64 {
        0.5 * self.first_order.entrance_pupil.diameter_mm / MM_PER_WORLD_UNIT
    }

    /// The film point (lens space, mm) of raster point `p_raster` in an image of
    /// `width` x `height` pixels: inverted, the film's height spanning the image's.
    pub fn film_point(&self, p_raster: Vec2, width: u32, height: u32) -> Vec3 {
        let mm_per_pixel = 2.0 * self.film_half_height / height as f32;
        let centre = self.raster_centre(width, height);
        let u = (p_raster.x - centre.x) * mm_per_pixel;
        let v = (centre.y - p_raster.y) * mm_per_pixel;
        self.film.point(u, v)
    }

    /// The real lens's camera ray (camera space) of film point `film` (from
    /// [`Self::film_point`]) and lens sample `lens_u` in [0, 1)^2 at dispersion offset `k`
    /// (`optics::glass::dispersion_offset_f32` of the sample's wavelength; 0: the d line),
    /// with its weight (see the module's radiometry); `None` when the lens blocks it.
    pub fn generate_ray(&self, film: Vec3, lens_u: Vec2, k: f32) -> Option<(Ray, f32)> {
        let (start, area) = self.start(film, lens_u);
        let (out, transmission) = self.trace_to_scene_at(start, k)?;
        Some(self.finish(start, area, out, transmission))
    }

    /// [`Self::generate_ray`] for many samples (film point, lens sample, dispersion offset) at
    /// once, bit for bit: the rays cross the lens surface by surface together, laid out by lane
    /// so each surface's arithmetic runs as vector instructions across them (`lanes.rs`).
    pub fn generate_rays<const N: usize>(
        &self,
        samples: &[(Vec3, Vec2, f32)],
        out: &mut [Option<(Ray, f32)>; N],
    ) {
        let n = samples.len().min(N);
        let (mut lanes, area) = Lanes::<N>::start(self, samples);
        let starts: [LensRay; N] = std::array::from_fn(|l| lanes.ray(l));
        lanes.trace_to_scene(self);
        for l in 0..N {
            out[l] = (l < n && lanes.alive[l])
                .then(|| self.finish(starts[l], area[l], lanes.ray(l), lanes.transmission[l]));
        }
    }

    /// The ray from `film` toward the pupil point of `lens_u`, and the area it was drawn from.
    fn start(&self, film: Vec3, lens_u: Vec2) -> (LensRay, f32) {
        let (rear, area) = self.pupil.sample(film, lens_u);
        let toward_rear = rear - film;
        let start = LensRay {
            origin: film,
            direction: toward_rear.normalize(),
        };
        (start, area)
    }

    /// The camera ray and weight of a ray that left the film as `start` and the lens as
    /// `out`. The weight's cos^4 (the parent module's radiometry) holds for a film square to
    /// the axis; a tilted film's irradiance, cos(film) cos(rear) / d^2 dA, is that times
    /// (cos(film) / cos(rear)) (h0 / h)^2, h the film point's distance from the rear plane
    /// along the axis and h0 the film centre's: exactly 1 untilted.
    fn finish(&self, start: LensRay, area: f32, out: LensRay, transmission: f32) -> (Ray, f32) {
        let (d, n) = (start.direction, self.film.normal);
        let cos2 = d.z * d.z;
        let cos_film = (d.x * n.x + d.y * n.y) + d.z * n.z;
        let ratio = self.pupil.axis_depth / (start.origin.z - self.pupil.rear_z);
        let tilted = (cos_film / d.z) * (ratio * ratio);
        let weight =
            transmission * (cos2 * cos2) * area * self.pupil.inverse_centre_integral * tilted;
        (self.camera_from_lens(out), weight)
    }

    /// `ray` from the film through every surface to the scene at the d line, and the stop's
    /// transmission where it crosses (`None`: blocked).
    pub fn trace_to_scene(&self, ray: LensRay) -> Option<(LensRay, f32)> {
        self.trace_to_scene_at(ray, 0.0)
    }

    /// [`Self::trace_to_scene`] at dispersion offset `k`.
    pub fn trace_to_scene_at(&self, ray: LensRay, k: f32) -> Option<(LensRay, f32)> {
        let mut ray = ray;
        let mut transmission = 1.0;
        for i in (0..self.elements.interfaces.len()).rev() {
            ray = self.cross(i, ray, k, &mut transmission)?;
        }
        Some((ray, transmission))
    }

    /// Whether camera rays carry a wavelength: the lens has dispersive glass and the user
    /// left dispersion on.
    pub fn dispersive(&self) -> bool {
        self.params.dispersion && self.stopped.is_dispersive()
    }

    /// The dispersion offsets the exit pupil is bounded at: the d line, and for a dispersive
    /// lens both ends of the sampled spectrum (the pupil shifts and scales smoothly with the
    /// index in between).
    pub fn bounding_offsets(&self) -> Vec<f32> {
        use crate::film::spectral::{WAVELENGTH_MAX_NM, WAVELENGTH_MIN_NM};
        use crate::optics::glass::dispersion_offset_f32;
        if !self.dispersive() {
            return vec![0.0];
        }
        vec![
            0.0,
            dispersion_offset_f32(WAVELENGTH_MIN_NM),
            dispersion_offset_f32(WAVELENGTH_MAX_NM),
        ]
    }

    /// `ray` after surface `i` toward the scene at dispersion offset `k` (`None`: blocked); at
    /// the stop, its transmission goes to `transmission`.
    #[inline(always)]
    fn cross(&self, i: usize, ray: LensRay, k: f32, transmission: &mut f32) -> Option<LensRay> {
        let interface: &Interface = &self.elements.interfaces[i];
        if i == self.stop {
            // The opening (flat, in air): the ray goes on unrefracted.
            let (t, _) = interface.intersect(ray)?;
            let p = ray.origin + t * ray.direction;
            *transmission = self
                .aperture
                .transmission(Vec2::new(p.x, p.y) / self.stop_radius);
            if *transmission <= 0.0 {
                return None;
            }
            return Some(ray);
        }
        interface.pass_at(ray, Toward::Scene, k)
    }

    /// A lens-space ray in camera space (world units; +z toward the scene): flipped along the
    /// axis, turned by the tilt. The turn is written out (`turn`) so that the GLSL mirror
    /// rounds as this does, and the identity leaves every coordinate as it is.
    pub fn camera_from_lens(&self, ray: LensRay) -> Ray {
        let scale = 1.0 / MM_PER_WORLD_UNIT as f32;
        let o = ray.origin;
        let d = ray.direction;
        let origin = turn(
            &self.camera_from_lens,
            Vec3::new(o.x, o.y, self.entrance_pupil_z - o.z),
        );
        Ray {
            origin: Vec3::new(origin.x * scale, origin.y * scale, origin.z * scale),
            direction: turn(&self.camera_from_lens, Vec3::new(d.x, d.y, -d.z)),
        }
    }

    /// One line for the render's summary.
    pub fn summary(&self) -> String {
        use crate::film::spectral::{WAVELENGTH_MAX_NM, WAVELENGTH_MIN_NM};
        let colour = if self.dispersive() {
            format!("dispersion {WAVELENGTH_MIN_NM}-{WAVELENGTH_MAX_NM} nm")
        } else if self.stopped.is_dispersive() {
            "dispersion off".to_owned()
        } else {
            "no dispersion (no Abbe numbers)".to_owned()
        };
        format!(
            "lens {} at f/{:.2}, film {:.3} mm behind the last vertex, {colour}",
            self.name(),
            self.f_number,
            self.film_distance_mm
        )
    }
}

/// `m v` as ((c0 x + c1 y) + c2 z), coordinate by coordinate.
#[inline(always)]
fn turn(m: &Mat3, v: Vec3) -> Vec3 {
    let (c0, c1, c2) = (m.x_axis, m.y_axis, m.z_axis);
    Vec3::new(
        (c0.x * v.x + c1.x * v.y) + c2.x * v.z,
        (c0.y * v.x + c1.y * v.y) + c2.y * v.z,
        (c0.z * v.x + c1.z * v.y) + c2.z * v.z,
    )
}

#[cfg(test)]
mod tests;
