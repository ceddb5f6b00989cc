//! The automatic framing of a scene without a camera position: where the eye stands and what it
//! fits into the view.
//!
//! - A model (any other shape): a three-quarter view from above its front (glTF's convention: a
//!   model faces +Z), at the distance that fits its bounding sphere into the lens's field of
//!   view. The sphere does not depend on the direction, so turning the view keeps it framed.
//! - A board (test charts, signs, walls of samples: its bounding box's thinnest extent lies
//!   across the up axis and is under `BOARD_THINNESS` of the next): face-on from a little
//!   above, at the distance that fits its box's corners into the frame. A three-quarter view
//!   shows a board's face obliquely, and its sphere, as wide as its long side, leaves the frame
//!   mostly empty (a 8.6 x 2.4 x 1.3 row of samples filled 15 % of it).
//!
//! Both aim at the bounding box's centre.

use glam::{DVec3, Vec3};

use crate::camera::physical::MM_PER_WORLD_UNIT;
use crate::optics::paraxial::FirstOrder;
use crate::optics::Prescription;
use crate::scene::{Bounds, Scene};
use crate::settings::{CameraSettings, ProjectionKind, Settings};

use super::shot::{point, SettingsError};
use super::shot::{DEFAULT_HEIGHT, DEFAULT_SENSOR_HEIGHT_MM, DEFAULT_VFOV_DEGREES, DEFAULT_WIDTH};

/// The automatic framing's view of a model: turned this far around the vertical axis from the
/// front toward +X ...
pub const FRAMING_AZIMUTH_DEGREES: f64 = 35.0;
/// ... and this far above the horizon, a three-quarter view from above.
pub const FRAMING_ELEVATION_DEGREES: f64 = 25.0;
/// A board is seen face-on from this far above its horizontal normal: enough to read it as an
/// object standing in space, little enough to keep its face square to the view.
pub const BOARD_ELEVATION_DEGREES: f64 = 10.0;
/// A bounding box is a board's when its thinnest extent, across the up axis, is under this
/// fraction of the next thinnest (Khronos' flat test models measure 0.03 (VertexColorTest) to
/// 0.54 (AlphaBlendModeTest's row of samples); LightsPunctualLamp, a model, 0.64).
pub const BOARD_THINNESS: f32 = 0.6;
/// How much larger than its subject the automatic framing's view is (the subject reaches
/// 1 / 1.05 of the way to the frame's nearer edges, a thin margin).
const FRAMING_MARGIN: f64 = 1.05;

/// Where the camera stands and looks, before the checks of `CameraParams::build`.
pub(super) struct View {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
}

/// What the automatic framing fits into the view.
enum Subject {
    /// A sphere of this radius about the target.
    Sphere(f64),
    /// Points relative to the target, in the view's frame: x across, y up the image, z toward
    /// the eye.
    Points(Vec<DVec3>),
}

impl Subject {
    /// How far inside the view the subject lies, seen from `distance` with half-angle tangents
    /// `tan_v` (vertical) and `tan_h` (horizontal): negative where part of it is outside.
    fn excess(&self, distance: f64, tan_v: f64, tan_h: f64) -> f64 {
        match self {
            Self::Sphere(radius) => {
                distance * tan_v.min(tan_h).atan().sin() - FRAMING_MARGIN * radius
            }
            Self::Points(points) => points
                .iter()
                .map(|p| {
                    let depth = distance - p.z;
                    (depth * tan_v - FRAMING_MARGIN * p.y.abs())
                        .min(depth * tan_h - FRAMING_MARGIN * p.x.abs())
                })
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// A length of the subject's size, the bisection's first step.
    fn size(&self) -> f64 {
        match self {
            Self::Sphere(radius) => *radius,
            Self::Points(points) => points.iter().map(|p| p.length()).fold(0.0, f64::max),
        }
    }
}

/// The vertical field of view the default framing assumes: the real lens's, focused at
/// infinity (the field narrows a little nearer), or the settings' own.
pub(super) fn framing_vfov_degrees(c: &CameraSettings, real_lens: Option<&Prescription>) -> f64 {
    match real_lens {
        Some(lens) => {
            let efl = FirstOrder::of(lens).efl;
            let height = c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM);
            (2.0 * (0.5 * height / efl).atan()).to_degrees()
        }
        None => c.vfov_degrees.unwrap_or(DEFAULT_VFOV_DEGREES),
    }
}

/// Target (default: the centre of the scene's bounds), up (default: +y) and eye (default: the
/// automatic framing's).
pub(super) fn view(
    settings: &Settings,
    scene: &Scene,
    bounds: &Bounds,
    real_lens: Option<&Prescription>,
) -> Result<View, SettingsError> {
    let c = &settings.camera;
    let target = c
        .target
        .map(|t| point("target", t))
        .transpose()?
        .unwrap_or(bounds.center());
    let up = c.up.map(|u| point("up", u)).transpose()?.unwrap_or(Vec3::Y);
    let eye = match c.eye {
        Some(e) => point("eye", e)?,
        None => {
            let (direction, subject) = match board_normal(scene, bounds, up) {
                Some(normal) => {
                    let direction = elevated(normal, up, BOARD_ELEVATION_DEGREES);
                    (direction, board_subject(bounds, target, direction, up))
                }
                None => {
                    let (_, radius) = scene.bounding_sphere().ok_or(SettingsError::EmptyScene)?;
                    (framing_direction(up), Subject::Sphere(f64::from(radius)))
                }
            };
            let distance = framing_distance(settings, real_lens, &subject);
            target + (direction * distance).as_vec3()
        }
    };
    Ok(View { eye, target, up })
}

/// The horizontal normal of a board's face, or `None` where the bounds are not a board's: the
/// box axis that is the board's thin one, toward the side its triangles face (their
/// area-weighted normals' sum; +Z or +X where they face both ways alike, as a closed box's do).
pub(super) fn board_normal(scene: &Scene, bounds: &Bounds, up: Vec3) -> Option<DVec3> {
    let extent = bounds.diagonal();
    let up = up.normalize_or_zero();
    let mut axes = [
        (Vec3::Z, extent.z),
        (Vec3::X, extent.x),
        (Vec3::Y, extent.y),
    ];
    axes.sort_by(|a, b| a.1.total_cmp(&b.1));
    let [(thin, thickness), (_, next), (_, widest)] = axes;
    let across_up = thin.dot(up).abs() < 0.5;
    if !(across_up && thickness < BOARD_THINNESS * next) {
        return None;
    }
    let thin = thin.as_dvec3();
    // Twice the area each triangle shows along the axis, signed by the side it faces.
    let facing: f64 = scene
        .meshes
        .iter()
        .flat_map(|m| {
            m.triangles.iter().map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize].as_dvec3());
                (b - a).cross(c - a).dot(thin)
            })
        })
        .sum();
    // Alike both ways within a thousandth of the board's face: glTF's front.
    let face = f64::from(next) * f64::from(widest);
    Some(if facing < -2e-3 * face { -thin } else { thin })
}

/// `front` turned `degrees` up toward `up` (both unit, `front` across `up`).
fn elevated(front: DVec3, up: Vec3, degrees: f64) -> DVec3 {
    let up = up.as_dvec3().try_normalize().unwrap_or(DVec3::Y);
    let front = (front - up * up.dot(front)).normalize();
    let elevation = degrees.to_radians();
    front * elevation.cos() + up * elevation.sin()
}

/// The board's box corners in the frame of a view along `-direction` aimed at `target`.
fn board_subject(bounds: &Bounds, target: Vec3, direction: DVec3, up: Vec3) -> Subject {
    let side = up.as_dvec3().cross(direction).normalize();
    let image_up = direction.cross(side);
    let points = bounds.corners().map(|c| {
        let p = (c - target).as_dvec3();
        DVec3::new(p.dot(side), p.dot(image_up), p.dot(direction))
    });
    Subject::Points(points.to_vec())
}

/// The automatic framing's direction from the target to the eye for a model:
/// `FRAMING_AZIMUTH_DEGREES` around `up` from the front (+Z, or +X where `up` is along Z)
/// toward the side, and `FRAMING_ELEVATION_DEGREES` above the plane normal to `up`.
fn framing_direction(up: Vec3) -> DVec3 {
    let up = up.as_dvec3().try_normalize().unwrap_or(DVec3::Y);
    let front = (DVec3::Z - up * up.z)
        .try_normalize()
        .unwrap_or_else(|| (DVec3::X - up * up.x).normalize());
    let side = up.cross(front);
    let (azimuth, elevation) = (
        FRAMING_AZIMUTH_DEGREES.to_radians(),
        FRAMING_ELEVATION_DEGREES.to_radians(),
    );
    (front * azimuth.cos() + side * azimuth.sin()) * elevation.cos() + up * elevation.sin()
}

/// How far from its target the automatic framing stands: the nearest distance d where the
/// subject fills the view but for `FRAMING_MARGIN` (for a sphere of radius r,
/// d sin(half(d)) = margin x r). A lens with a focal length f (a thin lens in physical units,
/// or a real lens's effective focal length) focused at d throws the image to
/// s_i = f d / (d - f), so its field narrows as d nears f: tan(half) = (h / 2) / s_i for the
/// sensor height h. The excess grows with d, so bisection finds it; it is always beyond f.
fn framing_distance(
    settings: &Settings,
    real_lens: Option<&Prescription>,
    subject: &Subject,
) -> f64 {
    let c = &settings.camera;
    let width = f64::from(settings.image.width.unwrap_or(DEFAULT_WIDTH).max(1));
    let height = f64::from(settings.image.height.unwrap_or(DEFAULT_HEIGHT).max(1));
    let aspect = width / height;
    let perspective = c.projection != Some(ProjectionKind::Orthographic);
    let focal_length_mm = match real_lens {
        Some(lens) => Some(FirstOrder::of(lens).efl),
        None if perspective && c.aperture_radius.is_none() => c.focal_length_mm,
        None => None,
    };
    let sensor_mm = c.sensor_height_mm.unwrap_or(DEFAULT_SENSOR_HEIGHT_MM);
    let vfov = framing_vfov_degrees(c, real_lens)
        .clamp(1.0, 179.0)
        .to_radians();
    let f = focal_length_mm.map_or(0.0, |f| f / MM_PER_WORLD_UNIT);
    let tan_half = |d: f64| match focal_length_mm {
        Some(f_mm) if f_mm > 0.0 => 0.5 * sensor_mm / f_mm * ((d - f) / d).max(0.0),
        _ => (0.5 * vfov).tan(),
    };
    let excess = |d: f64| subject.excess(d, tan_half(d), tan_half(d) * aspect);
    let (mut near, mut far) = (f, f + subject.size().max(1e-9));
    for _ in 0..200 {
        if excess(far) >= 0.0 {
            break;
        }
        (near, far) = (far, far * 2.0);
    }
    for _ in 0..100 {
        let mid = 0.5 * (near + far);
        if excess(mid) < 0.0 {
            near = mid;
        } else {
            far = mid;
        }
    }
    far
}
