//! What a hit means: position, normals facing the viewer, material. Shared by every shading mode.

use glam::{Vec2, Vec3, Vec4};

use super::accel::Hit;
use super::steps::TriangleSteps;
use crate::camera::{Footprint, Ray};
use crate::interface::SHADOW_ORIGIN_OFFSET;
use crate::scene::texture::{FootprintSets, TexcoordFootprint, TexcoordSets};
use crate::scene::{Material, Texture};

/// A hit point with the normals the shading definition uses.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    pub position: Vec3,
    /// Geometric normal, flipped to face the incoming ray.
    pub geometric_normal: Vec3,
    /// Interpolated vertex normal (or the geometric one when the mesh has none), flipped to face
    /// the incoming ray independently of the geometric normal.
    pub shading_normal: Vec3,
    pub material: u32,
    /// Whether the ray met the triangle's back face (it sees it clockwise): a volume's
    /// boundary is left there.
    pub back_face: bool,
    /// Interpolated texture coordinates of each set ((0, 0) in a set the mesh lacks).
    pub texcoords: TexcoordSets,
}

/// Per-triangle shading data, in the renderer's triangle order.
pub(super) struct SurfaceData {
    /// Vertex normals per triangle; all zero when the mesh has none.
    pub normals: Vec<[Vec3; 3]>,
    /// Texture coordinates (set 0) per triangle; all zero when the mesh has none.
    pub texcoords: Vec<[Vec2; 3]>,
    /// The second set's per triangle (all zero where the mesh has none); empty when no mesh
    /// has one.
    pub texcoords1: Vec<[Vec2; 3]>,
    /// Vertex colours per triangle (`None` where its mesh has none); empty when no mesh has
    /// any.
    pub colours: Vec<Option<[Vec4; 3]>>,
    /// Tangents per triangle (`None` where its mesh has none); empty when no mesh has any.
    pub tangents: Vec<Option<[Vec4; 3]>>,
    pub materials: Vec<u32>,
    /// The moving triangles' normals and tangents at each step (the tables above hold them at
    /// the frame's own time).
    pub steps: std::sync::Arc<TriangleSteps>,
}

impl SurfaceData {
    pub(super) fn surface_point(&self, ray: &Ray, hit: &Hit, vertices: [Vec3; 3]) -> SurfacePoint {
        let position = ray.at(hit.t);
        let mut geometric_normal = (vertices[1] - vertices[0])
            .cross(vertices[2] - vertices[0])
            .normalize();
        let n = self.normals(hit);
        let mut shading_normal = if n[0] == Vec3::ZERO {
            geometric_normal
        } else {
            interpolate(n, hit.barycentric).normalize()
        };
        let back_face = geometric_normal.dot(ray.direction) > 0.0;
        if back_face {
            geometric_normal = -geometric_normal;
        }
        if shading_normal.dot(ray.direction) > 0.0 {
            shading_normal = -shading_normal;
        }
        SurfacePoint {
            position,
            geometric_normal,
            shading_normal,
            material: self.materials[hit.triangle as usize],
            back_face,
            texcoords: self.texcoords(hit.triangle, hit.barycentric),
        }
    }

    /// The vertex normals of the triangle `hit` met, where the ray met it.
    pub(super) fn normals(&self, hit: &Hit) -> [Vec3; 3] {
        let moving = self.steps.normals_at(hit.triangle, hit.moment);
        moving.unwrap_or(self.normals[hit.triangle as usize])
    }

    /// The tangents of the triangle `hit` met, where the ray met it (`None`: its mesh has
    /// none).
    pub(super) fn tangents(&self, hit: &Hit) -> Option<[Vec4; 3]> {
        match self.steps.tangents_at(hit.triangle, hit.moment) {
            Some(moving) => moving,
            None => self.tangents.get(hit.triangle as usize).copied().flatten(),
        }
    }

    /// The texture coordinates of each set at `barycentric` on `triangle`.
    pub(super) fn texcoords(&self, triangle: u32, barycentric: Vec2) -> TexcoordSets {
        let b = barycentric;
        self.triangle_texcoords(triangle)
            .map(|t| (1.0 - b.x - b.y) * t[0] + b.x * t[1] + b.y * t[2])
    }

    /// The corners' texture coordinates of each set of `triangle`.
    fn triangle_texcoords(&self, triangle: u32) -> [[Vec2; 3]; 2] {
        let t = triangle as usize;
        let second = self.texcoords1.get(t).copied().unwrap_or([Vec2::ZERO; 3]);
        [self.texcoords[t], second]
    }

    /// The pinhole's pixel footprint at `surface` in each set's texture coordinates.
    pub(super) fn texcoord_footprints(
        &self,
        triangle: u32,
        vertices: [Vec3; 3],
        surface: &SurfacePoint,
        footprint: &Footprint,
    ) -> FootprintSets {
        let dp = footprint.dp(surface.position, surface.geometric_normal);
        self.triangle_texcoords(triangle)
            .map(|texcoords| TexcoordFootprint::on_triangle(vertices, texcoords, dp))
    }
}

/// The scene's materials and their textures.
pub(super) struct Materials {
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
}

impl Materials {
    pub(super) fn get(&self, material: u32) -> &Material {
        &self.materials[material as usize]
    }
}

/// (1 - b1 - b2) a + b1 b + b2 c.
pub(super) fn interpolate(v: [Vec3; 3], b: Vec2) -> Vec3 {
    (1.0 - b.x - b.y) * v[0] + b.x * v[1] + b.y * v[2]
}

/// Where a shadow ray starts: off the surface along the facing geometric normal, by an amount
/// that grows with the magnitude of the coordinates (float spacing grows with them).
pub fn shadow_origin(p: &SurfacePoint) -> Vec3 {
    p.position + p.geometric_normal * origin_offset(p)
}

/// How far off the surface its rays start (`shadow_origin`).
fn origin_offset(p: &SurfacePoint) -> f32 {
    SHADOW_ORIGIN_OFFSET * (1.0 + p.position.abs().max_element())
}

/// Where a ray along `d` starts: `shadow_origin`, or as far behind the surface where `d`
/// goes through it (transmitted light).
pub(super) fn origin_towards(p: &SurfacePoint, d: Vec3) -> Vec3 {
    if d.dot(p.geometric_normal) < 0.0 {
        p.position - p.geometric_normal * origin_offset(p)
    } else {
        shadow_origin(p)
    }
}
