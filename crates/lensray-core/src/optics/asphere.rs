//! Even aspheres: a surface whose sag (its z from the vertex, + toward the film) at distance r
//! from the axis is
//!
//! z(r) = c r^2 / (1 + sqrt(1 - (1 + k) c^2 r^2)) + a2 r^2 + a4 r^4 + ... + a16 r^16,
//!
//! with c = 1 / radius the vertex curvature, k the conic constant and a2..a16 the even
//! polynomial's coefficients (mm^(1-n)). A prescription row gives them after its numbers as
//! keyword fields `k=`, `a2=`, `a4=`, ..., `a16=` (any left out is 0); a row with none of them
//! is a sphere, so pbrt's four-column files read unchanged.
//!
//! The tracer finds where a ray meets the sag by Newton's iteration (`trace.rs`); first-order
//! (paraxial) data use the vertex curvature alone, plus a2, which changes the paraxial power.

/// The powers of r the coefficients multiply.
pub const POWERS: [u32; 8] = [2, 4, 6, 8, 10, 12, 14, 16];

/// A surface's aspheric terms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Asphere {
    /// k: 0 a sphere, -1 a paraboloid.
    pub conic: f64,
    /// a2, a4, ..., a16.
    pub coefficients: [f64; 8],
}

impl Asphere {
    /// Reads one keyword field (`k=-0.5`, `a4=1e-5`) into the asphere; an error names what is
    /// wrong with it.
    pub fn read_field(&mut self, field: &str) -> Result<(), String> {
        let (key, value) = field.split_once('=').ok_or_else(|| {
            format!("'{field}' is neither a number nor a keyword field (k=, a4=, ...)")
        })?;
        let number: f64 = value
            .parse()
            .map_err(|_| format!("'{field}': '{value}' is not a number"))?;
        if !number.is_finite() {
            return Err(format!("'{field}': '{value}' is not a finite number"));
        }
        let key = key.to_ascii_lowercase();
        if key == "k" {
            self.conic = number;
            return Ok(());
        }
        let slot = key
            .strip_prefix('a')
            .and_then(|p| p.parse::<u32>().ok())
            .and_then(|p| POWERS.iter().position(|&q| q == p))
            .ok_or_else(|| {
                format!("'{key}' is no aspheric term (k, a2, a4, a6, a8, a10, a12, a14, a16)")
            })?;
        self.coefficients[slot] = number;
        Ok(())
    }

    /// The sag at squared distance `r2` from the axis for vertex curvature `c`; `None` where
    /// the conic's square root is undefined.
    pub fn sag(&self, c: f64, r2: f64) -> Option<f64> {
        let q2 = 1.0 - (1.0 + self.conic) * c * c * r2;
        if q2.is_nan() || q2 < 0.0 {
            return None;
        }
        let mut poly = 0.0;
        for a in self.coefficients.iter().rev() {
            poly = poly * r2 + a;
        }
        Some(c * r2 / (1.0 + q2.sqrt()) + poly * r2)
    }

    /// The largest distance from the axis at which the sag is defined (infinity for an
    /// oblate or hyperbolic conic, k <= -1).
    pub fn defined_radius(&self, c: f64) -> f64 {
        let limit = (1.0 + self.conic) * c * c;
        if limit <= 0.0 {
            f64::INFINITY
        } else {
            1.0 / limit.sqrt()
        }
    }

    /// The keyword fields that write this asphere back (only its non-zero terms).
    pub fn fields(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.conic != 0.0 {
            out.push(format!("k={}", self.conic));
        }
        for (a, p) in self.coefficients.iter().zip(POWERS) {
            if *a != 0.0 {
                out.push(format!("a{p}={a:e}"));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_fields_and_computes_the_sag() {
        let mut a = Asphere::default();
        a.read_field("k=-1").unwrap();
        a.read_field("A4=2e-5").unwrap();
        assert_eq!(a.conic, -1.0);
        assert_eq!(a.coefficients[1], 2e-5);
        // A paraboloid: c r^2 / 2, plus the r^4 term.
        let (c, r): (f64, f64) = (1.0 / 40.0, 6.0);
        let want = c * r * r / 2.0 + 2e-5 * r.powi(4);
        assert!((a.sag(c, r * r).unwrap() - want).abs() < 1e-15);
        assert!(a
            .read_field("a3=1")
            .unwrap_err()
            .contains("no aspheric term"));
        assert!(a.read_field("k=x").unwrap_err().contains("not a number"));
        assert!(a.read_field("k=inf").unwrap_err().contains("finite"));
        // A sphere's sag is undefined past its radius.
        let sphere = Asphere::default();
        assert_eq!(sphere.defined_radius(c), 40.0);
        assert!(sphere.sag(c, 41.0 * 41.0).is_none());
        assert_eq!(a.fields(), ["k=-1", "a4=2e-5"]);
    }
}
