//! A scene with round numbers for the tests: one cube filling [-1, 1]^3, so the bounding-sphere
//! radius is sqrt(3) and the centre the origin.

use glam::Vec3;

use lensray_core::scene::generate::{cuboid, SceneBuilder};
use lensray_core::scene::Scene;

pub(crate) fn unit_cube() -> Scene {
    let mut builder = SceneBuilder::new();
    let grey = builder.material("grey", Vec3::splat(0.5), Vec3::ZERO);
    builder.add(cuboid("cube", Vec3::ZERO, Vec3::ONE, 0.0, grey));
    builder.finish()
}
