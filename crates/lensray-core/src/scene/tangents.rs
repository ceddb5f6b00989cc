//! Tangents for normal maps where a file gives none: MikkTSpace (the `mikktspace` crate), the
//! algorithm glTF prescribes, over the mesh's positions, normals (the faces' where it has none)
//! and the texture coordinate set the normal map reads.
//!
//! glTF's v runs down the image while its normal maps' y runs up it, so the bitangent
//! cross(normal, tangent) w must point along -dp/dv: MikkTSpace's sign, which follows +dp/dv, is
//! negated (as three.js does for glTF). MikkTSpace gives a tangent per triangle corner; a vertex
//! whose corners get different tangents (a seam in the texture coordinates, a mirrored half) is
//! split into one vertex per tangent.

use std::collections::HashMap;

use glam::{Vec3, Vec4};

use super::{Mesh, Scene};

/// Gives tangents to every mesh of `scene` that has texture coordinates, no tangents and a
/// triangle whose material has a normal map (the base's, or else the clear coat's), in the set
/// that map reads (its first material's, where several differ). Returns the names of the
/// meshes whose normal maps stay unread: without texture coordinates, without a triangle whose
/// corners are three positions, or where MikkTSpace finds no tangent.
pub fn generate_missing(scene: &mut Scene) -> Vec<String> {
    let mut unread = Vec::new();
    for mesh in &mut scene.meshes {
        let normal_map = mesh.material_ids.iter().find_map(|&m| {
            let material = &scene.materials[m as usize];
            material
                .normal_texture
                .or(material.clearcoat_normal_texture)
        });
        let Some(normal_map) = normal_map else {
            continue;
        };
        if !mesh.tangents.is_empty() {
            continue;
        }
        if !generate_in_set(mesh, normal_map.texcoord_set as usize) {
            unread.push(mesh.name.clone());
        }
    }
    unread
}

/// `generate_missing`, with one notice naming the meshes whose normal maps stay unread.
pub fn unread_notice(scene: &mut Scene) -> Option<String> {
    let unread = generate_missing(scene);
    (!unread.is_empty()).then(|| {
        format!(
            "renders without the normal maps of {} (no texture coordinates, or no triangle with three \
             distinct corners, to find tangents by)",
            unread.join(", ")
        )
    })
}

/// Sets `mesh.tangents` by MikkTSpace in its first texture coordinate set, splitting vertices
/// where their corners' tangents differ; false (the mesh unchanged) where the mesh has no
/// texture coordinates or MikkTSpace fails.
pub fn generate(mesh: &mut Mesh) -> bool {
    generate_in_set(mesh, 0)
}

/// `generate` in texture coordinate set `set` (0: `texcoords`, 1: `texcoords1`).
pub fn generate_in_set(mesh: &mut Mesh, set: usize) -> bool {
    let texcoords = if set == 0 {
        &mesh.texcoords
    } else {
        &mesh.texcoords1
    };
    if texcoords.is_empty() || mesh.triangles.is_empty() {
        return false;
    }
    let mut corners = Corners {
        mesh,
        texcoords,
        tangents: vec![Vec4::ZERO; 3 * mesh.triangles.len()],
    };
    if !corners.has_proper_triangle() || !mikktspace::generate_tangents(&mut corners) {
        return false;
    }
    let tangents = corners.tangents;
    split_by_tangent(mesh, &tangents);
    true
}

/// The mesh as MikkTSpace reads it, and the tangent it gives each triangle corner.
struct Corners<'a> {
    mesh: &'a Mesh,
    /// The set the normal map reads.
    texcoords: &'a [glam::Vec2],
    tangents: Vec<Vec4>,
}

impl Corners<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.mesh.triangles[face][vert] as usize
    }

    /// Whether a triangle is left once MikkTSpace drops the degenerate ones, those with two
    /// corners at one position. With none left its generator indexes past its own tables (an
    /// overflow panic with overflow checks, memory out of bounds without).
    fn has_proper_triangle(&self) -> bool {
        self.mesh.triangles.iter().any(|t| {
            let [a, b, c] = t.map(|i| self.mesh.positions[i as usize]);
            a != b && a != c && b != c
        })
    }
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.triangles.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.vertex(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        if self.mesh.normals.is_empty() {
            let [a, b, c] = self.mesh.triangles[face].map(|i| self.mesh.positions[i as usize]);
            (b - a).cross(c - a).normalize_or_zero().to_array()
        } else {
            self.mesh.normals[self.vertex(face, vert)].to_array()
        }
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.texcoords[self.vertex(face, vert)].to_array()
    }

    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        let [x, y, z, w] = tangent;
        self.tangents[3 * face + vert] = Vec3::new(x, y, z).extend(-w);
    }
}

/// Gives `mesh` the tangent `corner_tangents[3 t + k]` at corner k of triangle t, one vertex per
/// distinct (vertex, tangent).
fn split_by_tangent(mesh: &mut Mesh, corner_tangents: &[Vec4]) {
    let count = mesh.positions.len();
    let mut tangents = vec![None; count];
    let mut added: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
    let mut copies = Vec::new();
    for (t, triangle) in mesh.triangles.iter_mut().enumerate() {
        for (k, index) in triangle.iter_mut().enumerate() {
            let tangent = corner_tangents[3 * t + k];
            match tangents[*index as usize] {
                None => tangents[*index as usize] = Some(tangent),
                Some(first) if first == tangent => {}
                Some(_) => {
                    let key = (*index, tangent.to_array().map(f32::to_bits));
                    *index = *added.entry(key).or_insert_with(|| {
                        copies.push((*index, tangent));
                        (count + copies.len() - 1) as u32
                    });
                }
            }
        }
    }
    let mut tangents: Vec<Vec4> = tangents
        .into_iter()
        .map(|t| t.unwrap_or(Vec4::ZERO))
        .collect();
    for (from, tangent) in copies {
        let i = from as usize;
        mesh.positions.push(mesh.positions[i]);
        if !mesh.normals.is_empty() {
            mesh.normals.push(mesh.normals[i]);
        }
        if !mesh.texcoords.is_empty() {
            mesh.texcoords.push(mesh.texcoords[i]);
        }
        if !mesh.texcoords1.is_empty() {
            mesh.texcoords1.push(mesh.texcoords1[i]);
        }
        if !mesh.colours.is_empty() {
            mesh.colours.push(mesh.colours[i]);
        }
        tangents.push(tangent);
    }
    mesh.tangents = tangents;
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3, Vec4};

    use super::generate;
    use crate::scene::generate::quad;

    /// A quad in the xy plane facing +z, u along +x and v down the image along -y (glTF's
    /// texture coordinates): by hand, dp/du = +x is the tangent and the bitangent the normal
    /// map's y runs along, image up, is +y = cross(+z, +x): w = +1.
    #[test]
    fn a_quads_tangent_is_its_u_direction() {
        let mut mesh = quad("q", Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 3.0, 0);
        mesh.normals = vec![Vec3::Z; mesh.positions.len()];
        mesh.texcoords = mesh
            .positions
            .iter()
            .map(|p| Vec2::new(p.x / 2.0, 1.0 - p.y / 3.0))
            .collect();
        assert!(generate(&mut mesh));
        assert_eq!(mesh.tangents.len(), mesh.positions.len(), "no vertex split");
        for (i, t) in mesh.tangents.iter().enumerate() {
            assert!(
                t.abs_diff_eq(Vec4::new(1.0, 0.0, 0.0, 1.0), 1e-6),
                "vertex {i}: tangent {t}, expected (1, 0, 0, 1)"
            );
        }
        // u along -x mirrors the texture: the tangent turns to -x and the bitangent stays up.
        for t in &mut mesh.texcoords {
            t.x = 1.0 - t.x;
        }
        assert!(generate(&mut mesh));
        for (i, t) in mesh.tangents.iter().enumerate() {
            assert!(
                t.abs_diff_eq(Vec4::new(-1.0, 0.0, 0.0, -1.0), 1e-6),
                "mirrored vertex {i}: tangent {t}, expected (-1, 0, 0, -1)"
            );
        }
    }

    #[test]
    fn without_texture_coordinates_there_is_no_tangent() {
        let mut mesh = quad("q", Vec3::ZERO, Vec3::X, Vec3::Y, 0);
        mesh.texcoords.clear();
        assert!(!generate(&mut mesh));
        assert!(mesh.tangents.is_empty());
    }
}
