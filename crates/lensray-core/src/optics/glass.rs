//! Glass whose index depends on the wavelength: each glass of a prescription is its d-line
//! index n_d and Abbe number V_d = (n_d - 1) / (n_F - n_C), and its index at wavelength
//! lambda is the two-term Cauchy fit through the d, F and C lines:
//!
//! - B = (n_d - 1) / (V_d (lambda_F^-2 - lambda_C^-2)),
//! - A = n_d - B / lambda_d^2,
//! - n(lambda) = A + B / lambda^2,
//!
//! with lambda_d = 587.56 nm, lambda_F = 486.13 nm and lambda_C = 656.27 nm (wavelengths in
//! micrometres inside the formula). The fit meets n_d at the d line and n_F - n_C = (n_d - 1) / V_d
//! exactly; against a glass catalogue's Sellmeier curves it is within a few 1e-4 across the
//! visible range (crates/lensray/tests/lens_reference/README.md has the table).
//!
//! Written as n(lambda) = n_d + B k(lambda), k = lambda^-2 - lambda_d^-2 ([`dispersion_offset`]),
//! which is the same line: so a ray at the d line (k = 0) sees n_d itself, bit for bit, and a
//! medium without dispersion (air, or a glass row without an Abbe number) has B = 0.

/// The Fraunhofer lines the Abbe number is defined by, nm.
pub const LAMBDA_D_NM: f64 = 587.56;
pub const LAMBDA_F_NM: f64 = 486.13;
pub const LAMBDA_C_NM: f64 = 656.27;

/// A medium of a prescription: its d-line index and, for a dispersive glass, its Abbe number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Glass {
    pub n_d: f64,
    /// `None`: the index is n_d at every wavelength.
    pub abbe: Option<f64>,
}

impl Glass {
    pub const AIR: Glass = Glass {
        n_d: 1.0,
        abbe: None,
    };

    /// Cauchy's B, µm^2 (0 without dispersion).
    pub fn cauchy_b(&self) -> f64 {
        match self.abbe {
            Some(v) if self.n_d != 1.0 => {
                let (f, c) = (LAMBDA_F_NM * 1e-3, LAMBDA_C_NM * 1e-3);
                (self.n_d - 1.0) / (v * (1.0 / (f * f) - 1.0 / (c * c)))
            }
            _ => 0.0,
        }
    }

    /// Cauchy's A.
    pub fn cauchy_a(&self) -> f64 {
        let d = LAMBDA_D_NM * 1e-3;
        self.n_d - self.cauchy_b() / (d * d)
    }

    /// The index at `lambda_nm`.
    pub fn index(&self, lambda_nm: f64) -> f64 {
        self.n_d + self.cauchy_b() * dispersion_offset(lambda_nm)
    }

    /// Whether the index changes with the wavelength.
    pub fn is_dispersive(&self) -> bool {
        self.cauchy_b() != 0.0
    }
}

/// k(lambda) = lambda^-2 - lambda_d^-2 (µm^-2): the index at lambda is n_d + B k.
pub fn dispersion_offset(lambda_nm: f64) -> f64 {
    let l = lambda_nm * 1e-3;
    let d = LAMBDA_D_NM * 1e-3;
    1.0 / (l * l) - 1.0 / (d * d)
}

/// [`dispersion_offset`] in f32, as a render computes it per camera ray (the GLSL mirrors it:
/// `dispersion_offset` in real_lens.glsl).
#[inline]
pub fn dispersion_offset_f32(lambda_nm: f32) -> f32 {
    const D: f32 = crate::interface::GLASS_LAMBDA_D_UM;
    let l = lambda_nm * 1e-3;
    1.0 / (l * l) - 1.0 / (D * D)
}

const _: () =
    assert!(crate::interface::GLASS_LAMBDA_D_UM as f64 == (LAMBDA_D_NM * 1e-3) as f32 as f64);

#[cfg(test)]
mod tests {
    use super::*;

    /// The fit passes n_d at the d line and its F - C difference is (n_d - 1) / V_d: the
    /// definition of the Abbe number.
    #[test]
    fn cauchy_meets_the_d_line_and_the_abbe_number() {
        // N-BK7 (Schott: n_d 1.5168, V_d 64.17; catalogue n_F 1.52238, n_C 1.51432).
        let bk7 = Glass {
            n_d: 1.5168,
            abbe: Some(64.17),
        };
        assert!((bk7.index(LAMBDA_D_NM) - 1.5168).abs() < 1e-15);
        let v = (bk7.n_d - 1.0) / (bk7.index(LAMBDA_F_NM) - bk7.index(LAMBDA_C_NM));
        assert!((v - 64.17).abs() < 1e-10, "V_d {v}");
        assert!((bk7.index(LAMBDA_F_NM) - 1.52238).abs() < 2e-4);
        assert!((bk7.index(LAMBDA_C_NM) - 1.51432).abs() < 2e-4);
        // A + B / lambda^2 is the same line.
        let l: f64 = 0.45;
        let direct = bk7.cauchy_a() + bk7.cauchy_b() / (l * l);
        assert!((direct - bk7.index(450.0)).abs() < 1e-14);
        assert!(dispersion_offset_f32(LAMBDA_D_NM as f32).abs() < 1e-5);
        assert!(!Glass::AIR.is_dispersive());
        assert_eq!(Glass { abbe: None, ..bk7 }.index(400.0), 1.5168);
    }
}
