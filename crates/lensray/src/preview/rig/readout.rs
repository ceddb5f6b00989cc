//! What the lens panel shows of the rig.

use lensray_core::settings::ProjectionKind;

use super::lens::RigLens;
use super::CameraRig;

/// What a lens panel shows of a real lens.
#[derive(Clone, Debug, PartialEq)]
pub struct RealLensReadout {
    /// As the settings name it (the panel's picker): a built-in name or a file.
    pub prescription: String,
    /// The prescription's own name.
    pub name: String,
    /// The f-numbers it stops down through: its widest to f/22.
    pub f_number_range: (f64, f64),
    /// World units from the entrance pupil.
    pub nearest_focus: f64,
    pub focal_length_mm: f64,
    /// Whether its glasses carry Abbe numbers, and whether dispersion is on.
    pub dispersive_glass: bool,
    pub dispersion: bool,
}

/// What a lens panel shows.
#[derive(Clone, Debug, PartialEq)]
pub struct LensReadout {
    pub projection: ProjectionKind,
    /// Physical units only.
    pub focal_length_mm: Option<f64>,
    /// Physical units only.
    pub f_number: Option<f64>,
    /// Physical units only.
    pub sensor_height_mm: Option<f64>,
    /// World units (with physical units, f / 2N); 0 is a pinhole.
    pub aperture_radius: f64,
    /// Along the view axis, world units.
    pub focus_distance: f64,
    /// Perspective only: the field of view the camera has (the lens's with physical units).
    pub vfov_degrees: Option<f64>,
    /// Orthographic only.
    pub ortho_height: Option<f64>,
    /// Eye to target.
    pub target_distance: f64,
    /// A real lens's limits (its f-number and sensor height are `f_number` and
    /// `sensor_height_mm`).
    pub real: Option<RealLensReadout>,
}

impl CameraRig {
    pub fn readout(&self) -> LensReadout {
        let cam = &self.camera;
        let physical = match cam.lens {
            RigLens::Physical(lens) => Some(lens),
            _ => None,
        };
        let real = match &cam.lens {
            RigLens::Real(real) => Some(real),
            _ => None,
        };
        let perspective = cam.projection == ProjectionKind::Perspective;
        LensReadout {
            projection: cam.projection,
            focal_length_mm: physical.map(|l| l.focal_length_mm),
            f_number: physical.map(|l| l.f_number).or(real.map(|r| r.f_number)),
            sensor_height_mm: physical
                .map(|l| l.sensor_height_mm)
                .or(real.map(|r| r.sensor_height_mm)),
            aperture_radius: cam.aperture_radius(),
            focus_distance: cam.focus_distance,
            vfov_degrees: perspective.then(|| cam.vfov_radians().to_degrees()),
            ortho_height: (!perspective).then_some(cam.ortho_height),
            target_distance: cam.distance(),
            real: real.map(|r| RealLensReadout {
                prescription: r.prescription.clone(),
                name: r.lens.name.clone(),
                f_number_range: r.f_number_range(),
                nearest_focus: self.min_focus_distance(),
                focal_length_mm: r.first_order.efl,
                dispersive_glass: r.lens.is_dispersive(),
                dispersion: r.dispersion,
            }),
        }
    }
}
