//! A glTF file's animations in the command's renders: a sequence plays the animation of the
//! camera in use and those that move meshes and lights on its frames (frame N at N / fps
//! seconds), and a single render says that it shows them at rest.

use anyhow::{Context, Result};

use lensray_core::scene::file::SceneDescription;
use lensray_core::scene::CameraAnimation;
use lensray_core::settings::{fps, CameraTimeline, Keyframes, Settings};

/// How many animations a note names before it counts the rest.
const NAMED: usize = 4;

/// The camera animation of `description` on frames at the rate `settings` give.
fn timeline(description: &SceneDescription, settings: &Settings) -> Result<Option<CameraTimeline>> {
    let Some(animation) = description.camera_animation() else {
        return Ok(None);
    };
    let fps = fps(settings).with_context(|| format!("scene {}", description.source))?;
    Ok(Some(CameraTimeline::new(animation.clone(), fps)))
}

/// A line for what `animation` moves: its name and keys.
fn summary(animation: &CameraAnimation) -> String {
    let (start, end) = animation.time_range();
    format!(
        "{} moves the camera: keys from {start:.3} s to {end:.3} s",
        animation.name
    )
}

/// `keyframes` with the animation of the camera in use playing on the frames (at the fps of
/// `settings`), unless a key moves the camera; one line each says what plays and what does not.
pub fn play(
    keyframes: Keyframes,
    description: &SceneDescription,
    settings: &Settings,
) -> Result<Keyframes> {
    let timeline = timeline(description, settings)?;
    // Animations of the file's other cameras do not move the one in use.
    let other_cameras = description
        .cameras
        .iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != description.camera)
        .filter_map(|(_, c)| c.animation.as_ref().map(|a| a.name.as_str()));
    let mut others: Vec<&str> = description
        .other_animations
        .iter()
        .map(String::as_str)
        .chain(other_cameras)
        .collect();
    let played = timeline.as_ref().map(|t| t.animation().name.as_str());
    others.retain(|name| Some(*name) != played);
    others.sort_unstable();
    others.dedup();
    if !others.is_empty() {
        let more = match others.len().saturating_sub(NAMED) {
            0 => String::new(),
            n => format!(" and {n} more"),
        };
        eprintln!(
            "note: the file's {}{more} are not played: lensray plays the animation of the camera in use and those that move meshes and lights (skins and morph targets render at rest)",
            others[..others.len().min(NAMED)].join(", ")
        );
    }
    let Some(timeline) = timeline else {
        return Ok(keyframes);
    };
    let (first, last) = timeline.frame_range();
    let line = format!(
        "{}, frames {first} to {last} at {} fps (frame N at N / fps seconds)",
        summary(timeline.animation()),
        timeline.fps()
    );
    let (keyframes, warning) = keyframes.with_camera_timeline(timeline);
    match warning {
        Some(warning) => eprintln!("warning: {warning}"),
        None => eprintln!("{line}"),
    }
    Ok(keyframes)
}

/// Says that a render of one image shows the animated camera at rest.
pub fn note_still(description: &SceneDescription) {
    if let Some(animation) = description.camera_animation() {
        eprintln!(
            "note: {}; this render is the camera at rest, a sequence (--frames) plays it",
            summary(animation)
        );
    }
}

/// Says what the file's animations move besides cameras: played on the frames at `fps` in a
/// sequence, at rest in a single render (`fps` none).
pub fn note_motion(description: &SceneDescription, fps: Option<f64>) {
    let Some(motion) = &description.motion else {
        return;
    };
    let (start, end) = motion.time_range();
    let count = |n: usize, one: &str, many: &str| match n {
        1 => format!("1 {one}"),
        n => format!("{n} {many}"),
    };
    let what = format!(
        "{} move{} {} and {}: keys from {start:.3} s to {end:.3} s",
        motion.names.join(", "),
        if motion.names.len() == 1 { "s" } else { "" },
        count(motion.meshes.len(), "mesh", "meshes"),
        count(motion.lights.len(), "light", "lights"),
    );
    match fps {
        Some(fps) => {
            eprintln!("{what}, posed on each frame at {fps} fps (frame N at N / fps seconds)")
        }
        None => eprintln!(
            "note: {what}; this render shows them at rest (with motion blur, about 0 s), a sequence (--frames) plays them"
        ),
    }
}

/// Says what motion blur or a rolling shutter (`shutter` on) does not move in a still: the
/// camera (its keys and animation play in sequences only); the file's animated meshes and
/// lights move about 0 s.
pub fn note_shutter(description: &SceneDescription, shutter: bool, sequence: bool) {
    if !shutter {
        return;
    }
    let animated = description.motion.as_ref();
    if !sequence {
        let meshes = match animated {
            Some(_) => "; the file's animated meshes and lights move as on frame 0 of a sequence (about 0 s)",
            None => "",
        };
        eprintln!("note: motion blur and a rolling shutter move the camera by its keys or animation, which play in sequences (--frames): in this render the camera stands still{meshes}");
    }
}
