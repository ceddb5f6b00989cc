//! Focusing a real lens: moving it along the axis until a subject at the focus distance images
//! on the film. First the thick lens's cardinal points give the film's place (Newton's
//! equation), then tracing refines it to the plane where the real rays from the subject's
//! axial point gather most tightly (least RMS spread at the taking aperture, so spherical
//! aberration's focus shift on stopping down is in it).

use super::RealLensError;
use crate::camera::physical::MM_PER_WORLD_UNIT;
use crate::optics::paraxial::FirstOrder;
use crate::optics::trace::wide::{Elements, LensRay};
use crate::optics::trace::Toward;
use crate::optics::Prescription;
use glam::DVec3;

/// Rings of the entrance pupil the refinement traces (equal areas).
const RINGS: u32 = 32;

/// Lens-space z (mm) of the film that focuses `lens` on a subject `focus_distance` world
/// units in front of its entrance pupil.
pub(super) fn film_z(
    lens: &Prescription,
    first_order: &FirstOrder,
    focus_distance: f64,
) -> Result<f32, RealLensError> {
    let entrance_pupil_z = first_order.entrance_pupil.position_mm;
    let subject_z = entrance_pupil_z - focus_distance * MM_PER_WORLD_UNIT;
    let front_focus_z = first_order.ffl;
    // Newton: x x' = -f^2, with x = subject - F and x' = image - F'.
    let x = subject_z - front_focus_z;
    if !(x < 0.0 && subject_z < 0.0) {
        return Err(RealLensError::CannotFocus {
            lens: lens.name.clone(),
            focus: focus_distance,
            nearest: (entrance_pupil_z - front_focus_z.min(0.0)) / MM_PER_WORLD_UNIT,
        });
    }
    let efl = first_order.efl;
    let thick_lens_z = lens.length() + first_order.bfl - efl * efl / x;
    let refined = least_spread_z(lens, first_order, subject_z, thick_lens_z);
    Ok(refined.unwrap_or(thick_lens_z) as f32)
}

/// The plane near `guess_z` where meridional rays from the axial point at `subject_z`,
/// through equal-area rings of the entrance pupil, have the least mean square height: for
/// rays of height y_i and slope s_i at `guess_z`, z = guess_z - sum(y_i s_i) / sum(s_i^2).
/// `None` when no ray passes.
fn least_spread_z(
    lens: &Prescription,
    first_order: &FirstOrder,
    subject_z: f64,
    guess_z: f64,
) -> Option<f64> {
    let elements = Elements::new(lens);
    let pupil = first_order.entrance_pupil;
    let subject = DVec3::new(0.0, 0.0, subject_z);
    let (mut ys, mut ss) = (0.0, 0.0);
    for ring in 0..RINGS {
        let height = 0.5 * pupil.diameter_mm * ((ring as f64 + 0.5) / RINGS as f64).sqrt();
        let aim = DVec3::new(0.0, height, pupil.position_mm);
        let ray = LensRay {
            origin: subject,
            direction: (aim - subject).normalize(),
        };
        let Some(out) = elements.trace(ray, Toward::Film) else {
            continue;
        };
        let slope = out.direction.y / out.direction.z;
        let y = out.origin.y + (guess_z - out.origin.z) * slope;
        ys += y * slope;
        ss += slope * slope;
    }
    (ss > 0.0).then(|| guess_z - ys / ss)
}
