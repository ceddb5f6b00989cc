//! What `lensray lens` prints: a lens's first-order data (object at infinity, d-line indices as
//! given, mm) and real-ray data: chief rays at 5-20 degrees of field and the longitudinal
//! spherical aberration at four heights of the entrance pupil; then its colour: each element's
//! glass, the efl and bfl at the F, d and C lines, the axial colour (paraxial rear focus at F
//! minus at C) and the lateral colour (the F chief ray's height minus the C one's, both on the
//! d-line paraxial focal plane, each found at its own wavelength). Signs: + toward the film.

use std::fmt::Write;

use glam::DVec3;
use serde::Serialize;

use super::glass::{LAMBDA_C_NM, LAMBDA_D_NM, LAMBDA_F_NM};
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

/// A glass element: the medium between two surfaces.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ElementGlass {
    /// Its front and rear surfaces (1-based rows).
    pub surfaces: [usize; 2],
    pub n_d: f64,
    /// `None`: no Abbe number given (non-dispersive).
    pub v_d: Option<f64>,
}

/// A figure at the F, d and C lines.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[expect(non_snake_case, reason = "the Fraunhofer lines' names")]
pub struct ByLine {
    pub F: f64,
    pub d: f64,
    pub C: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LateralColour {
    pub field_deg: f64,
    /// The F-line chief ray's height minus the C-line one's on the d-line paraxial focal plane.
    pub lateral_color_mm: f64,
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
    pub glasses: Vec<ElementGlass>,
    pub efl_lines_mm: ByLine,
    pub bfl_lines_mm: ByLine,
    /// The paraxial rear focal point at F minus that at C (object at infinity).
    pub axial_color_mm: f64,
    /// Fields whose chief ray passes at both lines.
    pub lateral_color: Vec<LateralColour>,
}

impl LensData {
    pub fn of(lens: &Prescription) -> Self {
        let first = FirstOrder::of(lens);
        let elements = Elements::new(lens);
        let focus = lens.length() + first.bfl;
        let chief_ray = CHIEF_RAY_FIELDS
            .iter()
            .filter_map(|&field| {
                Some(ChiefRay {
                    field_deg: field,
                    image_height_mm: chief_ray_height(lens, field, focus)?,
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
            glasses: glasses(lens),
            efl_lines_mm: by_line(|l| FirstOrder::of(&lens.at_wavelength(l)).efl),
            bfl_lines_mm: by_line(|l| FirstOrder::of(&lens.at_wavelength(l)).bfl),
            axial_color_mm: 0.0,
            lateral_color: Vec::new(),
        }
        .with_colour(lens, focus)
    }

    /// The axial and lateral colour (see the module's documentation).
    fn with_colour(mut self, lens: &Prescription, focus: f64) -> Self {
        self.axial_color_mm = self.bfl_lines_mm.F - self.bfl_lines_mm.C;
        let (f_lens, c_lens) = (
            lens.at_wavelength(LAMBDA_F_NM),
            lens.at_wavelength(LAMBDA_C_NM),
        );
        self.lateral_color = CHIEF_RAY_FIELDS
            .iter()
            .filter_map(|&field| {
                let f = chief_ray_height(&f_lens, field, focus)?;
                let c = chief_ray_height(&c_lens, field, focus)?;
                Some(LateralColour {
                    field_deg: field,
                    lateral_color_mm: f - c,
                })
            })
            .collect();
        self
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
        self.colour_text(&mut out);
        out
    }

    fn colour_text(&self, out: &mut String) {
        let _ = writeln!(out, "glasses (element: surfaces, n_d, V_d)");
        for g in &self.glasses {
            let v = g.v_d.map_or("-".into(), |v| format!("{v:.2}"));
            let [front, rear] = g.surfaces;
            let _ = writeln!(out, "  {front:>3}-{rear:<3} {:.5}  {v}", g.n_d);
        }
        let lines = |b: &ByLine| format!("F {:.4}, d {:.4}, C {:.4}", b.F, b.d, b.C);
        let _ = writeln!(out, "{:<28} {}", "efl_lines_mm", lines(&self.efl_lines_mm));
        let _ = writeln!(out, "{:<28} {}", "bfl_lines_mm", lines(&self.bfl_lines_mm));
        let _ = writeln!(out, "{:<28} {:.5}", "axial_color_mm", self.axial_color_mm);
        let _ = writeln!(
            out,
            "lateral_color (F chief ray minus C, on the d-line focal plane)"
        );
        let _ = writeln!(out, "  field_deg  lateral_color_mm");
        for c in &self.lateral_color {
            let _ = writeln!(out, "  {:>9.1}  {:>16.5}", c.field_deg, c.lateral_color_mm);
        }
    }
}

/// `figure` at the F, d and C lines.
fn by_line(figure: impl Fn(f64) -> f64) -> ByLine {
    ByLine {
        F: figure(LAMBDA_F_NM),
        d: figure(LAMBDA_D_NM),
        C: figure(LAMBDA_C_NM),
    }
}

/// Each glass element of `lens`, front to rear.
fn glasses(lens: &Prescription) -> Vec<ElementGlass> {
    let s = lens.surfaces();
    (0..s.len())
        .filter(|&i| s[i].index != 1.0)
        .map(|i| ElementGlass {
            surfaces: [i + 1, i + 2],
            n_d: s[i].index,
            v_d: s[i].abbe,
        })
        .collect()
}

/// The height at which the chief ray of `field` degrees (traced through `lens` as its indices
/// are) meets the plane z = `focus`; `None` if a clear aperture blocks it.
fn chief_ray_height(lens: &Prescription, field: f64, focus: f64) -> Option<f64> {
    let first = FirstOrder::of(lens);
    let elements = Elements::new(lens);
    let ray = chief_ray(lens, &elements, &first, field)?;
    let out = elements.trace(ray, Toward::Film)?;
    let t = (focus - out.origin.z) / out.direction.z;
    Some(out.origin.y + t * out.direction.y)
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
