//! Smooth vertex normals for meshes that have none: each corner's normal is the angle-weighted
//! average of the face normals around its vertex (Thürmer and Wüthrich's weights: the face's
//! angle at the vertex), over the faces whose normals lie within a crease angle of the corner's
//! own face. Corners of one vertex whose normals differ become separate vertices, so a crease
//! stays sharp. Meshes with normals keep them.

use std::collections::HashMap;

use glam::Vec3;

use super::{Mesh, Scene};

impl Scene {
    /// Gives every mesh without normals smooth ones, creased at `crease_degrees` (0 to 180);
    /// returns how many meshes it changed.
    pub fn smooth_normals(&mut self, crease_degrees: f64) -> usize {
        let cos_crease = crease_degrees.clamp(0.0, 180.0).to_radians().cos() as f32;
        let mut changed = 0;
        for mesh in self.meshes.iter_mut().filter(|m| m.normals.is_empty()) {
            smooth_mesh(mesh, cos_crease);
            changed += 1;
        }
        changed
    }
}

/// A unit face normal (zero for a degenerate face) and the face's angle at each corner.
fn face_frame(mesh: &Mesh, triangle: [u32; 3]) -> (Vec3, [f32; 3]) {
    let p = triangle.map(|i| mesh.positions[i as usize]);
    let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    let angles = std::array::from_fn(|k| {
        let a = p[(k + 1) % 3] - p[k];
        let b = p[(k + 2) % 3] - p[k];
        a.angle_between(b)
    });
    (normal, angles.map(|a| if a.is_finite() { a } else { 0.0 }))
}

fn smooth_mesh(mesh: &mut Mesh, cos_crease: f32) {
    let frames: Vec<(Vec3, [f32; 3])> = mesh
        .triangles
        .iter()
        .map(|&t| face_frame(mesh, t))
        .collect();
    // The faces around each vertex, with the corner's index in the face.
    let mut around: Vec<Vec<(usize, usize)>> = vec![Vec::new(); mesh.positions.len()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for (k, &v) in t.iter().enumerate() {
            around[v as usize].push((f, k));
        }
    }
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut texcoords = Vec::new();
    let mut texcoords1 = Vec::new();
    let mut index: HashMap<(u32, [u32; 3]), u32> = HashMap::new();
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    for (f, t) in mesh.triangles.iter().enumerate() {
        let own = frames[f].0;
        let corner = |k: usize| {
            let v = t[k];
            let sum: Vec3 = around[v as usize]
                .iter()
                .filter(|&&(g, _)| own == Vec3::ZERO || frames[g].0.dot(own) >= cos_crease)
                .map(|&(g, corner)| frames[g].0 * frames[g].1[corner])
                .sum();
            // A corner with no usable neighbour keeps its face's normal (or +z if degenerate).
            let normal =
                sum.try_normalize()
                    .unwrap_or(if own == Vec3::ZERO { Vec3::Z } else { own });
            (v, normal)
        };
        let corners: [u32; 3] = std::array::from_fn(|k| {
            let (v, normal) = corner(k);
            *index
                .entry((v, normal.to_array().map(f32::to_bits)))
                .or_insert_with(|| {
                    positions.push(mesh.positions[v as usize]);
                    normals.push(normal);
                    if let Some(&uv) = mesh.texcoords.get(v as usize) {
                        texcoords.push(uv);
                    }
                    if let Some(&uv) = mesh.texcoords1.get(v as usize) {
                        texcoords1.push(uv);
                    }
                    (positions.len() - 1) as u32
                })
        });
        triangles.push(corners);
    }
    mesh.positions = positions;
    mesh.normals = normals;
    mesh.texcoords = texcoords;
    mesh.texcoords1 = texcoords1;
    mesh.triangles = triangles;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's 12 triangles around shared corners (8 vertices).
    fn cube() -> Mesh {
        let positions = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        Mesh {
            colours: Vec::new(),
            tangents: Vec::new(),
            name: "cube".into(),
            positions,
            normals: Vec::new(),
            material_ids: vec![0; triangles.len()],
            triangles,
            ..Default::default()
        }
    }

    #[test]
    fn a_crease_below_the_dihedral_angle_keeps_a_cube_faceted() {
        let mut scene = Scene {
            meshes: vec![cube()],
            materials: vec![Default::default()],
            ..Default::default()
        };
        assert_eq!(scene.smooth_normals(60.0), 1);
        let mesh = &scene.meshes[0];
        // Each face's corners carry its own axis normal: 6 faces x 4 corners.
        assert_eq!(mesh.positions.len(), 24);
        for t in &mesh.triangles {
            let p = t.map(|i| mesh.positions[i as usize]);
            let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            for &i in t {
                assert!((mesh.normals[i as usize] - face).length() < 1e-6);
            }
        }
    }

    #[test]
    fn a_crease_above_it_averages_by_angle() {
        let mut scene = Scene {
            meshes: vec![cube()],
            materials: vec![Default::default()],
            ..Default::default()
        };
        scene.smooth_normals(100.0);
        let mesh = &scene.meshes[0];
        // Every corner sees three faces at 90 degrees each: the normal points out diagonally.
        assert_eq!(mesh.positions.len(), 8);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let out = (*p - Vec3::splat(0.5)).normalize();
            assert!((*n - out).length() < 1e-5, "{p}: {n} != {out}");
        }
    }
}
