//! A file's animated meshes and lights at a frame: posed at the frame's time and loaded on the
//! render path; while the shutter is open (motion blur, a rolling shutter) the meshes that move
//! over the frame's span go with their steps, at which the path meets each at a ray's moment.

use anyhow::Result;

use crate::paths::RenderPath;
use lensray_core::scene::motion::SceneMotion;
use lensray_core::scene::Scene;
use lensray_core::settings::Shutter;

/// Poses `scene` (the scene `motion` was read with, or an earlier pose of it) at frame `frame`
/// of a sequence at `rate` frames a second (frame N at N / rate seconds) and loads it on
/// `path`, the meshes that move over the frame's span with their steps where `shutter` is open.
pub fn load_frame(
    path: &mut dyn RenderPath,
    motion: &SceneMotion,
    scene: &mut Scene,
    (frame, rate): (f64, f64),
    shutter: Option<&Shutter>,
) -> Result<()> {
    motion.pose(scene, frame / rate);
    match shutter.and_then(|shutter| shutter.object_motion(motion, frame, rate)) {
        Some(steps) => path.load_moving_scene(scene, &steps),
        None => path.load_scene(scene),
    }
}
