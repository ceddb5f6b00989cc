//! The built-in default scene, generated in code so that `lensray` renders something without any
//! file: a row of seven coloured spheres receding in depth on a checkerboard, focused on the
//! middle (green) one, so that depth of field shows at a glance: the near spheres and the
//! checkerboard in front blur, the far ones and the ground behind blur, the subject stays sharp.

use glam::Vec3;

use super::file::SceneDescription;
use super::generate::{camera_settings, checkerboard, describe, uv_sphere, SceneBuilder};

/// What [`SceneDescription::source`] says for this scene.
pub const DEFAULT_SCENE_SOURCE: &str = "built-in default";

/// Eye of the default camera.
pub const DEFAULT_EYE: Vec3 = Vec3::new(0.0, 1.6, 8.0);

/// Centre of the sphere the default camera focuses on.
pub const DEFAULT_SUBJECT: Vec3 = Vec3::new(0.0, 0.5, 0.0);

/// Sphere radius in the default scene.
const RADIUS: f32 = 0.5;

/// Spacing of the spheres along the view direction.
const DEPTH_STEP: f32 = 1.5;

/// Centres of the seven spheres, nearest first; index 3 is [`DEFAULT_SUBJECT`]. Each is placed at
/// an evenly stepped horizontal position in the image (`x / distance` grows by 0.11 per sphere),
/// so the row runs diagonally across the frame instead of hiding behind itself.
pub fn default_sphere_centers() -> [Vec3; 7] {
    std::array::from_fn(|i| {
        let t = i as f32 - 3.0;
        let z = -DEPTH_STEP * t;
        let distance = DEFAULT_EYE.z - z;
        Vec3::new(0.11 * t * distance, RADIUS, z)
    })
}

/// The default scene: 7 spheres of 960 triangles and a 28 x 30 checkerboard of 1 m tiles, 8400
/// triangles in all. Camera: 40 degree field of view, aperture radius 0.12 m, focused at the
/// subject's distance (8.07 m along the view axis); the nearest sphere is 3.5 m away, the
/// farthest 12.5 m. 640 x 480, 16 spp, lit by a point light high up to the left (hard shadows
/// towards the back right), under a pale sky.
pub fn default_scene() -> SceneDescription {
    let mut b = SceneBuilder::new();
    let light_tile = b.material("tile_light", Vec3::splat(0.8), Vec3::ZERO);
    let dark_tile = b.material("tile_dark", Vec3::splat(0.12), Vec3::ZERO);
    b.add(checkerboard(
        "ground",
        (-14.0, 14.0),
        (-22.0, 8.0),
        0.0,
        1.0,
        [light_tile, dark_tile],
    ));
    let colours = [
        ("red", Vec3::new(0.8, 0.04, 0.04)),
        ("orange", Vec3::new(0.85, 0.3, 0.02)),
        ("yellow", Vec3::new(0.8, 0.7, 0.04)),
        ("green", Vec3::new(0.05, 0.6, 0.08)),
        ("cyan", Vec3::new(0.03, 0.55, 0.7)),
        ("blue", Vec3::new(0.06, 0.12, 0.8)),
        ("magenta", Vec3::new(0.7, 0.04, 0.6)),
    ];
    for ((name, colour), center) in colours.iter().zip(default_sphere_centers()) {
        let m = b.material(name, *colour, Vec3::ZERO);
        b.add(uv_sphere(
            &format!("sphere_{name}"),
            center,
            RADIUS,
            32,
            16,
            m,
        ));
    }
    let scene = b.finish();
    let camera = camera_settings(
        DEFAULT_EYE,
        DEFAULT_SUBJECT,
        DEFAULT_SUBJECT,
        40.0,
        0.12,
        scene.bounds(),
    );
    describe(
        scene,
        camera,
        16,
        [0.45, 0.6, 0.85],
        Some((Vec3::new(-4.0, 10.0, 5.0), [400.0, 400.0, 400.0])),
        DEFAULT_SCENE_SOURCE,
    )
}
