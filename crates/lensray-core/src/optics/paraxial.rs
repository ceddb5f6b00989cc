//! First-order optics of a prescription (the course's "Paraxial Approximation", made exact for
//! thick lenses): ray-transfer (ABCD) matrices acting on (height y, reduced angle n u), the
//! cardinal points and the pupils. Lengths in mm, + toward the film; object and image space
//! are air.

use super::prescription::{Prescription, Surface};

/// A 2x2 ray-transfer matrix [[a, b], [c, d]] on (y, n u).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Abcd {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
}

impl Abcd {
    pub const IDENTITY: Abcd = Abcd {
        a: 1.0,
        b: 0.0,
        c: 0.0,
        d: 1.0,
    };

    /// Travel `thickness` through a medium of index `index`.
    pub fn transfer(thickness: f64, index: f64) -> Self {
        Abcd {
            b: thickness / index,
            ..Self::IDENTITY
        }
    }

    /// Refraction at `surface` from index `from` to `to`: power (to - from) / radius (0 for
    /// the flat stop), plus an asphere's r^2 term's 2 (to - from) a2 (`Surface::paraxial_curvature`).
    pub fn refraction(surface: &Surface, from: f64, to: f64) -> Self {
        let power = if surface.radius == 0.0 {
            0.0
        } else {
            (to - from) / surface.radius
                + 2.0 * (to - from) * surface.asphere.map_or(0.0, |a| a.coefficients[0])
        };
        Abcd {
            c: -power,
            ..Self::IDENTITY
        }
    }

    /// `self` after `first` (matrices apply right to left).
    pub fn after(self, first: Abcd) -> Abcd {
        Abcd {
            a: self.a * first.a + self.b * first.c,
            b: self.a * first.b + self.b * first.d,
            c: self.c * first.a + self.d * first.c,
            d: self.c * first.b + self.d * first.d,
        }
    }

    /// (y, n u) after the matrix.
    pub fn apply(self, y: f64, nu: f64) -> (f64, f64) {
        (self.a * y + self.b * nu, self.c * y + self.d * nu)
    }
}

/// The matrix from just before surface `from` to just after surface `to - 1`, with the
/// transfers between them (not the one after `to - 1`).
pub fn surfaces_matrix(lens: &Prescription, from: usize, to: usize) -> Abcd {
    let s = lens.surfaces();
    let mut m = Abcd::IDENTITY;
    for i in from..to {
        if i > from {
            m = Abcd::transfer(s[i - 1].thickness, s[i - 1].index).after(m);
        }
        m = Abcd::refraction(&s[i], lens.index_before(i), s[i].index).after(m);
    }
    m
}

/// The whole lens: first vertex (object space) to last vertex (image space).
pub fn system_matrix(lens: &Prescription) -> Abcd {
    surfaces_matrix(lens, 0, lens.surfaces().len())
}

/// A pupil: where the stop's image lies and how wide it is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Pupil {
    /// mm, + toward the film: from the first vertex (entrance), from the last (exit).
    pub position_mm: f64,
    pub diameter_mm: f64,
}

/// The first-order data of a lens, object at infinity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstOrder {
    pub efl: f64,
    /// Last vertex to the rear focal point.
    pub bfl: f64,
    /// First vertex to the front focal point.
    pub ffl: f64,
    /// From the first vertex.
    pub front_principal_plane: f64,
    /// From the last vertex.
    pub rear_principal_plane: f64,
    pub entrance_pupil: Pupil,
    pub exit_pupil: Pupil,
    /// efl over the entrance pupil's diameter.
    pub f_number: f64,
}

impl FirstOrder {
    /// The first-order data of `lens` (its power must not be zero).
    pub fn of(lens: &Prescription) -> Self {
        let m = system_matrix(lens);
        let efl = -1.0 / m.c;
        let bfl = -m.a / m.c;
        let ffl = m.d / m.c;
        let stop = lens.stop();
        let stop_diameter = lens.surfaces()[stop].diameter;
        // Front group: first vertex to the stop plane. The stop's centre is conjugate to the
        // object-space point at b / a; the lateral magnification there is a.
        let front = if stop == 0 {
            Abcd::IDENTITY
        } else {
            let s = &lens.surfaces()[stop - 1];
            Abcd::transfer(s.thickness, s.index).after(surfaces_matrix(lens, 0, stop))
        };
        let entrance_pupil = Pupil {
            position_mm: front.b / front.a,
            diameter_mm: stop_diameter / front.a.abs(),
        };
        // Rear group: the stop plane to the last vertex. The stop's centre images at -b / d
        // from the last vertex, magnified by 1 / d (the matrix's determinant is 1).
        let rear = surfaces_matrix(lens, stop, lens.surfaces().len());
        let exit_pupil = Pupil {
            position_mm: -rear.b / rear.d,
            diameter_mm: stop_diameter / rear.d.abs(),
        };
        FirstOrder {
            efl,
            bfl,
            ffl,
            front_principal_plane: (m.d - 1.0) / m.c,
            rear_principal_plane: (1.0 - m.a) / m.c,
            entrance_pupil,
            exit_pupil,
            f_number: efl / entrance_pupil.diameter_mm,
        }
    }
}

/// Third-order (Seidel) longitudinal spherical aberration of `lens` for a ray entering
/// parallel to the axis at `height` (mm, + toward the film): the sum over the surfaces of
/// S_I = -A^2 h delta(u / n), with A = n (h c + u) the paraxial refraction invariant, along the
/// paraxial marginal ray; the axial shift is -S_I / (2 n' u'^2) in the image space.
pub fn seidel_lsa(lens: &Prescription, height: f64) -> f64 {
    let s = lens.surfaces();
    let (mut h, mut u) = (height, 0.0);
    let mut sum = 0.0;
    for (i, surface) in s.iter().enumerate() {
        let (n, n2) = (lens.index_before(i), surface.index);
        let c = surface.paraxial_curvature();
        let a = n * (h * c + u);
        let u2 = (n * u - h * (n2 - n) * c) / n2;
        sum += -a * a * h * (u2 / n2 - u / n);
        u = u2;
        if i + 1 < s.len() {
            h += surface.thickness * u;
        }
    }
    -sum / (2.0 * u * u)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A biconvex singlet against the thick-lens formula (lensmaker's equation with thickness):
    /// 1/f = (n - 1) (1/R1 - 1/R2 + (n - 1) t / (n R1 R2)), principal planes at
    /// -f (n - 1) t / (n R2) and -f (n - 1) t / (n R1) from the vertices.
    #[test]
    fn a_singlet_follows_the_thick_lens_formula() {
        let (r1, r2, t, n) = (60.0, -40.0, 8.0, 1.6);
        let lens =
            Prescription::parse("s", &format!("0 2 1 20\n{r1} {t} {n} 30\n{r2} 0 1 30\n")).unwrap();
        let f = FirstOrder::of(&lens);
        let power = (n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * t / (n * r1 * r2));
        let efl = 1.0 / power;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
        assert!(close(f.efl, efl), "{} vs {efl}", f.efl);
        let h1 = -efl * (n - 1.0) * t / (n * r2);
        let h2 = -efl * (n - 1.0) * t / (n * r1);
        // The stop 2 mm before the lens: the front principal plane measured from the stop.
        assert!(close(f.front_principal_plane, 2.0 + h1), "{f:?}");
        assert!(close(f.rear_principal_plane, h2), "{f:?}");
        assert!(close(f.bfl, efl + h2), "{f:?}");
        assert!(close(f.ffl, 2.0 + h1 - efl), "{f:?}");
        // The stop is in front of everything: it is its own entrance pupil.
        assert_eq!(f.entrance_pupil.position_mm, 0.0);
        assert!(close(f.entrance_pupil.diameter_mm, 20.0));
        assert!(close(f.f_number, efl / 20.0));
    }
}
