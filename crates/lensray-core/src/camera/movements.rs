//! A view camera's movements: shift and tilt.
//!
//! - **Shift** moves the film window off the lens's axis: in the course's terms the window's
//!   xStart..xStop and yStart..yStop move while the image plane keeps facing along the view
//!   axis, so lines parallel to the film stay parallel in the image (a level camera keeps a
//!   tall building's verticals vertical and shifts up to take in its top). The screen window's
//!   centre moves (`raster::ScreenWindow`), and with it every matrix built from it: the
//!   projection gets its off-axis terms, and the G-buffer, the raster and hybrid paths and the
//!   preview follow. A shift is given in millimetres on the film for a lens with a focal
//!   length (a physical camera, a real lens), and as a fraction of the image height otherwise;
//!   +x moves the window right in the image, +y up.
//! - **Tilt** turns the lens against the film, and the plane of focus turns with it
//!   (Scheimpflug: film plane, lens plane and plane of focus meet in one line). For a thin
//!   lens of focal length f tilted by theta toward hinge direction h, the thin-lens equation
//!   along the tilted axis maps the film plane (z = -v behind the lens) to the plane
//!   (h · p) sin(theta) / f + z (cos(theta) / f - 1 / v) = 1: it crosses the view axis at
//!   1 / D = cos(theta) / f - 1 / v and meets the plane z = 0 through the lens at the hinge
//!   line, J = f / sin(theta) from the axis toward h (the hinge rule). lensray keeps D, the
//!   focus distance a user gives, where the plane crosses the view axis, and sets the film
//!   distance from it: the plane is z + (D / J) h · (x, y) = D (`ThinLens::focus_tilt` =
//!   (D / J) h). The aperture stays facing the film (its foreshortening by cos(theta), under
//!   1 % below 8 degrees, is left out).
//! - A **thin lens in world units** (an aperture radius and a focus distance, no focal length)
//!   has no hinge rule to follow; neither has an orthographic camera. There the tilt turns the
//!   plane of focus itself by theta about the line where it crosses the view axis:
//!   `focus_tilt` = tan(theta) h.
//! - The **tilt direction** is the direction in the image toward which the plane of focus
//!   comes nearer, in degrees counter-clockwise from the image's bottom: 0 lays the plane like
//!   the ground (near at the bottom of the image, falling away toward the top), 90 like a wall
//!   on the right.

use glam::{DVec2, DVec3, Vec2};
use thiserror::Error;

/// Tilts at or past this many degrees lay the plane of focus through the lens.
pub const MAX_TILT_DEGREES: f64 = 90.0;

/// What a user gives for shift and tilt (`--shift`, `--tilt`, `--tilt-direction`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Movements {
    /// The film window's offset from the axis: mm on the film for a lens with a focal length,
    /// a fraction of the image height otherwise; +x right, +y up in the image.
    pub shift: [f64; 2],
    /// The lens's tilt against the film, degrees in [0, 90).
    pub tilt_degrees: f64,
    /// Degrees counter-clockwise from the image's bottom: where the plane of focus comes
    /// nearer (the hinge's side).
    pub tilt_direction_degrees: f64,
}

/// How a tilt turns the plane of focus.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TiltModel {
    /// A thin lens of this focal length (world units): the hinge rule, J = f / sin(tilt).
    FocalLength(f64),
    /// No focal length: the plane of focus turns by the tilt itself.
    PlaneAngle,
}

#[derive(Debug, Error, PartialEq)]
pub enum MovementError {
    #[error("{0} must be a finite number, got {1}")]
    NotFinite(&'static str, String),
    #[error("tilt must be in [0, {MAX_TILT_DEGREES}) degrees, got {0}")]
    Tilt(f64),
    #[error("the tilted plane of focus passes through the lens's opening (hinge {hinge:.4} from the axis, aperture reach {reach:.4}): use a smaller tilt or aperture")]
    HingeInAperture { hinge: f64, reach: f64 },
    #[error("the tilted plane of focus comes nearer than the near plane ({near}) inside the image: use a smaller tilt or move the focus out")]
    PlaneBeforeNear { near: f64 },
    #[error("the three focus points lie on one line: pick three that span the plane")]
    Collinear,
    #[error("the plane through the three focus points passes through the lens: pick points that lie on a plane away from the camera")]
    ThroughLens,
    #[error("the plane through the three focus points does not cross the view axis in front of the camera (it runs parallel to it or crosses behind): aim the camera toward the plane")]
    NotInFront,
    #[error("no tilt of this lens lays the plane of focus through the three points: it would need sin(tilt) = {0:.3}")]
    BeyondTilt(f64),
}

impl Movements {
    pub const NONE: Movements = Movements {
        shift: [0.0, 0.0],
        tilt_degrees: 0.0,
        tilt_direction_degrees: 0.0,
    };

    /// Each value finite, the tilt in [0, 90) degrees.
    pub fn check(&self) -> Result<(), MovementError> {
        if !self
            .shift
            .iter()
            .all(|x| x.is_finite() && (*x as f32).is_finite())
        {
            return Err(MovementError::NotFinite(
                "shift",
                format!("{:?}", self.shift),
            ));
        }
        if !self.tilt_direction_degrees.is_finite() {
            return Err(MovementError::NotFinite(
                "tilt direction",
                self.tilt_direction_degrees.to_string(),
            ));
        }
        if !(0.0..MAX_TILT_DEGREES).contains(&self.tilt_degrees) {
            return Err(MovementError::Tilt(self.tilt_degrees));
        }
        Ok(())
    }

    /// The shift, as a vector.
    pub fn shift(&self) -> DVec2 {
        DVec2::from_array(self.shift)
    }

    /// The unit direction in the image (x right, y up) toward the hinge.
    pub fn hinge_direction(&self) -> DVec2 {
        let (sin, cos) = self.tilt_direction_degrees.to_radians().sin_cos();
        DVec2::new(sin, -cos)
    }

    /// The plane of focus's slope (`ThinLens::focus_tilt`) for focus distance `focus_distance`.
    pub fn focus_tilt(&self, focus_distance: f64, model: TiltModel) -> Vec2 {
        if self.tilt_degrees == 0.0 {
            return Vec2::ZERO;
        }
        let tilt = self.tilt_degrees.to_radians();
        let slope = match model {
            TiltModel::FocalLength(f) => focus_distance * tilt.sin() / f,
            TiltModel::PlaneAngle => tilt.tan(),
        };
        (self.hinge_direction() * slope).as_vec2()
    }
}

/// A plane of focus as the movements and focus that lay it (`--focus-plane`'s answer).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FocusPlane {
    /// Where the plane crosses the view axis, world units.
    pub focus_distance: f64,
    pub tilt_degrees: f64,
    pub tilt_direction_degrees: f64,
}

impl FocusPlane {
    /// The plane of focus through three camera-space points, for a lens that tilts as `model`
    /// says. The plane is m · p = 1 with m = (s, 1) / D (s the slope, D the focus distance):
    /// three equations for m.
    pub fn through(points: [DVec3; 3], model: TiltModel) -> Result<FocusPlane, MovementError> {
        let [p0, p1, p2] = points;
        let normal = (p1 - p0).cross(p2 - p0);
        let span = (p1 - p0).length() * (p2 - p0).length();
        // Depths come in f32: points on one line land up to ~1e-7 off it.
        if normal.length() <= 1e-4 * span || span == 0.0 {
            return Err(MovementError::Collinear);
        }
        let unit = normal.normalize();
        let scale = p0.length().max(p1.length()).max(p2.length());
        if unit.dot(p0).abs() <= 1e-6 * scale {
            return Err(MovementError::ThroughLens);
        }
        let rows = glam::DMat3::from_cols(p0, p1, p2).transpose();
        let m = rows.inverse() * DVec3::ONE;
        if !m.is_finite() || m.z <= 0.0 {
            return Err(MovementError::NotInFront);
        }
        let focus_distance = 1.0 / m.z;
        let slope = DVec2::new(m.x, m.y) / m.z;
        let magnitude = slope.length();
        let tilt = match model {
            TiltModel::FocalLength(f) => {
                let sin = magnitude * f / focus_distance;
                if sin >= 1.0 {
                    return Err(MovementError::BeyondTilt(sin));
                }
                sin.asin()
            }
            TiltModel::PlaneAngle => magnitude.atan(),
        };
        let direction = if magnitude > 0.0 {
            slope.x.atan2(-slope.y).to_degrees().rem_euclid(360.0)
        } else {
            0.0
        };
        Ok(FocusPlane {
            focus_distance,
            tilt_degrees: tilt.to_degrees(),
            tilt_direction_degrees: direction,
        })
    }
}
