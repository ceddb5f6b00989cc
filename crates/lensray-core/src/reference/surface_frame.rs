//! What a surface's vertices add to its material: vertex colours, which multiply the base
//! colour, and tangents, the frame in which a normal map tilts the shading normal.
//! shaders/include/surface_frame.glsl mirrors it, operation for operation.

use glam::{Vec2, Vec3, Vec4};

use super::accel::Hit;
use super::surface::{interpolate, SurfaceData, SurfacePoint};
use crate::scene::texture::{sample, TexcoordFootprint};
use crate::scene::{Material, Texture};

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

    /// The shading normal ns of `surface` (unit, turned to the viewer) tilted by `material`'s
    /// normal map, read over the footprint `duv`, at `hit` (a triangle of corners `vertices`).
    /// The map's normal m = (2 texel - 1) (scale, scale, 1) is read in the frame of the
    /// interpolated vertex normal n0: the tangent T (the interpolated tangent made orthogonal
    /// to ns), the bitangent cross(n0, T) w and n0. Where the viewer sees the back, ns = -n0
    /// and the whole frame turns with it: the result is
    /// normalize(s m.x T + m.y w cross(ns, T) + m.z ns), s = +1 in front and -1 behind. `ns`
    /// where the mesh has no tangents or the frame is degenerate.
    pub(super) fn normal_mapped(
        &self,
        material: &Material,
        textures: &[Texture],
        hit: &Hit,
        vertices: [Vec3; 3],
        surface: &SurfacePoint,
        duv: &TexcoordFootprint,
    ) -> Vec3 {
        let (triangle, b, ns) = (hit.triangle, hit.barycentric, surface.shading_normal);
        let (Some(normal_map), Some(Some(tangents))) = (
            &material.normal_texture,
            self.tangents.get(triangle as usize),
        ) else {
            return ns;
        };
        let texel = sample(textures, normal_map, surface.texcoord, duv);
        let normals = self.normals[triangle as usize];
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
        let scale = material.normal_scale;
        let n = t * (s * m.x * scale) + bitangent * (m.y * scale) + ns * m.z;
        let length_squared = n.dot(n);
        if !(length_squared > 0.0 && length_squared.is_finite()) {
            return ns;
        }
        n / length_squared.sqrt()
    }
}
