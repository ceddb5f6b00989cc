//! A ghost's light: the share of a ray's power that follows a ghost's path (reflected by
//! surface j, back to surface i, reflected again, on to the film: `Elements::trace_ghost_at`),
//! the product of the two reflectances and of the transmittances (1 - R) of every surface it
//! crosses, each at the ray's angle there and its wavelength (`coating`). The stop is an
//! opening, not an interface: it clips the path and passes the rest whole.

use super::coating::Coating;
use super::glass::dispersion_offset;
use super::trace::wide::{refract, Elements, Interface, LensRay};
use super::trace::Toward;

/// One step of a ghost's path: crossing a surface toward the film or the scene, or being
/// reflected by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum GhostStep {
    Cross(Toward),
    Reflect(Toward),
}

/// The steps of ghost `(i, j)` through `n` surfaces, surface by surface.
fn steps(n: usize, (i, j): (usize, usize)) -> Vec<(usize, GhostStep)> {
    let mut steps: Vec<(usize, GhostStep)> = (0..j)
        .map(|s| (s, GhostStep::Cross(Toward::Film)))
        .collect();
    steps.push((j, GhostStep::Reflect(Toward::Film)));
    steps.extend(
        (i + 1..j)
            .rev()
            .map(|s| (s, GhostStep::Cross(Toward::Scene))),
    );
    steps.push((i, GhostStep::Reflect(Toward::Scene)));
    steps.extend((i + 1..n).map(|s| (s, GhostStep::Cross(Toward::Film))));
    steps
}

/// `ray` (from the scene) along ghost `(i, j)` at wavelength `lambda_nm`, each surface under
/// `coatings[s]`: the ray that leaves the last surface and the share of its power it carries,
/// or `None` where the path is blocked (as `trace_ghost_at`).
pub fn ghost_throughput(
    elements: &Elements,
    coatings: &[Coating],
    ray: LensRay,
    (i, j): (usize, usize),
    lambda_nm: f64,
) -> Option<(LensRay, f64)> {
    let n = elements.interfaces.len();
    assert_eq!(coatings.len(), n, "one coating per surface");
    if !(i < j && j < n) {
        return None;
    }
    let k = dispersion_offset(lambda_nm);
    let mut ray = ray;
    let mut share = 1.0;
    for (s, step) in steps(n, (i, j)) {
        let surface = &elements.interfaces[s];
        let (_, normal) = surface.intersect(ray)?;
        let cos = -normal.dot(ray.direction);
        let toward = match step {
            GhostStep::Cross(toward) | GhostStep::Reflect(toward) => toward,
        };
        let reflectance = reflectance(surface, coatings[s], toward, cos, (k, lambda_nm));
        (ray, share) = match step {
            GhostStep::Cross(toward) => (
                surface.pass_at(ray, toward, k)?,
                share * (1.0 - reflectance),
            ),
            GhostStep::Reflect(_) => (surface.reflect(ray)?, share * reflectance),
        };
    }
    Some((ray, share))
}

/// One ray of a ghost's (or the direct path's) grid, traced without clipping: where it leaves
/// the lens, the share of its power it carries, where it crossed the stop's plane (a ghost
/// between surfaces on either side of the stop crosses it three times) and how far out it
/// passed the clear apertures. A ghost's image interpolates these across the grid's cells and
/// clips there, so its outline follows the stop's shape and the rims exactly, not the grid
/// (Hullin et al. 2011).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GhostVertex {
    pub out: LensRay,
    pub share: f64,
    /// The stop's plane, crossing by crossing (x, y in mm); `crossings` of them are set.
    pub stops: [[f64; 2]; 3],
    pub crossings: usize,
    /// The largest (r / clear radius)^2 over the surfaces met, the stop aside: past 1 the ray
    /// is blocked by a rim.
    pub rim: f64,
}

/// `ray` (from the scene) along ghost `ghost` (or straight through, `None`) at `lambda_nm`,
/// unclipped ([`GhostVertex`]); `stop` is the stop's row, which reflects nothing. The direct
/// path carries all the power (the renderer's own image of a source has no coating losses);
/// a ghost carries its reflectances and transmittances as [`ghost_throughput`]. `None` where
/// the ray misses a surface or is totally internally reflected.
pub fn ghost_vertex(
    elements: &Elements,
    coatings: &[Coating],
    ray: LensRay,
    ghost: Option<(usize, usize)>,
    (lambda_nm, stop): (f64, usize),
) -> Option<GhostVertex> {
    let n = elements.interfaces.len();
    let path = match ghost {
        Some(pair) => steps(n, pair),
        None => (0..n)
            .map(|s| (s, GhostStep::Cross(Toward::Film)))
            .collect(),
    };
    let k = dispersion_offset(lambda_nm);
    let mut vertex = GhostVertex {
        out: ray,
        share: 1.0,
        stops: [[0.0; 2]; 3],
        crossings: 0,
        rim: 0.0,
    };
    for (s, step) in path {
        let surface = &elements.interfaces[s];
        let ray = vertex.out;
        let (t, normal) = surface.intersect(ray)?;
        let p = ray.origin + t * ray.direction;
        if s == stop {
            if vertex.crossings < 3 {
                vertex.stops[vertex.crossings] = [p.x, p.y];
            }
            vertex.crossings += 1;
            continue;
        }
        let r2 = (p.x * p.x + p.y * p.y) / (surface.aperture_radius * surface.aperture_radius);
        vertex.rim = vertex.rim.max(r2);
        let cos = -normal.dot(ray.direction);
        let (toward, reflects) = match step {
            GhostStep::Cross(toward) => (toward, false),
            GhostStep::Reflect(toward) => (toward, true),
        };
        let reflectance = match ghost {
            Some(_) => reflectance(surface, coatings[s], toward, cos, (k, lambda_nm)),
            None => 0.0,
        };
        let direction = if reflects {
            vertex.share *= reflectance;
            ray.direction - 2.0 * ray.direction.dot(normal) * normal
        } else {
            vertex.share *= 1.0 - reflectance;
            let before = surface.index_before + surface.dispersion_before * k;
            let after = surface.index_after + surface.dispersion_after * k;
            let (from, to) = match toward {
                Toward::Film => (before, after),
                Toward::Scene => (after, before),
            };
            refract(ray.direction, normal, from / to)?
        };
        vertex.out = LensRay {
            origin: p,
            direction,
        };
    }
    Some(vertex)
}

/// What `surface` under `coating` reflects of light meeting it at `cos` going `toward`, at
/// dispersion offset `k` (wavelength `lambda_nm`); the stop reflects nothing.
fn reflectance(
    surface: &Interface,
    coating: Coating,
    toward: Toward,
    cos: f64,
    (k, lambda_nm): (f64, f64),
) -> f64 {
    if surface.radius == 0.0 {
        return 0.0;
    }
    let before = surface.index_before + surface.dispersion_before * k;
    let after = surface.index_after + surface.dispersion_after * k;
    let (from, to) = match toward {
        Toward::Film => (before, after),
        Toward::Scene => (after, before),
    };
    coating.reflectance(from, to, cos, lambda_nm)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::builtin;
    use crate::optics::glass::LAMBDA_D_NM;
    use glam::DVec3;

    /// On the axis every surface is met at normal incidence, where a bare interface reflects
    /// ((n1 - n2) / (n1 + n2))^2: a ghost of double-gauss-50 carries the product of its two
    /// reflectances and the transmittances of the surfaces it crosses (the stop aside),
    /// written out here from the indices alone. With the surfaces between air and glass
    /// coated, a ghost reflected by one of them carries less, and one between two cemented
    /// surfaces more (the coats let more through on the way).
    #[test]
    fn an_axial_ghost_carries_its_two_reflectances_and_the_transmittances_between() {
        let lens = builtin::lens("double-gauss-50").unwrap();
        let elements = Elements::new(&lens);
        let n = elements.interfaces.len();
        let axial = LensRay {
            origin: DVec3::new(0.0, 0.0, -50.0),
            direction: DVec3::Z,
        };
        let normal = |s: usize| {
            let (a, b) = (lens.index_before(s), lens.surfaces()[s].index);
            if lens.surfaces()[s].radius == 0.0 {
                0.0
            } else {
                ((a - b) / (a + b)).powi(2)
            }
        };
        let bare = vec![Coating::Uncoated; n];
        // Surfaces between air and glass coated, cemented ones bare, as lenses are made.
        let coated: Vec<Coating> = (0..n)
            .map(
                |s| match lens.index_before(s) == 1.0 || lens.surfaces()[s].index == 1.0 {
                    true => Coating::default(),
                    false => Coating::Uncoated,
                },
            )
            .collect();
        let mut checked = 0;
        for i in 0..n {
            for j in i + 1..n {
                let Some((_, share)) =
                    ghost_throughput(&elements, &bare, axial, (i, j), LAMBDA_D_NM)
                else {
                    continue;
                };
                let crossed: f64 = steps(n, (i, j))
                    .iter()
                    .filter(|(_, step)| matches!(step, GhostStep::Cross(_)))
                    .map(|&(s, _)| 1.0 - normal(s))
                    .product();
                let expected = normal(i) * normal(j) * crossed;
                assert!(
                    (share - expected).abs() < 1e-12 * expected.max(1e-30),
                    "ghost ({i}, {j}): {share} against {expected}"
                );
                let (_, with_coats) =
                    ghost_throughput(&elements, &coated, axial, (i, j), LAMBDA_D_NM).unwrap();
                // A coat on a reflecting surface dims the ghost; between two bare (cemented)
                // reflectors the coats only let more through on the way.
                let reflector_coated =
                    coated[i] != Coating::Uncoated || coated[j] != Coating::Uncoated;
                assert!(
                    if reflector_coated {
                        with_coats < share
                    } else {
                        with_coats >= share
                    },
                    "ghost ({i}, {j}) coated: {with_coats} against {share}"
                );
                checked += 1;
            }
        }
        // The stop and the cemented surfaces aside, most pairs are ghosts.
        assert!(checked > 40, "{checked} axial ghosts");
    }
}
