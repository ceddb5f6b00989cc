//! What `lensray lens` prints: a lens's first-order data (object at infinity, d-line indices as
//! given, mm) and real-ray data: chief rays at 5-20 degrees of field and the longitudinal
//! spherical aberration at four heights of the entrance pupil. Signs: + toward the film.

use std::fmt::Write;

use glam::DVec3;
use serde::Serialize;

use super::paraxial::{FirstOrder, Pupil};
use super::prescription::Prescription;
use super::trace::wide::{Elements, LensRay};
use super::trace::Toward;

/// Field angles of the chief-ray table, degrees.
pub const CHIEF_RAY_FIELDS: [f64; 4] = [5.0, 10.0, 15.0, 20.0];
/// Heights of the spherical-aberration rays, fractions of the entrance pupil's radius.
pub const LSA_FRACTIONS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ChiefRay {
    pub field_deg: f64,
    /// Where the ray through the stop's centre meets the paraxial focal plane.
    pub image_height_mm: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Aberration {
    pub pupil_fraction: f64,
    /// Where the ray crosses the axis minus the paraxial focus.
    pub lsa_mm: f64,
}

/// The data `lensray lens --json` writes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LensData {
    pub name: String,
    pub efl_mm: f64,
    pub bfl_mm: f64,
    pub ffl_mm: f64,
    pub front_principal_plane_mm: f64,
    pub rear_principal_plane_mm: f64,
    pub entrance_pupil: Pupil,
    pub exit_pupil: Pupil,
    pub f_number: f64,
    /// Fields whose chief ray a clear aperture blocks are left out.
    pub chief_ray: Vec<ChiefRay>,
    /// Traced without clipping (the aberration of the surfaces' shapes).
    pub lsa: Vec<Aberration>,
}

impl LensData {
    pub fn of(lens: &Prescription) -> Self {
        let first = FirstOrder::of(lens);
        let elements = Elements::new(lens);
        let focus = lens.length() + first.bfl;
        let chief_ray = CHIEF_RAY_FIELDS
            .iter()
            .filter_map(|&field| {
                let ray = chief_ray(lens, &elements, &first, field)?;
                let out = elements.trace(ray, Toward::Film)?;
                let t = (focus - out.origin.z) / out.direction.z;
                Some(ChiefRay {
                    field_deg: field,
                    image_height_mm: out.origin.y + t * out.direction.y,
                })
            })
            .collect();
        let open = unclipped(&elements);
        let lsa = LSA_FRACTIONS
            .iter()
            .filter_map(|&fraction| {
                let height = fraction * 0.5 * first.entrance_pupil.diameter_mm;
                let ray = LensRay {
                    origin: DVec3::new(0.0, height, start_z(lens)),
                    direction: DVec3::Z,
                };
                let out = open.trace(ray, Toward::Film)?;
                let crossing = out.origin.z - out.origin.y * out.direction.z / out.direction.y;
                Some(Aberration {
                    pupil_fraction: fraction,
                    lsa_mm: crossing - focus,
                })
            })
            .collect();
        LensData {
            name: lens.name.clone(),
            efl_mm: first.efl,
            bfl_mm: first.bfl,
            ffl_mm: first.ffl,
            front_principal_plane_mm: first.front_principal_plane,
            rear_principal_plane_mm: first.rear_principal_plane,
            entrance_pupil: first.entrance_pupil,
            exit_pupil: first.exit_pupil,
            f_number: first.f_number,
            chief_ray,
            lsa,
        }
    }

    /// The same data as a table.
    pub fn text(&self) -> String {
        let mut out = String::new();
        let mut row = |name: &str, value: String| {
            let _ = writeln!(out, "{name:<28} {value}");
        };
        row("lens", self.name.clone());
        row("efl_mm", format!("{:.4}", self.efl_mm));
        row("bfl_mm", format!("{:.4}", self.bfl_mm));
        row("ffl_mm", format!("{:.4}", self.ffl_mm));
        row(
            "front_principal_plane_mm",
            format!("{:.4}", self.front_principal_plane_mm),
        );
        row(
            "rear_principal_plane_mm",
            format!("{:.4}", self.rear_principal_plane_mm),
        );
        let pupil = |p: &Pupil| {
            format!(
                "position {:.4} mm, diameter {:.4} mm",
                p.position_mm, p.diameter_mm
            )
        };
        row("entrance_pupil", pupil(&self.entrance_pupil));
        row("exit_pupil", pupil(&self.exit_pupil));
        row("f_number", format!("{:.4}", self.f_number));
        let _ = writeln!(
            out,
            "chief_ray (through the stop's centre, on the paraxial focal plane)"
        );
        let _ = writeln!(out, "  field_deg  image_height_mm");
        for c in &self.chief_ray {
            let _ = writeln!(out, "  {:>9.1}  {:>15.4}", c.field_deg, c.image_height_mm);
        }
        let _ = writeln!(out, "lsa (axis crossing minus the paraxial focus)");
        let _ = writeln!(out, "  pupil_fraction  lsa_mm");
        for a in &self.lsa {
            let _ = writeln!(out, "  {:>14.2}  {:>6.4}", a.pupil_fraction, a.lsa_mm);
        }
        out
    }
}

/// Where object-space rays start: in front of every surface's cap.
fn start_z(lens: &Prescription) -> f64 {
    let widest = lens
        .surfaces()
        .iter()
        .map(|s| s.diameter)
        .fold(0.0, f64::max);
    -2.0 * widest
}

/// The elements with every opening unbounded.
fn unclipped(elements: &Elements) -> Elements {
    let mut open = elements.clone();
    for i in &mut open.interfaces {
        i.aperture_radius = f64::INFINITY;
    }
    open
}

/// The object-space ray at `field` degrees (rising toward the film, imaging above the axis)
/// that crosses the stop's plane on the axis: secant steps on its starting height from the
/// paraxial guess (aimed at the entrance pupil's centre). `None` if a clear aperture before
/// the stop blocks it.
fn chief_ray(
    lens: &Prescription,
    elements: &Elements,
    first: &FirstOrder,
    field: f64,
) -> Option<LensRay> {
    let (sin, cos) = field.to_radians().sin_cos();
    let z0 = start_z(lens);
    let direction = DVec3::new(0.0, sin, cos);
    let stop = lens.stop();
    let open = unclipped(elements);
    // The height at the stop's plane of the ray starting at height y0.
    let at_stop = |y0: f64| -> Option<f64> {
        let mut ray = LensRay {
            origin: DVec3::new(0.0, y0, z0),
            direction,
        };
        for interface in &open.interfaces[..stop] {
            ray = interface.pass(ray, Toward::Film)?;
        }
        let (t, _) = open.interfaces[stop].intersect(ray)?;
        Some(ray.origin.y + t * ray.direction.y)
    };
    let mut a = (z0 - first.entrance_pupil.position_mm) * sin / cos;
    let mut b = a + 1e-3;
    let (mut fa, mut fb) = (at_stop(a)?, at_stop(b)?);
    for _ in 0..50 {
        if fb.abs() < 1e-13 || fb == fa {
            break;
        }
        let next = b - fb * (b - a) / (fb - fa);
        (a, fa) = (b, fb);
        b = next;
        fb = at_stop(b)?;
    }
    let ray = LensRay {
        origin: DVec3::new(0.0, b, z0),
        direction,
    };
    // Clipped before the stop: blocked.
    let mut clipped = ray;
    for interface in &elements.interfaces[..stop] {
        clipped = interface.pass(clipped, Toward::Film)?;
    }
    Some(ray)
}
