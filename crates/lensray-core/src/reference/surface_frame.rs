//! What a surface's vertices add to its material: vertex colours, which multiply the base
//! colour, and tangents, the frame in which a normal map tilts the shading normal.
//! shaders/include/surface_frame.glsl mirrors it, operation for operation.

use glam::{Vec2, Vec3, Vec4};

use super::accel::Hit;
use super::surface::{interpolate, SurfaceData, SurfacePoint};
use crate::interface::REFLECTION_MIN_COSINE;
use crate::scene::texture::{sample, FootprintSets, TextureRef};
use crate::scene::Texture;

/// The base colour `base` times the vertex colour `colour` (its RGB; alpha is not read).
pub(super) fn vertex_coloured(base: Vec3, colour: Option<Vec4>) -> Vec3 {
    match colour {
        Some(c) => base * c.truncate(),
        None => base,
    }
}

impl SurfaceData {
    /// The vertex colour of `triangle` at barycentrics `b` (the weights of v1, v2); `None`
    /// where its mesh has no colours.
    pub(super) fn colour(&self, triangle: u32, b: Vec2) -> Option<Vec4> {
        let c = self.colours.get(triangle as usize)?.as_ref()?;
        Some((1.0 - b.x - b.y) * c[0] + b.x * c[1] + b.y * c[2])
    }

    /// Whether the mesh of `triangle` has vertex colours.
    pub(super) fn has_colours(&self, triangle: u32) -> bool {
        self.colours
            .get(triangle as usize)
            .is_some_and(Option::is_some)
    }

    /// The shading normal ns of `surface` (unit, turned to the viewer) tilted by the normal
    /// map `map` (a texture and its scale: the base's or the clear coat's, `Material::
    /// normal_map`), read over the footprint `duv`, at `hit` (a triangle of corners `vertices`).
    /// The map's normal m = (2 texel - 1) (scale, scale, 1) is read in the frame of the
    /// interpolated vertex normal n0: the tangent T (the interpolated tangent made orthogonal
    /// to ns), the bitangent cross(n0, T) w and n0. Where the viewer sees the back, ns = -n0
    /// and the whole frame turns with it: the result is
    /// normalize(s m.x T + m.y w cross(ns, T) + m.z ns), s = +1 in front and -1 behind. `ns`
    /// where the mesh has no tangents or the frame is degenerate.
    pub(super) fn normal_mapped(
        &self,
        map: Option<(TextureRef, f32)>,
        textures: &[Texture],
        hit: &Hit,
        vertices: [Vec3; 3],
        surface: &SurfacePoint,
        duv: &FootprintSets,
    ) -> Vec3 {
        let (b, ns) = (hit.barycentric, surface.shading_normal);
        let (Some((normal_map, scale)), Some(tangents)) = (map, self.tangents(hit)) else {
            return ns;
        };
        let texel = sample(textures, &normal_map, &surface.texcoords, duv);
        let normals = self.normals(hit);
        let n0 = if normals[0] == Vec3::ZERO {
            (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0])
        } else {
            interpolate(normals, b)
        };
        let s = if ns.dot(n0) < 0.0 { -1.0 } else { 1.0 };
        let t4 = (1.0 - b.x - b.y) * tangents[0] + b.x * tangents[1] + b.y * tangents[2];
        let t = t4.truncate();
        let t = t - ns * ns.dot(t);
        let length_squared = t.dot(t);
        if !(length_squared > 0.0 && length_squared.is_finite()) {
            return ns;
        }
        let t = t / length_squared.sqrt();
        let w = if t4.w < 0.0 { -1.0 } else { 1.0 };
        let bitangent = ns.cross(t) * w;
        let m = texel.truncate() * 2.0 - Vec3::ONE;
        let n = t * (s * m.x * scale) + bitangent * (m.y * scale) + ns * m.z;
        let length_squared = n.dot(n);
        if !(length_squared > 0.0 && length_squared.is_finite()) {
            return ns;
        }
        n / length_squared.sqrt()
    }
}

/// The shading normal `n` turned towards the geometric normal `ng` (unit, on the viewer's side)
/// just enough that the mirror reflection of the view `v` (unit, towards the viewer) about it
/// leaves above the geometric surface, at a cosine of at least t = min(0.9 ng.v,
/// `REFLECTION_MIN_COSINE`); `n` itself where its reflection already does.
///
/// A shading normal (interpolated, or tilted by a normal map) can face away from the viewer or
/// mirror the view under the surface: the BRDF then sees the viewer below its hemisphere and
/// its draws fall below the surface, and a glossy surface turns black there ("pepper" and dark
/// rings). Turning the normal keeps the specular lobe's peak above the surface, as Cycles does
/// (docs/shading-normals.md says why this rather than microfacet-based normal mapping).
///
/// The normal n' = x X + z ng stays in the plane of `ng` and `n` (X: the unit part of `n`
/// across `ng`), x^2 + z^2 = 1. With v = (v_x, v_z) in that plane, the reflection's height
/// 2 (n'.v) z - v_z = t gives, in s = z^2,
/// 4 a s^2 - 4 b s + c = 0 with a = v_x^2 + v_z^2, b = a + v_z t, c = (v_z + t)^2,
/// whose roots are s = (b +- sqrt(b^2 - a c)) / (2 a). Squaring added the equation
/// 2 x z v_x = -(t + v_z (1 - 2 s)): of the two roots, the one whose unsquared equation holds
/// (the smaller residual) is the normal.
pub(super) fn reflection_safe_normal(ng: Vec3, v: Vec3, n: Vec3) -> Vec3 {
    let v_z = v.dot(ng);
    let t = (0.9 * v_z).min(REFLECTION_MIN_COSINE);
    let reflected_height = 2.0 * n.dot(v) * n.dot(ng) - v_z;
    if reflected_height >= t || v_z <= 0.0 {
        return n;
    }
    let across = n - ng * n.dot(ng);
    let length_squared = across.dot(across);
    if !(length_squared > 0.0 && length_squared.is_finite()) {
        return ng;
    }
    let x_axis = across / length_squared.sqrt();
    let v_x = v.dot(x_axis);
    let a = v_x * v_x + v_z * v_z;
    let b = a + v_z * t;
    let c = (v_z + t) * (v_z + t);
    let root = (b * b - a * c).max(0.0).sqrt();
    let inv_2a = 0.5 / a;
    let candidate = |s: f32| {
        let s = s.clamp(0.0, 1.0);
        let (z, x) = (s.sqrt(), (1.0 - s).sqrt());
        let residual = (2.0 * x * z * v_x - (t + v_z * (1.0 - 2.0 * s))).abs();
        (x_axis * x + ng * z, residual)
    };
    let (n1, r1) = candidate((b + root) * inv_2a);
    let (n2, r2) = candidate((b - root) * inv_2a);
    if r1 <= r2 {
        n1
    } else {
        n2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mirror reflection's height of `v` about `n` above the plane of `ng`.
    fn reflected_height(ng: Vec3, v: Vec3, n: Vec3) -> f32 {
        (2.0 * n.dot(v) * n - v).dot(ng)
    }

    /// Over views and normals on a grid of the sphere: the normal stays unit and in the plane
    /// of `ng` and `n`; a normal whose reflection already clears t is kept as it is; one whose
    /// reflection does not is turned just enough, so that the reflection lands at t.
    #[test]
    fn reflections_about_the_safe_normal_clear_the_surface() {
        let ng = Vec3::Z;
        let (mut kept, mut turned, mut worst) = (0, 0, 0.0f32);
        let direction = |theta: f32, phi: f32| {
            Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        for i in 0..40 {
            let view_theta = (i as f32 + 0.5) / 40.0 * std::f32::consts::FRAC_PI_2;
            let v = direction(view_theta, 0.3);
            let t = (0.9 * v.dot(ng)).min(REFLECTION_MIN_COSINE);
            for j in 0..40 {
                let normal_theta = (j as f32 + 0.5) / 40.0 * 1.4;
                for k in 0..16 {
                    let n = direction(normal_theta, k as f32 / 16.0 * std::f32::consts::TAU);
                    let safe = reflection_safe_normal(ng, v, n);
                    assert!((safe.length() - 1.0).abs() < 1e-5, "{safe}");
                    assert!(safe.dot(ng.cross(n)).abs() < 1e-5, "{safe} left the plane");
                    let height = reflected_height(ng, v, safe);
                    if reflected_height(ng, v, n) >= t {
                        assert_eq!(safe, n);
                        kept += 1;
                    } else {
                        worst = worst.max((height - t).abs());
                        assert!(
                            (height - t).abs() < 2e-4,
                            "v {v}, n {n}: {height} against {t}"
                        );
                        assert!(safe.dot(ng) > n.dot(ng), "{safe} turned away from {ng}");
                        turned += 1;
                    }
                }
            }
        }
        println!("kept {kept}, turned {turned}, largest |height - t| {worst:.2e}");
        assert!(kept > 1000 && turned > 1000, "kept {kept}, turned {turned}");
    }
}
