//! Physical camera units -> the thin-lens model (slides "Paraxial Approximation").
//!
//! The paraxial derivation ends with s_o depending on s_i alone, which for a thin lens gives the
//! thin-lens equation 1/s_o + 1/s_i = 1/f: every ray leaving a film point at distance s_i behind
//! the lens passes through one point at distance s_o in front of it. That is why `thin_lens` can
//! aim all lens rays of a film point at one focal-plane point.
//!
//! World units are metres here; lens data are in millimetres as photographers give them.

/// Millimetres per world unit (metres).
pub const MM_PER_WORLD_UNIT: f64 = 1000.0;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicalLens {
    pub focal_length_mm: f64,
    pub f_number: f64,
    pub sensor_height_mm: f64,
}

impl PhysicalLens {
    /// Aperture diameter is f / N, so the radius is f / (2 N); in world units.
    pub fn aperture_radius(&self) -> f64 {
        self.focal_length_mm / (2.0 * self.f_number) / MM_PER_WORLD_UNIT
    }

    /// s_i from 1/s_o + 1/s_i = 1/f, in mm; `None` when the subject is at or inside the focal
    /// length (no real image forms).
    pub fn film_distance_mm(&self, focus_distance: f64) -> Option<f64> {
        self.tilted_film_distance_mm(focus_distance, 0.0)
    }

    /// The film distance (mm) of the lens tilted by `tilt` radians whose plane of focus crosses
    /// the view axis at `focus_distance`: 1 / s_i = cos(tilt) / f - 1 / s_o (`movements`);
    /// `None` where no real image forms.
    pub fn tilted_film_distance_mm(&self, focus_distance: f64, tilt: f64) -> Option<f64> {
        let s_o = focus_distance * MM_PER_WORLD_UNIT;
        let f = self.focal_length_mm;
        let inverse = tilt.cos() / f - 1.0 / s_o;
        (s_o > 0.0 && inverse > 0.0).then(|| 1.0 / inverse)
    }

    /// Vertical field of view (radians) of a sensor at the film distance: 2 atan(h / (2 s_i)).
    pub fn vfov(&self, focus_distance: f64) -> Option<f64> {
        let s_i = self.film_distance_mm(focus_distance)?;
        Some(2.0 * (self.sensor_height_mm / (2.0 * s_i)).atan())
    }
}
