//! The triangles that move while the shutter is open (`scene::motion::ObjectMotion`), in the
//! renderer's triangle order: each one's corners at the span's `MOTION_STEPS` moments. A ray
//! at moment m in [0, 1] sees a moving triangle's corners, normals and tangents interpolated
//! linearly between the two steps around m, as Embree interpolates the time steps it
//! intersects (`accel.rs`), so what the shading reads is what the ray met.

use glam::{Vec3, Vec3A, Vec4};

use crate::interface::MOTION_STEPS;

/// How many steps a moving triangle keeps.
pub(super) const STEPS: usize = MOTION_STEPS as usize;

/// A triangle's three corners at each step.
pub(super) type Stepped<T> = [[T; 3]; STEPS];

/// The moving triangles' corners at each step; empty when nothing moves.
#[derive(Clone, Debug, Default)]
pub(super) struct TriangleSteps {
    /// Per triangle of the renderer: its row in the tables below, or [`NOT_MOVING`]; empty
    /// when no triangle moves.
    rows: Vec<u32>,
    pub(super) vertices: Vec<Stepped<Vec3A>>,
    /// All zero where the mesh has no normals.
    normals: Vec<Stepped<Vec3>>,
    /// `None` where the mesh has no tangents.
    tangents: Vec<Option<Stepped<Vec4>>>,
}

/// The row of a triangle that stands still.
const NOT_MOVING: u32 = u32::MAX;

impl TriangleSteps {
    /// Appends triangle `triangle` (the renderer's next) standing still.
    pub(super) fn push_still(&mut self, triangle: usize) {
        if !self.rows.is_empty() {
            self.rows.push(NOT_MOVING);
        }
        debug_assert!(self.rows.is_empty() || self.rows.len() == triangle + 1);
    }

    /// Appends triangle `triangle` (the renderer's next) moving through `vertices`, with its
    /// normals and tangents at each step.
    pub(super) fn push_moving(
        &mut self,
        triangle: usize,
        vertices: Stepped<Vec3A>,
        normals: Stepped<Vec3>,
        tangents: Option<Stepped<Vec4>>,
    ) {
        if self.rows.is_empty() {
            self.rows = vec![NOT_MOVING; triangle];
        }
        self.rows.push(self.vertices.len() as u32);
        self.vertices.push(vertices);
        self.normals.push(normals);
        self.tangents.push(tangents);
    }

    /// The row of `triangle` in the tables, where it moves.
    pub(super) fn row(&self, triangle: u32) -> Option<usize> {
        let row = *self.rows.get(triangle as usize)?;
        (row != NOT_MOVING).then_some(row as usize)
    }

    /// The corners of moving row `row` at moment `moment`.
    pub(super) fn vertices_at(&self, row: usize, moment: f32) -> [Vec3A; 3] {
        between(&self.vertices[row], moment)
    }

    /// The vertex normals of `triangle` at `moment`, where it moves.
    pub(super) fn normals_at(&self, triangle: u32, moment: f32) -> Option<[Vec3; 3]> {
        Some(between(&self.normals[self.row(triangle)?], moment))
    }

    /// The tangents of `triangle` at `moment`, where it moves (`Some(None)`: it moves
    /// without tangents).
    pub(super) fn tangents_at(&self, triangle: u32, moment: f32) -> Option<Option<[Vec4; 3]>> {
        let row = self.row(triangle)?;
        Some(self.tangents[row].as_ref().map(|t| between(t, moment)))
    }

    /// Bytes of the tables.
    pub(super) fn bytes(&self) -> u64 {
        (std::mem::size_of_val(self.rows.as_slice())
            + std::mem::size_of_val(self.vertices.as_slice())
            + std::mem::size_of_val(self.normals.as_slice())
            + std::mem::size_of_val(self.tangents.as_slice())) as u64
    }
}

/// The steps' corners interpolated at `moment` in [0, 1]: linearly between the two steps around
/// it, as Embree's motion blur (and `CameraMotion::pose_at`'s step and fraction).
fn between<T>(steps: &Stepped<T>, moment: f32) -> [T; 3]
where
    T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    let (i, f) = crate::camera::motion::step_at(moment, STEPS);
    std::array::from_fn(|c| steps[i][c] * (1.0 - f) + steps[i + 1][c] * f)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle sliding 7 m along x over the span (1 m a step) is at x + 7 m at moment 1, and
    /// x + 3.5 m half way between steps 3 and 4; a still one has no row.
    #[test]
    fn a_moving_triangle_is_between_its_steps() {
        let at = |x: f32| {
            [
                Vec3A::new(x, 0.0, 0.0),
                Vec3A::new(x + 1.0, 0.0, 0.0),
                Vec3A::Y,
            ]
        };
        let mut steps = TriangleSteps::default();
        steps.push_still(0);
        steps.push_moving(
            1,
            std::array::from_fn(|k| at(k as f32)),
            [[Vec3::Z; 3]; STEPS],
            None,
        );
        steps.push_still(2);
        assert_eq!(
            (steps.row(0), steps.row(1), steps.row(2)),
            (None, Some(0), None)
        );
        assert_eq!(steps.vertices_at(0, 1.0), at(7.0));
        assert_eq!(steps.vertices_at(0, 0.5), at(3.5));
        assert_eq!(steps.vertices_at(0, 0.0), at(0.0));
        assert_eq!(steps.normals_at(1, 0.3), Some([Vec3::Z; 3]));
        assert_eq!(steps.tangents_at(1, 0.3), Some(None));
        assert_eq!(steps.normals_at(2, 0.3), None);
    }

    /// Embree meets a moving triangle where its steps have it at the ray's moment, and the
    /// hit's vertices are those: a unit triangle in z = 0 sliding 7 m along +x over the span
    /// stops a ray down the z axis at x = 0.25 early in the span and not late, and one at
    /// x = 6.75 late and not early; single-sided, it is faced at its moment too.
    #[test]
    fn a_ray_meets_a_moving_triangle_where_its_moment_has_it() {
        use super::super::accel::Accel;
        use glam::Vec3;
        let at = |x: f32| {
            [
                Vec3A::new(x, 0.0, 0.0),
                Vec3A::new(x + 1.0, 0.0, 0.0),
                Vec3A::new(x, 1.0, 0.0),
            ]
        };
        let mut steps = TriangleSteps::default();
        steps.push_moving(
            0,
            std::array::from_fn(|k| at(k as f32)),
            [[Vec3::Z; 3]; STEPS],
            None,
        );
        let steps = std::sync::Arc::new(steps);
        for single_sided in [false, true] {
            let accel =
                Accel::build_with_tests(&[at(0.0)], &[], &[single_sided], None, steps.clone());
            let down = |x: f32, moment: f32| {
                let origin = Vec3::new(x, 0.25, 1.0);
                accel.closest_hit(origin, Vec3::NEG_Z, (0.0, 10.0), None, moment)
            };
            let hit = down(0.25, 0.0).expect("early, at x = 0.25");
            assert!((hit.t - 1.0).abs() < 1e-6 && hit.moment == 0.0, "{hit:?}");
            assert_eq!(accel.hit_vertices(&hit), at(0.0).map(Vec3::from));
            assert!(
                down(0.25, 1.0).is_none(),
                "late, the triangle has left x = 0.25"
            );
            let late = down(6.75, 13.0 / 14.0).expect("late, at x = 6.75");
            let expected = at(6.5).map(Vec3::from);
            let got = accel.hit_vertices(&late);
            assert!(
                (0..3).all(|c| (got[c] - expected[c]).length() < 1e-5),
                "{got:?}"
            );
            assert!(down(6.75, 0.2).is_none());
            // From below, a single-sided triangle lets the ray through at every moment.
            let up = accel.closest_hit(
                Vec3::new(6.75, 0.25, -1.0),
                Vec3::Z,
                (0.0, 10.0),
                None,
                13.0 / 14.0,
            );
            assert_eq!(up.is_none(), single_sided);
        }
    }
}
