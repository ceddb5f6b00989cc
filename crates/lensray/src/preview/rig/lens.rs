//! The rig's lenses: a thin lens in world or photographic units, or a real lens with the
//! first-order data that bounds its controls; and the lens picker's choices.

use std::sync::Arc;

use lensray_core::camera::physical::{PhysicalLens, MM_PER_WORLD_UNIT};
use lensray_core::optics::paraxial::FirstOrder;
use lensray_core::optics::Prescription;

use super::{REAL_F_NUMBER_MAX, REAL_MAX_MAGNIFICATION};

/// The lens, in the units the user chose.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum RigLens {
    /// World units; 0 is a pinhole.
    Aperture { radius: f64 },
    /// Photographic units; the field of view follows the lens (see `camera::physical`).
    Physical(PhysicalLens),
    /// A lens prescription traced surface by surface (`camera::real_lens`).
    Real(RealRigLens),
}

/// A real lens as the rig holds it: what the settings name, and its first-order data for the
/// limits (widest f-number, nearest focus) and the framing.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct RealRigLens {
    /// As the settings give it: a built-in name or a prescription file.
    pub(super) prescription: String,
    pub(super) lens: Arc<Prescription>,
    pub(super) first_order: FirstOrder,
    pub(super) f_number: f64,
    pub(super) sensor_height_mm: f64,
    /// Camera rays carry wavelengths through the glass (`--dispersion`).
    pub(super) dispersion: bool,
}

impl RealRigLens {
    pub(super) fn new(
        prescription: String,
        lens: Prescription,
        f_number: Option<f64>,
        sensor: f64,
    ) -> Self {
        let first_order = FirstOrder::of(&lens);
        RealRigLens {
            prescription,
            lens: Arc::new(lens),
            f_number: f_number.unwrap_or(first_order.f_number),
            first_order,
            sensor_height_mm: sensor,
            dispersion: true,
        }
    }

    /// The f-numbers the steps and the panel allow: the lens's widest to f/22 (a value given
    /// outside stays until changed: `RealLens` accepts a marked f-number a little wider).
    pub(super) fn f_number_range(&self) -> (f64, f64) {
        let widest = self.first_order.f_number;
        (widest, REAL_F_NUMBER_MAX.max(widest))
    }

    /// Nearest focus distance from the entrance pupil, world units (see
    /// `REAL_MAX_MAGNIFICATION`; never at or inside the front focal point, nor behind the
    /// first vertex).
    pub(super) fn nearest_focus(&self) -> f64 {
        let fo = &self.first_order;
        let entrance_pupil_z = fo.entrance_pupil.position_mm;
        // Newton: magnification m = -f / x, x the subject's distance before the front focal
        // point (lens-space z, negative toward the scene).
        let subject_z = fo.ffl - fo.efl.abs() / REAL_MAX_MAGNIFICATION;
        let limit = 1.001 * (entrance_pupil_z - fo.ffl.min(0.0));
        (entrance_pupil_z - subject_z).max(limit) / MM_PER_WORLD_UNIT
    }

    /// The vertical field of view focused at `focus_distance`, to first order (the film
    /// where Newton's equation puts it; `RealLens::pinhole_vfov` refines the film by tracing).
    pub(super) fn vfov(&self, focus_distance: f64) -> f64 {
        let fo = &self.first_order;
        let subject_z = fo.entrance_pupil.position_mm - focus_distance * MM_PER_WORLD_UNIT;
        let x = (subject_z - fo.ffl).min(-1e-9);
        let film_z = self.lens.length() + fo.bfl - fo.efl * fo.efl / x;
        let exit_pupil_z = self.lens.length() + fo.exit_pupil.position_mm;
        let slope = 0.5 * self.sensor_height_mm / (film_z - exit_pupil_z)
            * fo.exit_pupil.diameter_mm
            / fo.entrance_pupil.diameter_mm;
        2.0 * slope.abs().atan()
    }

    /// Radius of the entrance pupil at the f-number, world units.
    pub(super) fn entrance_pupil_radius(&self) -> f64 {
        let widest = self.first_order.f_number;
        0.5 * self.first_order.entrance_pupil.diameter_mm * widest
            / self.f_number.max(widest)
            / MM_PER_WORLD_UNIT
    }
}

/// `n` clamped to `range`, except that a value already outside it (given by the user) may
/// stay where it is or move toward the range.
pub(super) fn clamp_toward(n: f64, range: (f64, f64), current: f64) -> f64 {
    n.clamp(range.0.min(current), range.1.max(current))
}

/// What the lens picker offers: the thin lens or a real one by its name in the settings.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LensChoice {
    Thin,
    Real(String),
}

impl LensChoice {
    pub fn label(&self) -> String {
        match self {
            LensChoice::Thin => "thin lens".to_owned(),
            LensChoice::Real(name) => {
                if lensray_core::optics::builtin::lens(name).is_some() {
                    name.clone()
                } else {
                    // A file: its name, the folder on hover.
                    let path = std::path::Path::new(name);
                    path.file_name()
                        .map_or(name.clone(), |f| f.to_string_lossy().into_owned())
                }
            }
        }
    }
}
