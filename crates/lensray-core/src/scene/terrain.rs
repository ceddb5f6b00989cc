//! The terrain benchmark scene: a 513 x 513 height field and 700 icospheres on it, 748,288
//! triangles, the size of the evaluation scenes that the software traversal is measured on.
//! Deterministic: every position comes from closed-form functions and a fixed integer hash.

use glam::Vec3;

use super::file::SceneDescription;
use super::generate::{camera_settings, describe, hue, SceneBuilder};
use super::Mesh;

/// Vertices along each side of the height field.
pub const TERRAIN_GRID: u32 = 513;
/// Icospheres scattered over the height field.
pub const TERRAIN_SPHERES: u32 = 700;
/// Subdivisions of each icosphere (20 * 4^2 = 320 triangles).
pub const TERRAIN_SPHERE_LEVEL: u32 = 2;
/// Side of the square height field, metres.
const SIDE: f32 = 40.0;

/// The height of the terrain at (x, z): a few octaves of sines, up to ~2.5 m.
fn height(x: f32, z: f32) -> f32 {
    1.2 * (0.21 * x).sin() * (0.17 * z).cos()
        + 0.6 * (0.53 * x + 0.31 * z).sin()
        + 0.25 * (1.7 * x).cos() * (1.3 * z).sin()
        + 0.08 * (4.1 * x + 3.7 * z).sin()
}

/// The unit normal of [`height`]'s surface, from its gradient by central differences.
fn normal(x: f32, z: f32) -> Vec3 {
    let h = 1e-2;
    let dx = (height(x + h, z) - height(x - h, z)) / (2.0 * h);
    let dz = (height(x, z + h) - height(x, z - h)) / (2.0 * h);
    Vec3::new(-dx, 1.0, -dz).normalize()
}

/// The height field: `TERRAIN_GRID`^2 vertices over [-SIDE/2, SIDE/2]^2, two triangles a cell,
/// wound to face +y.
fn height_field(material: u32) -> Mesh {
    let cells = TERRAIN_GRID - 1;
    let at = |i: u32| -0.5 * SIDE + SIDE * i as f32 / cells as f32;
    let mut positions = Vec::with_capacity((TERRAIN_GRID * TERRAIN_GRID) as usize);
    let mut normals = Vec::with_capacity(positions.capacity());
    for j in 0..TERRAIN_GRID {
        for i in 0..TERRAIN_GRID {
            let (x, z) = (at(i), at(j));
            positions.push(Vec3::new(x, height(x, z), z));
            normals.push(normal(x, z));
        }
    }
    let index = |i: u32, j: u32| j * TERRAIN_GRID + i;
    let mut triangles = Vec::with_capacity(2 * (cells * cells) as usize);
    for j in 0..cells {
        for i in 0..cells {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            triangles.push([a, c, b]);
            triangles.push([a, d, c]);
        }
    }
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: "terrain".into(),
        material_ids: vec![material; triangles.len()],
        positions,
        normals,
        triangles,
        ..Default::default()
    }
}

/// A unit icosphere: the icosahedron with each triangle split in four `level` times, vertices
/// pushed onto the sphere (shared edges are split once: the mesh is closed).
pub fn icosphere(level: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints = std::collections::BTreeMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    (positions, triangles)
}

/// SplitMix32-style integer hash to [0, 1): the spheres' places and sizes.
fn unit_hash(i: u32, salt: u32) -> f32 {
    let mut x = i.wrapping_mul(0x9e37_79b9) ^ salt.wrapping_mul(0x85eb_ca6b);
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    (x >> 8) as f32 / (1u32 << 24) as f32
}

/// The terrain scene: the height field, `TERRAIN_SPHERES` icospheres of radius 0.15 to 0.6 m
/// resting on it in ten hues, seen obliquely from above one corner, lit by one point light.
pub fn terrain() -> SceneDescription {
    let mut b = SceneBuilder::new();
    let ground = b.material("ground", Vec3::new(0.45, 0.5, 0.35), Vec3::ZERO);
    let colours: Vec<u32> = (0..10)
        .map(|i| {
            b.material(
                &format!("hue_{i}"),
                hue(i as f32 / 10.0, 0.8, 0.85),
                Vec3::ZERO,
            )
        })
        .collect();
    b.add(height_field(ground));
    let (unit_positions, triangles) = icosphere(TERRAIN_SPHERE_LEVEL);
    for i in 0..TERRAIN_SPHERES {
        let x = (unit_hash(i, 1) - 0.5) * 0.9 * SIDE;
        let z = (unit_hash(i, 2) - 0.5) * 0.9 * SIDE;
        let radius = 0.15 + 0.45 * unit_hash(i, 3);
        let center = Vec3::new(x, height(x, z) + 0.8 * radius, z);
        let material = colours[(i % 10) as usize];
        b.add(Mesh {
            colours: Vec::new(),
            tangents: Vec::new(),
            name: format!("sphere_{i}"),
            positions: unit_positions
                .iter()
                .map(|&n| center + radius * n)
                .collect(),
            normals: unit_positions.clone(),
            material_ids: vec![material; triangles.len()],
            triangles: triangles.clone(),
            ..Default::default()
        });
    }
    let scene = b.finish();
    let subject = Vec3::new(0.0, height(0.0, 0.0), 0.0);
    let camera = camera_settings(
        Vec3::new(-14.0, 9.0, 16.0),
        subject,
        subject,
        50.0,
        0.05,
        scene.bounds(),
    );
    describe(
        scene,
        camera,
        16,
        [0.55, 0.7, 0.9],
        Some((Vec3::new(-10.0, 25.0, 10.0), [2000.0, 2000.0, 2000.0])),
        "generated terrain",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terrain_has_the_evaluation_scenes_triangle_count() {
        let (positions, triangles) = icosphere(TERRAIN_SPHERE_LEVEL);
        assert_eq!((positions.len(), triangles.len()), (162, 320));
        for p in &positions {
            assert!((p.length() - 1.0).abs() < 1e-6);
        }
        let description = terrain();
        assert_eq!(description.scene.triangle_count(), 748_288);
        // Deterministic: a second build is identical.
        let again = terrain();
        assert_eq!(
            description.scene.meshes[700].positions,
            again.scene.meshes[700].positions
        );
    }
}
