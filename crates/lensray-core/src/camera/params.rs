//! What a user gives to describe a camera, checked before anything is built.

use std::sync::Arc;

use glam::Vec3;
use thiserror::Error;

use super::aperture::{ApertureShape, MAX_BLADES};
use super::look_at::CameraFrame;
use super::movements::{MovementError, Movements, TiltModel};
use super::physical::{PhysicalLens, MM_PER_WORLD_UNIT};
use super::real_lens::{RealLens, RealLensError, RealLensParams};
use super::{Aperture, Camera, Lens, Projection, ThinLens};

/// Largest image side accepted.
pub const MAX_IMAGE_SIDE: u32 = 16384;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProjectionParams {
    Perspective { vfov_degrees: f64 },
    Orthographic { height: f64 },
}

#[derive(Clone, Debug, PartialEq)]
pub enum LensParams {
    Pinhole,
    /// World units.
    ThinLens {
        aperture_radius: f64,
        focus_distance: f64,
    },
    /// Photographic units; for perspective, the field of view follows from the sensor height and
    /// the film distance (and replaces `vfov_degrees`).
    Physical {
        lens: PhysicalLens,
        focus_distance: f64,
    },
    /// A lens prescription traced exactly (`real_lens`); the field of view follows from the
    /// lens and the film (and replaces `vfov_degrees`).
    Real(RealLensParams),
}

#[derive(Clone, Debug, PartialEq)]
pub struct CameraParams {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub projection: ProjectionParams,
    pub lens: LensParams,
    pub near: f64,
    pub far: f64,
    pub width: u32,
    pub height: u32,
    /// Shift and tilt (`movements`); `Movements::NONE` for a camera without.
    pub movements: Movements,
}

#[derive(Debug, Error, PartialEq)]
pub enum CameraError {
    #[error("{0} must be a finite number, got {1}")]
    NotFinite(&'static str, String),
    #[error("{0} must be greater than zero, got {1}")]
    NotPositive(&'static str, f64),
    #[error("{0} must not be negative, got {1}")]
    Negative(&'static str, f64),
    #[error("degenerate camera: eye and target coincide")]
    EyeIsTarget,
    #[error("degenerate camera: up {0:?} is parallel to the view direction")]
    UpParallelToView(Vec3),
    #[error("vertical field of view must be in (0, 180) degrees, got {0}")]
    FieldOfView(f64),
    #[error("far plane ({far}) must lie beyond the near plane ({near})")]
    NearFar { near: f64, far: f64 },
    #[error("focus distance {focus} is not in front of the lens (must exceed {min})")]
    FocusNotInFront { focus: f64, min: f64 },
    #[error(
        "focus distance {} m is within the focal length ({} mm): no image forms",
        significant(*.focus),
        significant(*.focal_length_mm)
    )]
    FocusWithinFocalLength { focus: f64, focal_length_mm: f64 },
    #[error("image {0}x{1} is out of range: each side must be in 1..={MAX_IMAGE_SIDE}")]
    ImageSize(u32, u32),
    #[error("aperture blades must be between 3 and {MAX_BLADES}, got {0} (leave them out for a round aperture)")]
    ApertureBlades(u32),
    #[error("aperture roundness must be in [0, 1] (0: straight blades, 1: round), got {0}")]
    ApertureRoundness(f32),
    #[error(transparent)]
    RealLens(#[from] RealLensError),
    #[error(transparent)]
    Movement(#[from] MovementError),
}

impl ApertureShape {
    /// The aperture of this shape, each value checked; the error names the first bad one.
    pub fn build(&self) -> Result<Aperture, CameraError> {
        if let Some(blades) = self.blades {
            if !(3..=MAX_BLADES).contains(&blades) {
                return Err(CameraError::ApertureBlades(blades));
            }
        }
        if !self.rotation_degrees.is_finite() {
            return Err(CameraError::NotFinite(
                "aperture rotation",
                self.rotation_degrees.to_string(),
            ));
        }
        if !(0.0..=1.0).contains(&self.roundness) {
            return Err(CameraError::ApertureRoundness(self.roundness));
        }
        positive("aperture aspect", f64::from(self.aspect))?;
        Ok(Aperture::new(self.clone()))
    }
}

/// `x` to 4 significant digits without trailing zeros, for messages (a focus distance of
/// 0.014248992316424847 m reads 0.01425, a focal length of 50 mm 50).
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    let decimals = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

fn finite_vec(name: &'static str, v: Vec3) -> Result<(), CameraError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(CameraError::NotFinite(name, format!("{v:?}")))
    }
}

pub(crate) fn positive(name: &'static str, x: f64) -> Result<f64, CameraError> {
    if !x.is_finite() || !(x as f32).is_finite() {
        Err(CameraError::NotFinite(name, x.to_string()))
    } else if x <= 0.0 || !(x as f32).is_normal() {
        Err(CameraError::NotPositive(name, x))
    } else {
        Ok(x)
    }
}

fn non_negative(name: &'static str, x: f64) -> Result<f64, CameraError> {
    if !x.is_finite() || !(x as f32).is_finite() {
        Err(CameraError::NotFinite(name, x.to_string()))
    } else if x < 0.0 {
        Err(CameraError::Negative(name, x))
    } else {
        Ok(x)
    }
}

/// A checked lens: the thin-lens model the camera is built with (a real lens's first-order
/// one), the field of view it sets (radians; none where the projection's own applies) and the
/// real lens, if any.
struct BuiltLens {
    thin: ThinLens,
    vfov: Option<f64>,
    real: Option<RealLens>,
    /// Screen units per mm of `Movements::shift` for a lens with a focal length (`None`:
    /// the shift is in image heights).
    shift_scale: Option<f64>,
}

impl CameraParams {
    /// Validates every parameter and builds the camera; the error names the first bad one.
    ///
    /// The checks hold for the f32 values the camera is built from, not only for the f64
    /// parameters: a value valid in f64 can overflow to infinity or underflow to 0 on conversion
    /// (infinite or NaN matrices), two distinct values can become equal (far == near, or the
    /// orthographic focus and near planes), and a vfov just under 180 degrees (179.999999) can
    /// round to an f32 half angle past pi/2, whose tangent is negative: the screen window would
    /// have a negative half height and the image would come out mirrored (`tests/camera.rs`,
    /// `validation::build_rejects_values_degenerate_in_f32`).
    pub fn build(&self) -> Result<Camera, CameraError> {
        self.build_with_aperture(Aperture::ROUND)
    }

    /// `build` with the aperture shaped as `aperture`: what `build()?.with_aperture(aperture)`
    /// gives, but a real lens's exit pupil is bounded once, for the shaped stop (bounding it
    /// traces millions of rays).
    pub fn build_with_aperture(&self, aperture: Aperture) -> Result<Camera, CameraError> {
        let frame = self.check_frame()?;
        self.check_image_size()?;
        let (near, far) = self.check_clip_planes()?;
        self.movements.check()?;
        let lens = self.build_lens(near, &aperture)?;
        let projection = self.build_projection(lens.vfov)?;
        let shift_scale = lens
            .shift_scale
            .unwrap_or(2.0 * f64::from(projection.screen_half_height()));
        let screen_shift = (self.movements.shift() * shift_scale).as_vec2();

        let lens = match lens.real {
            Some(real) => Lens::Real {
                real: Arc::new(real),
                first_order: lens.thin,
            },
            None => Lens::Thin(lens.thin),
        };
        let camera = Camera::new(
            projection,
            frame,
            lens,
            near as f32,
            far as f32,
            self.width,
            self.height,
            screen_shift,
        );
        // The real lens already has its shaped stop: this sets the thin lens's aperture.
        let camera = camera.with_aperture(aperture)?;
        check_plane_of_focus(&camera)?;
        Ok(camera)
    }

    /// The camera's frame from eye, target and up, each finite and not degenerate.
    fn check_frame(&self) -> Result<CameraFrame, CameraError> {
        finite_vec("eye", self.eye)?;
        finite_vec("target", self.target)?;
        finite_vec("up", self.up)?;
        if (self.target - self.eye).length() <= f32::EPSILON * self.eye.length().max(1.0) {
            return Err(CameraError::EyeIsTarget);
        }
        CameraFrame::look_at(self.eye, self.target, self.up)
            .ok_or(CameraError::UpParallelToView(self.up))
    }

    /// Each image side in 1..=MAX_IMAGE_SIDE.
    fn check_image_size(&self) -> Result<(), CameraError> {
        if !(1..=MAX_IMAGE_SIDE).contains(&self.width)
            || !(1..=MAX_IMAGE_SIDE).contains(&self.height)
        {
            return Err(CameraError::ImageSize(self.width, self.height));
        }
        Ok(())
    }

    /// Near and far, positive and apart in f32.
    fn check_clip_planes(&self) -> Result<(f64, f64), CameraError> {
        let near = positive("near", self.near)?;
        let far = positive("far", self.far)?;
        if far as f32 <= near as f32 {
            return Err(CameraError::NearFar { near, far });
        }
        Ok((near, far))
    }

    /// The lens of `self.lens`, checked: its thin-lens model, the field of view it sets (none
    /// for a pinhole or a thin lens in world units) and the real lens, if any, its stop shaped
    /// as `aperture`.
    fn build_lens(&self, near: f64, aperture: &Aperture) -> Result<BuiltLens, CameraError> {
        let (thin, vfov) = match &self.lens {
            LensParams::Pinhole => (ThinLens::PINHOLE, None),
            &LensParams::ThinLens {
                aperture_radius,
                focus_distance,
            } => {
                let aperture_radius = non_negative("aperture radius", aperture_radius)?;
                let focus_distance = self.check_focus(focus_distance, near)?;
                let focus_tilt = self
                    .movements
                    .focus_tilt(focus_distance, TiltModel::PlaneAngle);
                (
                    ThinLens {
                        aperture_radius: aperture_radius as f32,
                        focus_distance: focus_distance as f32,
                        focus_tilt,
                        aperture: Aperture::ROUND,
                    },
                    None,
                )
            }
            &LensParams::Physical {
                lens,
                focus_distance,
            } => return self.build_physical_lens(&lens, focus_distance, near),
            LensParams::Real(params) => return self.build_real_lens(params, near, aperture),
        };
        Ok(BuiltLens {
            thin,
            vfov,
            real: None,
            shift_scale: None,
        })
    }

    /// A lens in photographic units: its thin-lens model (the plane of focus tilted by the
    /// hinge rule), the field of view it gives and the film's screen units per mm.
    fn build_physical_lens(
        &self,
        lens: &PhysicalLens,
        focus_distance: f64,
        near: f64,
    ) -> Result<BuiltLens, CameraError> {
        positive("focal length (mm)", lens.focal_length_mm)?;
        positive("f-number", lens.f_number)?;
        positive("sensor height (mm)", lens.sensor_height_mm)?;
        non_negative("aperture radius", lens.aperture_radius())?;
        let focus_distance = self.check_focus(focus_distance, near)?;
        let tilt = self.movements.tilt_degrees.to_radians();
        let film_distance_mm = lens.tilted_film_distance_mm(focus_distance, tilt).ok_or(
            CameraError::FocusWithinFocalLength {
                focus: focus_distance,
                focal_length_mm: lens.focal_length_mm,
            },
        )?;
        let vfov = 2.0 * (lens.sensor_height_mm / (2.0 * film_distance_mm)).atan();
        let focal_length = lens.focal_length_mm / MM_PER_WORLD_UNIT;
        let focus_tilt = self
            .movements
            .focus_tilt(focus_distance, TiltModel::FocalLength(focal_length));
        Ok(BuiltLens {
            thin: ThinLens {
                aperture_radius: lens.aperture_radius() as f32,
                focus_distance: focus_distance as f32,
                focus_tilt,
                aperture: Aperture::ROUND,
            },
            vfov: Some(vfov),
            real: None,
            shift_scale: Some(1.0 / film_distance_mm),
        })
    }

    /// A lens prescription traced exactly, its stop shaped as `aperture`, with its first-order
    /// model and the field of view it gives.
    fn build_real_lens(
        &self,
        params: &RealLensParams,
        near: f64,
        aperture: &Aperture,
    ) -> Result<BuiltLens, CameraError> {
        if matches!(self.projection, ProjectionParams::Orthographic { .. }) {
            return Err(RealLensError::Orthographic.into());
        }
        if let Some(n) = params.f_number {
            positive("f-number", n)?;
        }
        positive("sensor height (mm)", params.sensor_height_mm)?;
        let focus_distance = self.check_focus(params.focus_distance, near)?;
        let params = RealLensParams {
            focus_distance,
            movements: self.movements,
            ..params.clone()
        };
        let aspect = self.width as f32 / self.height as f32;
        let real = RealLens::new(params, aspect, aperture.clone())?;
        // The first-order model: a thin lens at the entrance pupil, its radius the
        // pupil's, focused where the real lens is; tilted, its plane of focus is the thin
        // lens's of the same focal length (the hinge rule; the traced one comes from the
        // optics, `real_lens::film`).
        let efl = real.first_order.efl / MM_PER_WORLD_UNIT;
        let thin = ThinLens {
            aperture_radius: real.entrance_pupil_radius() as f32,
            focus_distance: focus_distance as f32,
            focus_tilt: self
                .movements
                .focus_tilt(focus_distance, TiltModel::FocalLength(efl)),
            aperture: Aperture::ROUND,
        };
        let vfov = real.pinhole_vfov();
        Ok(BuiltLens {
            thin,
            vfov: Some(vfov),
            shift_scale: Some(real.pinhole_shift_scale()),
            real: Some(real),
        })
    }

    /// The projection, its field of view `lens_vfov` (radians) where the lens sets one; in f32,
    /// the tangent of a perspective's half angle must be positive and finite (see `build`).
    fn build_projection(&self, lens_vfov: Option<f64>) -> Result<Projection, CameraError> {
        Ok(match self.projection {
            ProjectionParams::Perspective { vfov_degrees } => {
                let vfov = match lens_vfov {
                    Some(vfov) => vfov,
                    None => {
                        if !vfov_degrees.is_finite() || vfov_degrees <= 0.0 || vfov_degrees >= 180.0
                        {
                            return Err(CameraError::FieldOfView(vfov_degrees));
                        }
                        vfov_degrees.to_radians()
                    }
                };
                let projection = Projection::Perspective { vfov: vfov as f32 };
                let half = projection.screen_half_height();
                if !(half.is_normal() && half > 0.0) {
                    return Err(CameraError::FieldOfView(match lens_vfov {
                        Some(vfov) => vfov.to_degrees(),
                        None => vfov_degrees,
                    }));
                }
                projection
            }
            ProjectionParams::Orthographic { height } => Projection::Orthographic {
                height: positive("orthographic view height", height)? as f32,
            },
        })
    }

    /// The focal plane must lie in front of the lens plane (the eye for perspective, the near
    /// plane where orthographic rays start).
    fn check_focus(&self, focus: f64, near: f64) -> Result<f64, CameraError> {
        let min = match self.projection {
            ProjectionParams::Orthographic { .. } => near,
            ProjectionParams::Perspective { .. } => 0.0,
        };
        if !focus.is_finite() || !(focus as f32).is_finite() {
            return Err(CameraError::NotFinite("focus distance", focus.to_string()));
        }
        if focus <= min || focus as f32 <= min as f32 {
            return Err(CameraError::FocusNotInFront { focus, min });
        }
        Ok(focus)
    }
}

/// A tilted plane of focus must stay clear of the lens: its hinge outside the opening's reach
/// (else lens rays would cross the plane at the lens), and for orthographic rays, which start
/// on the near plane, beyond that plane over the whole image.
fn check_plane_of_focus(camera: &Camera) -> Result<(), MovementError> {
    let lens = camera.lens.first_order();
    let s = lens.focus_tilt;
    if s == glam::Vec2::ZERO {
        return Ok(());
    }
    let depth = lens.focus_distance - camera.lens_plane_z();
    let reach = lens.reach();
    if depth - s.length() * reach <= 0.0 {
        return Err(MovementError::HingeInAperture {
            hinge: f64::from(depth / s.length()),
            reach: f64::from(reach),
        });
    }
    if camera.is_orthographic() {
        let w = &camera.screen_window;
        for (x, y) in [
            (w.x_start(), w.y_start()),
            (w.x_start(), w.y_stop()),
            (w.x_stop(), w.y_start()),
            (w.x_stop(), w.y_stop()),
        ] {
            if lens.focus_depth_at(glam::Vec2::new(x, y)) <= camera.near {
                return Err(MovementError::PlaneBeforeNear {
                    near: f64::from(camera.near),
                });
            }
        }
    }
    Ok(())
}
