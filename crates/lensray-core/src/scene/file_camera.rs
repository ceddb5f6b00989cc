//! A camera a scene file carries (glTF's `cameras`), and how it becomes lensray's camera
//! settings: the same eye, view direction, up, field of view (or orthographic extent), clip
//! planes and aspect ratio, so that the course's matrices reproduce the file's projection. Lens
//! settings (aperture, focal length, a real lens) apply on top.

use glam::DVec3;

use super::camera_animation::CameraAnimation;
use super::Scene;
use crate::settings::{ProjectionKind, Settings};

/// A camera of a scene file, in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct FileCamera {
    pub name: String,
    pub eye: DVec3,
    /// The view direction (glTF: the node's -Z axis), unit length.
    pub forward: DVec3,
    /// The node's +Y axis, unit length.
    pub up: DVec3,
    pub projection: FileProjection,
    /// The file's animation that moves this camera, if one does (its node's pose above is the
    /// node at rest).
    pub animation: Option<CameraAnimation>,
}

/// The projection of a [`FileCamera`], as glTF gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FileProjection {
    /// `yfov` in radians; without `aspect_ratio` the image's own applies; without `zfar` the far
    /// plane is infinite.
    Perspective {
        yfov: f64,
        aspect_ratio: Option<f64>,
        znear: f64,
        zfar: Option<f64>,
    },
    /// Half the view's width and height.
    Orthographic {
        xmag: f64,
        ymag: f64,
        znear: f64,
        zfar: f64,
    },
}

impl FileCamera {
    /// Sets `settings`' camera to this one, and the image size to its aspect ratio where the
    /// settings give no size. The target lies along the view direction at the depth of the
    /// scene's centre, so the default focus falls there. A perspective camera without `zfar`
    /// gets its far plane just beyond the scene (lensray's default), which draws what an
    /// infinite one does.
    pub fn apply(&self, settings: &mut Settings, scene: &Scene) {
        let centre_depth = scene.bounds().map_or(1.0, |b| {
            (b.center().as_dvec3() - self.eye).dot(self.forward)
        });
        let (znear, aspect) = match self.projection {
            FileProjection::Perspective {
                znear,
                aspect_ratio,
                ..
            } => (znear, aspect_ratio),
            FileProjection::Orthographic {
                znear, xmag, ymag, ..
            } => (znear, Some(xmag / ymag)),
        };
        let target_depth = centre_depth.max(2.0 * znear).max(1e-6);
        let c = &mut settings.camera;
        c.eye = Some(self.eye.to_array());
        c.target = Some((self.eye + self.forward * target_depth).to_array());
        c.up = Some(self.up.to_array());
        c.near = Some(znear);
        match self.projection {
            FileProjection::Perspective { yfov, zfar, .. } => {
                c.projection = Some(ProjectionKind::Perspective);
                c.vfov_degrees = Some(yfov.to_degrees());
                c.far = zfar;
            }
            FileProjection::Orthographic { ymag, zfar, .. } => {
                c.projection = Some(ProjectionKind::Orthographic);
                c.ortho_height = Some(2.0 * ymag);
                c.far = Some(zfar);
            }
        }
        let image = &mut settings.image;
        if let (Some(aspect), None, None) = (aspect, image.width, image.height) {
            let height = crate::settings::DEFAULT_HEIGHT;
            image.height = Some(height);
            image.width = Some(((f64::from(height) * aspect).round() as u32).max(1));
        }
    }
}

/// The camera `choice` names among `cameras`: its name, or its index (from 0).
pub fn pick_camera<'a>(cameras: &'a [FileCamera], choice: &str) -> Result<&'a FileCamera, String> {
    let by_name = cameras.iter().find(|c| c.name == choice);
    let by_index = || choice.parse::<usize>().ok().and_then(|i| cameras.get(i));
    by_name.or_else(by_index).ok_or_else(|| {
        if cameras.is_empty() {
            format!("--camera {choice}: the scene has no cameras")
        } else {
            let names: Vec<String> = cameras
                .iter()
                .enumerate()
                .map(|(i, c)| format!("{i}: {}", c.name))
                .collect();
            format!(
                "--camera {choice}: no camera of that name or index; the scene has {}",
                names.join(", ")
            )
        }
    })
}
