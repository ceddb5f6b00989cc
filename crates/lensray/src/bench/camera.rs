//! The shot's camera as the JSON file gives it: everything an outside renderer needs to frame
//! the same image (the comparison with Mitsuba 3, `scripts/mitsuba/`, reads it).

use serde::Serialize;

use lensray_core::camera::{Camera, Lens, Projection};

/// The camera of a shot, resolved: world units of the scene as the bench holds it (metres: a
/// scene in other units is scaled), pixel rows from the top of the image.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CameraInfo {
    pub eye: [f32; 3],
    /// A point on the view axis, one unit in front of the eye.
    pub target: [f32; 3],
    /// The camera's true up: unit length, orthogonal to the view axis (the up given in the
    /// settings, made orthogonal).
    pub up: [f32; 3],
    /// "perspective" or "orthographic".
    pub projection: &'static str,
    /// The vertical field of view (perspective; the horizontal follows from width / height).
    pub vfov_degrees: Option<f64>,
    /// The view's height in world units (orthographic).
    pub ortho_height: Option<f32>,
    /// "thin", or "real": a lens traced surface by surface, of which `aperture_radius` and
    /// `focus_distance` describe the first-order thin lens.
    pub lens: &'static str,
    /// "round", or "shaped" (blades, an aspect or an image: `aperture_radius` is the radius of
    /// the circle the shape is inscribed in).
    pub aperture: &'static str,
    /// The thin lens's aperture radius (0: a pinhole).
    pub aperture_radius: f32,
    /// The distance of the plane in focus from the lens, along the view axis (not along the
    /// ray).
    pub focus_distance: f32,
    /// Clipping planes along the view axis; perspective rays start at the lens, unclipped by
    /// `near`.
    pub near: f32,
    pub far: f32,
    pub width: u32,
    pub height: u32,
}

impl CameraInfo {
    pub fn of(camera: &Camera) -> Self {
        let frame = &camera.frame;
        let (projection, vfov_degrees, ortho_height) = match camera.projection {
            Projection::Perspective { vfov } => {
                ("perspective", Some(f64::from(vfov).to_degrees()), None)
            }
            Projection::Orthographic { height } => ("orthographic", None, Some(height)),
        };
        let thin = camera.lens.first_order();
        let a = &thin.aperture;
        Self {
            eye: frame.eye.to_array(),
            target: (frame.eye + frame.forward).to_array(),
            up: frame.true_up.to_array(),
            projection,
            vfov_degrees,
            ortho_height,
            lens: match camera.lens {
                Lens::Thin(_) => "thin",
                Lens::Real { .. } => "real",
            },
            aperture: if a.fan().is_empty() && a.image().is_none() && a.shape.aspect == 1.0 {
                "round"
            } else {
                "shaped"
            },
            aperture_radius: thin.aperture_radius,
            focus_distance: thin.focus_distance,
            near: camera.near,
            far: camera.far,
            width: camera.width,
            height: camera.height,
        }
    }
}
