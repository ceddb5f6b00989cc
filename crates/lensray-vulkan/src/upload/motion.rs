//! The meshes that move while the shutter is open (`lensray_core::scene::motion::ObjectMotion`),
//! as the shaders read them (shaders/include/scene.glsl's vertex_position): a moving vertex's
//! position holds `-(row + 1)` in w (a still one's holds 1), and the scene group's
//! `motion_vertices` holds row r's positions at each step from `3 r MOTION_STEPS`, then its
//! normals, then its tangents. A moving light's position names its row the same way, which
//! holds its positions, then its directions. The CPU reference keeps the same steps per triangle
//! (lensray-core's reference/steps.rs) and interpolates them the same way.

use glam::{Vec3A, Vec4};
use lensray_core::interface::GpuLight;
use lensray_core::interface::MOTION_STEPS;
use lensray_core::scene::motion::{LightSteps, MeshSteps};
use obvhs::aabb::Aabb;

const STEPS: usize = MOTION_STEPS as usize;

/// Marks the vertices of the moving mesh `steps` (which start at `base` in `positions`) with
/// their rows, and appends their positions, normals and tangents at each step to
/// `motion_vertices` (zeros for what the mesh lacks).
pub(super) fn push_moving_mesh(
    positions: &mut [[f32; 4]],
    motion_vertices: &mut Vec<[f32; 4]>,
    base: usize,
    steps: &MeshSteps,
) {
    assert_eq!(steps.steps.len(), STEPS, "one pose per step");
    for i in 0..steps.steps[0].positions.len() {
        let row = motion_vertices.len() / (3 * STEPS);
        // Exact: rows stay below 2^24, as vertices do.
        positions[base + i][3] = -((row + 1) as f32);
        let step = |k: usize| &steps.steps[k];
        for k in 0..STEPS {
            motion_vertices.push(step(k).positions[i].extend(1.0).to_array());
        }
        for k in 0..STEPS {
            let normal = step(k).normals.get(i).map_or(Vec4::ZERO, |n| n.extend(0.0));
            motion_vertices.push(normal.to_array());
        }
        for k in 0..STEPS {
            let tangent = step(k).tangents.get(i).copied().unwrap_or(Vec4::ZERO);
            motion_vertices.push(tangent.to_array());
        }
    }
}

/// Marks the moving light `steps` (`light`, flattened) with its row, and appends its positions
/// and directions at each step (and a row's third attribute, zeros) to `motion_vertices`.
pub(super) fn push_moving_light(
    light: &mut GpuLight,
    motion_vertices: &mut Vec<[f32; 4]>,
    steps: &LightSteps,
) {
    assert_eq!(steps.steps.len(), STEPS, "one pose per step");
    let row = motion_vertices.len() / (3 * STEPS);
    light.position[3] = -((row + 1) as f32);
    motion_vertices.extend(
        steps
            .steps
            .iter()
            .map(|l| l.position.extend(1.0).to_array()),
    );
    motion_vertices.extend(
        steps
            .steps
            .iter()
            .map(|l| l.direction.extend(0.0).to_array()),
    );
    motion_vertices.extend(std::iter::repeat_n([0.0; 4], STEPS));
}

/// Whether the vertex whose flattened position is `position` moves while the shutter is open.
pub(crate) fn vertex_moves(position: &[f32; 4]) -> bool {
    position[3] < 0.0
}

/// The box triangle `triangle` (its vertex `indices` into `positions`) sweeps while the shutter
/// is open: its vertices at every step (`motion_vertices`); `None` where it stands still.
pub(crate) fn swept_box(
    positions: &[[f32; 4]],
    indices: &[u32],
    motion_vertices: &[[f32; 4]],
    triangle: usize,
) -> Option<Aabb> {
    let corners = &indices[3 * triangle..3 * triangle + 3];
    if !corners
        .iter()
        .any(|&i| vertex_moves(&positions[i as usize]))
    {
        return None;
    }
    let mut swept = Aabb::empty();
    for &i in corners {
        let position = positions[i as usize];
        if vertex_moves(&position) {
            let row = (-position[3]) as usize - 1;
            for step in &motion_vertices[3 * STEPS * row..3 * STEPS * row + STEPS] {
                swept.extend(Vec3A::from_slice(&step[..3]));
            }
        } else {
            swept.extend(Vec3A::from_slice(&position[..3]));
        }
    }
    Some(swept)
}
