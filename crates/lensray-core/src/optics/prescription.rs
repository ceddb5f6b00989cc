//! A lens prescription: the table of a lens's surfaces, scene side first, in the layout of
//! pbrt's lens files. One surface per row:
//!
//! | column | meaning |
//! |---|---|
//! | 1 | curvature radius, mm: + when the centre of curvature lies toward the film; 0 marks the aperture stop (a flat opening) |
//! | 2 | thickness to the next surface along the axis, mm (the last row's is ignored: the film distance comes from focusing) |
//! | 3 | refractive index (d line) of the medium after the surface, toward the film; 0 or 1: air |
//! | 4 | clear-aperture diameter, mm (the stop's: its full opening) |
//! | 5 | optional: the Abbe number V_d of that medium (`glass.rs`: its index at other wavelengths) |
//! | then | optional keyword fields `k=`, `a2=` ... `a16=`: an even asphere (`asphere.rs`) |
//!
//! `#` starts a comment; blank lines are skipped. A row's problem is reported with its line.

use std::path::Path;

use super::asphere::Asphere;
use super::glass::Glass;

/// One surface of a prescription.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// mm; 0: the aperture stop.
    pub radius: f64,
    /// mm, to the next surface.
    pub thickness: f64,
    /// Index of the medium after the surface (1 for air).
    pub index: f64,
    /// Clear-aperture diameter, mm.
    pub diameter: f64,
    /// Abbe number of the medium after the surface, when given.
    pub abbe: Option<f64>,
    /// The surface's aspheric terms; `None`: a sphere (or the flat stop).
    pub asphere: Option<Asphere>,
}

impl Surface {
    pub fn is_stop(&self) -> bool {
        self.radius == 0.0
    }

    /// The medium after the surface.
    pub fn glass(&self) -> Glass {
        Glass {
            n_d: self.index,
            abbe: self.abbe,
        }
    }

    /// The curvature the paraxial (first-order) data use: the vertex's, plus twice an
    /// asphere's r^2 term (the sag's second-order part is (c / 2 + a2) r^2).
    pub fn paraxial_curvature(&self) -> f64 {
        if self.radius == 0.0 {
            return 0.0;
        }
        1.0 / self.radius + 2.0 * self.asphere.map_or(0.0, |a| a.coefficients[0])
    }
}

/// A lens: its surfaces, scene side first, checked (see `Prescription::new`).
#[derive(Clone, Debug, PartialEq)]
pub struct Prescription {
    /// What it is called: a built-in name or the file's.
    pub name: String,
    /// The first comment line of its file (its source), if any.
    pub description: Option<String>,
    surfaces: Vec<Surface>,
    stop: usize,
}

/// Why a prescription cannot be a lens.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PrescriptionError {
    #[error("line {line}: {problem}")]
    Row { line: usize, problem: String },
    #[error("the lens has no surfaces")]
    Empty,
    #[error("the lens has no aperture stop (a row of radius 0)")]
    NoStop,
    #[error("the lens has two aperture stops (rows {first} and {second} have radius 0)")]
    TwoStops { first: usize, second: usize },
    #[error(
        "surface {surface}: thickness {thickness} mm before glass (index {index}) must be positive"
    )]
    Thickness {
        surface: usize,
        thickness: f64,
        index: f64,
    },
    #[error("surface {surface}: clear-aperture diameter must be positive, got {diameter}")]
    Diameter { surface: usize, diameter: f64 },
    #[error("surface {surface}: the radius {radius} mm is smaller than the clear-aperture radius {half} mm")]
    RadiusBelowAperture {
        surface: usize,
        radius: f64,
        half: f64,
    },
    #[error("surface {surface}: the Abbe number must be positive, got {abbe}")]
    Abbe { surface: usize, abbe: f64 },
    #[error("surface {0}: an asphere needs a base curvature (a non-zero radius; radius 0 marks the stop)")]
    AsphereWithoutCurvature(usize),
    #[error("surface {surface}: the asphere's sag is undefined beyond {limit} mm from the axis, inside its clear-aperture radius {half} mm (1 - (1 + k) c^2 r^2 < 0)")]
    SagUndefined {
        surface: usize,
        limit: f64,
        half: f64,
    },
    #[error("surface {surface}: Newton's iteration on the asphere's sag does not converge for the axial ray at height {height:.4} mm")]
    NewtonFails { surface: usize, height: f64 },
    #[error("the stop (surface {0}) must be in air (index 1 on both sides)")]
    StopInGlass(usize),
    #[error("the last surface must leave the lens into air (index 1), got {0}")]
    EndsInGlass(f64),
}

/// A surface's own checks: a positive Abbe number; a sphere larger than its clear aperture;
/// an asphere with a base curvature and a sag defined across its clear aperture.
fn check_shape(surface: usize, s: &Surface) -> Result<(), PrescriptionError> {
    if let Some(abbe) = s.abbe {
        if abbe.is_nan() || abbe <= 0.0 {
            return Err(PrescriptionError::Abbe { surface, abbe });
        }
    }
    let half = 0.5 * s.diameter;
    match s.asphere {
        Some(_) if s.is_stop() => Err(PrescriptionError::AsphereWithoutCurvature(surface)),
        Some(asphere) => {
            let limit = asphere.defined_radius(1.0 / s.radius);
            if limit < half {
                return Err(PrescriptionError::SagUndefined {
                    surface,
                    limit,
                    half,
                });
            }
            Ok(())
        }
        None if !s.is_stop() && s.radius.abs() < half => {
            Err(PrescriptionError::RadiusBelowAperture {
                surface,
                radius: s.radius,
                half,
            })
        }
        None => Ok(()),
    }
}

impl Prescription {
    /// Parses prescription text (see the module doc); `name` names the lens.
    pub fn parse(name: &str, text: &str) -> Result<Self, PrescriptionError> {
        let mut surfaces = Vec::new();
        let mut description = None;
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let (content, comment) = match raw.split_once('#') {
                Some((before, after)) => (before, Some(after.trim())),
                None => (raw, None),
            };
            if description.is_none() && surfaces.is_empty() && content.trim().is_empty() {
                description = comment.filter(|c| !c.is_empty()).map(str::to_owned);
            }
            let all: Vec<&str> = content.split_whitespace().collect();
            if all.is_empty() {
                continue;
            }
            let row = |problem: String| PrescriptionError::Row { line, problem };
            let numbers_end = all
                .iter()
                .position(|f| f.contains('='))
                .unwrap_or(all.len());
            let (fields, keywords) = all.split_at(numbers_end);
            let asphere = if keywords.is_empty() {
                None
            } else {
                let mut asphere = Asphere::default();
                for field in keywords {
                    asphere.read_field(field).map_err(row)?;
                }
                Some(asphere)
            };
            if !(4..=5).contains(&fields.len()) {
                return Err(row(format!(
                    "expected 4 numbers (radius, thickness, index, diameter) and an optional Abbe number, got {}",
                    fields.len()
                )));
            }
            let mut numbers = [0.0; 5];
            for (k, field) in fields.iter().enumerate() {
                let value: f64 = field
                    .parse()
                    .map_err(|_| row(format!("'{field}' is not a number")))?;
                if !value.is_finite() {
                    return Err(row(format!("'{field}' is not a finite number")));
                }
                numbers[k] = value;
            }
            let index = if numbers[2] == 0.0 { 1.0 } else { numbers[2] };
            if index < 1.0 {
                return Err(row(format!("refractive index {index} is below 1")));
            }
            surfaces.push(Surface {
                radius: numbers[0],
                thickness: numbers[1],
                index,
                diameter: numbers[3],
                abbe: (fields.len() == 5).then_some(numbers[4]),
                asphere,
            });
        }
        Self::new(name, description, surfaces)
    }

    /// Reads a prescription file; the lens is named after the file's stem.
    pub fn read(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let name = path
            .file_stem()
            .map_or_else(|| "lens".into(), |s| s.to_string_lossy().into_owned());
        Self::parse(&name, &text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// A lens of `surfaces`, checked: exactly one stop, in air; positive thicknesses before
    /// glass (and none negative); positive clear apertures within each sphere; air after
    /// the last surface.
    pub fn new(
        name: &str,
        description: Option<String>,
        surfaces: Vec<Surface>,
    ) -> Result<Self, PrescriptionError> {
        if surfaces.is_empty() {
            return Err(PrescriptionError::Empty);
        }
        let stops: Vec<usize> = (0..surfaces.len())
            .filter(|&i| surfaces[i].is_stop())
            .collect();
        let stop = match stops[..] {
            [] => return Err(PrescriptionError::NoStop),
            [stop] => stop,
            [first, second, ..] => {
                return Err(PrescriptionError::TwoStops {
                    first: first + 1,
                    second: second + 1,
                })
            }
        };
        let last = surfaces.len() - 1;
        for (i, s) in surfaces.iter().enumerate() {
            let surface = i + 1;
            if s.diameter.is_nan() || s.diameter <= 0.0 {
                return Err(PrescriptionError::Diameter {
                    surface,
                    diameter: s.diameter,
                });
            }
            let glass_after = s.index != 1.0;
            if i < last && (s.thickness < 0.0 || glass_after && s.thickness <= 0.0) {
                return Err(PrescriptionError::Thickness {
                    surface,
                    thickness: s.thickness,
                    index: s.index,
                });
            }
            check_shape(surface, s)?;
        }
        let before = if stop == 0 {
            1.0
        } else {
            surfaces[stop - 1].index
        };
        if surfaces[stop].index != 1.0 || before != 1.0 {
            return Err(PrescriptionError::StopInGlass(stop + 1));
        }
        if surfaces[last].index != 1.0 {
            return Err(PrescriptionError::EndsInGlass(surfaces[last].index));
        }
        let lens = Prescription {
            name: name.into(),
            description,
            surfaces,
            stop,
        };
        lens.check_newton_on_axis()?;
        Ok(lens)
    }

    /// Every asphere's Newton iteration converges for the rays parallel to the axis that
    /// reach it (heights across the first surface's clear aperture).
    fn check_newton_on_axis(&self) -> Result<(), PrescriptionError> {
        use super::trace::{wide, Toward};
        if self.surfaces.iter().all(|s| s.asphere.is_none()) {
            return Ok(());
        }
        let elements = wide::Elements::new(self);
        const HEIGHTS: u32 = 64;
        let half = 0.5 * self.surfaces[0].diameter;
        for j in 0..=HEIGHTS {
            let height = half * f64::from(j) / f64::from(HEIGHTS);
            let mut ray = wide::LensRay {
                origin: glam::DVec3::new(0.0, height, -1.0 - half),
                direction: glam::DVec3::Z,
            };
            for (i, interface) in elements.interfaces.iter().enumerate() {
                if self.surfaces[i].asphere.is_some() && interface.newton(ray).is_none() {
                    return Err(PrescriptionError::NewtonFails {
                        surface: i + 1,
                        height,
                    });
                }
                match interface.pass(ray, Toward::Film) {
                    Some(next) => ray = next,
                    None => break,
                }
            }
        }
        Ok(())
    }

    pub fn surfaces(&self) -> &[Surface] {
        &self.surfaces
    }

    /// The aperture stop's row (0-based).
    pub fn stop(&self) -> usize {
        self.stop
    }

    /// The index of the medium before surface `i` (air before the first).
    pub fn index_before(&self, i: usize) -> f64 {
        if i == 0 {
            1.0
        } else {
            self.surfaces[i - 1].index
        }
    }

    /// Each surface's vertex on the axis, mm from the first (+ toward the film).
    pub fn vertices(&self) -> Vec<f64> {
        let mut z = 0.0;
        self.surfaces
            .iter()
            .map(|s| {
                let here = z;
                z += s.thickness;
                here
            })
            .collect()
    }

    /// The last surface's vertex, mm from the first: the lens's length.
    pub fn length(&self) -> f64 {
        let n = self.surfaces.len();
        self.surfaces[..n - 1].iter().map(|s| s.thickness).sum()
    }

    /// The same lens with the stop's diameter `diameter` (stopping down or opening).
    pub fn with_stop_diameter(&self, diameter: f64) -> Self {
        let mut lens = self.clone();
        lens.surfaces[lens.stop].diameter = diameter;
        lens
    }

    /// The same lens with every medium's index at `lambda_nm` (`glass.rs`), for first-order
    /// data at that wavelength.
    pub fn at_wavelength(&self, lambda_nm: f64) -> Self {
        let mut lens = self.clone();
        for s in &mut lens.surfaces {
            s.index = s.glass().index(lambda_nm);
        }
        lens
    }

    /// The glass of element surface `i`'s medium before it (air before the first).
    pub fn glass_before(&self, i: usize) -> Glass {
        if i == 0 {
            Glass::AIR
        } else {
            self.surfaces[i - 1].glass()
        }
    }

    /// Whether any glass's index changes with the wavelength.
    pub fn is_dispersive(&self) -> bool {
        self.surfaces.iter().any(|s| s.glass().is_dispersive())
    }

    /// One line naming the glass rows without an Abbe number (they are non-dispersive), if
    /// there are any.
    pub fn dispersion_notice(&self) -> Option<String> {
        let rows = self.rows_without_abbe();
        if rows.is_empty() {
            return None;
        }
        let list: Vec<String> = rows.iter().map(usize::to_string).collect();
        Some(format!(
            "lens {}: the glass after surface{} {} has no Abbe number (5th column): its index is n_d at every wavelength",
            self.name,
            if rows.len() == 1 { "" } else { "s" },
            list.join(", ")
        ))
    }

    /// The rows (1-based) of glass without an Abbe number: non-dispersive.
    pub fn rows_without_abbe(&self) -> Vec<usize> {
        (0..self.surfaces.len())
            .filter(|&i| self.surfaces[i].index != 1.0 && self.surfaces[i].abbe.is_none())
            .map(|i| i + 1)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SINGLET: &str = "# a test singlet\n0 2 1 20\n50 5 1.5 20\n-50 0 1 20\n";

    #[test]
    fn parses_rows_comments_and_the_abbe_number() {
        let lens = Prescription::parse(
            "t",
            "# source line\n\n30 4 1.67 25 57.3 # a comment\n-200 1 1 25\n0 2 0 17\n-30 3 1.6 25\n40 0 1 25\n",
        )
        .unwrap();
        assert_eq!(lens.description.as_deref(), Some("source line"));
        assert_eq!(lens.surfaces().len(), 5);
        assert_eq!(lens.surfaces()[0].abbe, Some(57.3));
        assert_eq!(lens.surfaces()[1].abbe, None);
        assert_eq!(lens.surfaces()[2].index, 1.0);
        assert_eq!(lens.stop(), 2);
        assert_eq!(lens.vertices(), [0.0, 4.0, 5.0, 7.0, 10.0]);
        assert_eq!(lens.length(), 10.0);
        assert!(Prescription::parse("s", SINGLET).is_ok());
        // Glass rows without an Abbe number are named in one notice; air rows are not.
        let notice = lens.dispersion_notice().expect("row 4 has no Abbe number");
        assert!(notice.contains("surface 4 has no Abbe number"), "{notice}");
        assert!(lens.is_dispersive());
        let singlet = Prescription::parse("s", SINGLET).unwrap();
        assert!(!singlet.is_dispersive());
        assert!(singlet
            .dispersion_notice()
            .unwrap()
            .contains("surface 2 has"));
    }

    #[test]
    fn bad_prescriptions_are_refused() {
        let cases: [(&str, &str); 16] = [
            (
                "0 1 1 10\n50 5 1.5 20 0\n-50 0 1 20\n",
                "Abbe number must be positive",
            ),
            (
                "0 1 1 10\n50 5 1.5 20 -3\n-50 0 1 20\n",
                "Abbe number must be positive",
            ),
            (
                "0 1 1 10 k=-1\n50 5 1.5 20\n-50 0 1 20\n",
                "needs a base curvature",
            ),
            (
                "0 1 1 10\n10 5 1.5 20 k=2\n-50 0 1 20\n",
                "sag is undefined",
            ),
            (
                "0 1 1 10\n12 8 1.9 10\n-30 0 1 10 a4=0.5 a6=-0.3\n",
                "does not converge",
            ),
            ("0 1 1 10\n50 5 1.5 20 k=x\n-50 0 1 20\n", "not a number"),
            ("50 5 1.5 20\n-50 0 1 20\n", "no aperture stop"),
            (
                "0 1 1 10\n0 1 1 10\n50 5 1.5 20\n-50 0 1 20\n",
                "two aperture stops",
            ),
            ("0 1 1 10\n50 0 1.5 20\n-50 0 1 20\n", "must be positive"),
            ("0 1 1 10\n50 -1 1 20\n-50 0 1 20\n", "must be positive"),
            (
                "0 1 1 10\n50 nan 1.5 20\n-50 0 1 20\n",
                "not a finite number",
            ),
            ("0 1 1 10\n50 5 1.5\n-50 0 1 20\n", "expected 4 numbers"),
            (
                "0 1 1 10\n50 5 1.5 0\n-50 0 1 20\n",
                "diameter must be positive",
            ),
            ("0 1 1 10\n50 5 1.5 20\n-50 0 1.5 20\n", "into air"),
            (
                "0 1 1 10\n5 5 1.5 20\n-50 0 1 20\n",
                "smaller than the clear-aperture",
            ),
            ("# only a comment\n", "no surfaces"),
        ];
        for (text, needle) in cases {
            let err = Prescription::parse("bad", text)
                .expect_err(text)
                .to_string();
            assert!(err.contains(needle), "{text:?}: {err}");
        }
    }
}
