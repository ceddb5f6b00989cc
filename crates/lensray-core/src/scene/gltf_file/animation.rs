//! A camera's animation read from the file's `animations`: the first animation whose channels
//! move the camera's node or one of its ancestors (translation, rotation, scale), with every
//! node of the chain from the scene root down; and every node's tracks (`node_tracks`), which
//! move meshes and lights (`scene::motion`). An animation whose data is bad (accessors of the wrong
//! kind or past their buffers, counts that differ, times that do not increase, values that are
//! not finite) is skipped with one notice, never an error: the file still renders.

use glam::{DMat4, DQuat, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::util::ReadOutputs;
use gltf::animation::{Interpolation, Property};

use super::nodes::check_accessor;
use crate::scene::camera_animation::{
    AnimatedNode, AnimationTrack, CameraAnimation, TrackInterpolation, TrackValue,
};

/// An animation as a line names it: "animation I ('NAME')".
pub(super) fn animation_name(animation: &gltf::Animation) -> String {
    match animation.name() {
        Some(name) => format!("animation {} ('{name}')", animation.index()),
        None => format!("animation {}", animation.index()),
    }
}

/// What the file's animations do to one camera.
pub(super) struct CameraAnimations {
    /// The animation played: the first that moves the camera and reads well.
    pub played: Option<CameraAnimation>,
    /// The indices of every animation that moves the camera.
    pub moving: Vec<usize>,
    /// One line for each that moves it and is not played: bad ones (skipped) and those after
    /// the first.
    pub notices: Vec<String>,
}

/// The animations of the camera whose node chain (root first, the camera's node last) is
/// `chain`.
pub(super) fn camera_animation(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    chain: &[usize],
    camera: &str,
) -> CameraAnimations {
    let mut notices = Vec::new();
    let mut played: Option<CameraAnimation> = None;
    let mut moving = Vec::new();
    for animation in document.animations() {
        let moves_chain = animation.channels().any(|c| {
            chain.contains(&c.target().node().index())
                && c.target().property() != Property::MorphTargetWeights
        });
        if !moves_chain {
            continue;
        }
        moving.push(animation.index());
        let name = animation_name(&animation);
        match read_chain(document, buffers, &animation, chain) {
            Err(e) => notices.push(format!(
                "{name} moves camera '{camera}' but {e}: the animation is skipped"
            )),
            Ok(nodes) => match &played {
                Some(first) => notices.push(format!(
                    "{name} also moves camera '{camera}'; lensray plays the first that does, {}",
                    first.name
                )),
                None => played = CameraAnimation::new(name, nodes),
            },
        }
    }
    CameraAnimations {
        played,
        moving,
        notices,
    }
}

/// The nodes of `chain` with the tracks `animation` gives them, or what is wrong with one.
fn read_chain(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    animation: &gltf::Animation,
    chain: &[usize],
) -> Result<Vec<AnimatedNode>, String> {
    let mut nodes: Vec<AnimatedNode> = chain
        .iter()
        .filter_map(|&i| document.nodes().nth(i))
        .map(|node| rest_node(&node))
        .collect();
    for channel in animation.channels() {
        let target = channel.target();
        let Some(at) = chain.iter().position(|&i| i == target.node().index()) else {
            continue;
        };
        let node = &mut nodes[at];
        let what = |e: String| {
            format!(
                "its channel {} (node {} {:?}) {e}",
                channel.index(),
                target.node().index(),
                target.property()
            )
        };
        match target.property() {
            Property::Translation => {
                node.translation = Some(read_track(&channel, buffers).map_err(what)?)
            }
            Property::Rotation => {
                node.rotation = Some(read_track(&channel, buffers).map_err(what)?)
            }
            Property::Scale => node.scale = Some(read_track(&channel, buffers).map_err(what)?),
            Property::MorphTargetWeights => {}
        }
    }
    Ok(nodes)
}

/// `node` at rest, no track moving it.
fn rest_node(node: &gltf::Node) -> AnimatedNode {
    let transform = node.transform();
    let (t, r, s) = transform.clone().decomposed();
    AnimatedNode {
        rest: DMat4::from_cols_array_2d(&transform.matrix().map(|c| c.map(f64::from))),
        rest_trs: (
            DVec3::from(t.map(f64::from)),
            DQuat::from_array(r.map(f64::from)),
            DVec3::from(s.map(f64::from)),
        ),
        translation: None,
        rotation: None,
        scale: None,
    }
}

/// Every node with the tracks of the file's animations: all of them play at once, on one
/// timeline, the first (in the file's order) that moves a node's translation, rotation or
/// scale moving it.
pub(super) struct NodeTracks {
    /// By node index.
    pub nodes: Vec<AnimatedNode>,
    /// By node index: the animations whose tracks move it.
    pub movers: Vec<Vec<usize>>,
    /// One line for each animation skipped (bad data) or overruled on a node.
    pub notices: Vec<String>,
}

/// The tracks every animation gives the nodes (morph weights aside).
pub(super) fn node_tracks(document: &gltf::Document, buffers: &[Vec<u8>]) -> NodeTracks {
    let mut tracks = NodeTracks {
        nodes: document.nodes().map(|n| rest_node(&n)).collect(),
        movers: vec![Vec::new(); document.nodes().len()],
        notices: Vec::new(),
    };
    for animation in document.animations() {
        let mut moved: Vec<usize> = animation
            .channels()
            .filter(|c| c.target().property() != Property::MorphTargetWeights)
            .map(|c| c.target().node().index())
            .collect();
        moved.sort_unstable();
        moved.dedup();
        let name = animation_name(&animation);
        let read = match read_chain(document, buffers, &animation, &moved) {
            Ok(read) => read,
            Err(e) => {
                tracks
                    .notices
                    .push(format!("{name} {e}: the animation is skipped"));
                continue;
            }
        };
        let mut overruled = false;
        for (&i, node) in moved.iter().zip(read) {
            let into = &mut tracks.nodes[i];
            let mut took = false;
            for (mine, theirs) in [
                (&mut into.translation, node.translation),
                (&mut into.scale, node.scale),
            ] {
                match (mine.is_some(), theirs) {
                    (false, Some(track)) => (*mine, took) = (Some(track), true),
                    (true, Some(_)) => overruled = true,
                    _ => {}
                }
            }
            match (into.rotation.is_some(), node.rotation) {
                (false, Some(track)) => (into.rotation, took) = (Some(track), true),
                (true, Some(_)) => overruled = true,
                _ => {}
            }
            if took {
                tracks.movers[i].push(animation.index());
            }
        }
        if overruled {
            tracks.notices.push(format!(
                "{name} moves a node an earlier animation moves too: the earlier one moves it"
            ));
        }
    }
    tracks
}

/// A value a channel's output accessor holds, read from its elements.
trait ChannelOutput: TrackValue + Sized {
    /// The values of `outputs`, or `None` when they are not of this kind.
    fn from_outputs(outputs: ReadOutputs) -> Option<Vec<Self>>;
    /// Whether `accessor` holds this kind of value in a type the reader converts.
    fn fits(accessor: &gltf::Accessor) -> bool;
    /// Whether `value` may be a key's value (a rotation must not be zero).
    fn is_key(value: &Self) -> bool;
}

impl ChannelOutput for DVec3 {
    fn from_outputs(outputs: ReadOutputs) -> Option<Vec<Self>> {
        match outputs {
            ReadOutputs::Translations(v) | ReadOutputs::Scales(v) => {
                Some(v.map(|p| DVec3::from(p.map(f64::from))).collect())
            }
            _ => None,
        }
    }

    fn fits(accessor: &gltf::Accessor) -> bool {
        accessor.dimensions() == Dimensions::Vec3 && accessor.data_type() == DataType::F32
    }

    fn is_key(_: &Self) -> bool {
        true
    }
}

impl ChannelOutput for DQuat {
    fn from_outputs(outputs: ReadOutputs) -> Option<Vec<Self>> {
        match outputs {
            ReadOutputs::Rotations(r) => Some(
                r.into_f32()
                    .map(|q| DQuat::from_array(q.map(f64::from)))
                    .collect(),
            ),
            _ => None,
        }
    }

    fn fits(accessor: &gltf::Accessor) -> bool {
        accessor.dimensions() == Dimensions::Vec4
            && matches!(
                accessor.data_type(),
                DataType::F32 | DataType::I8 | DataType::U8 | DataType::I16 | DataType::U16
            )
    }

    fn is_key(value: &Self) -> bool {
        value.length_squared() > 1e-12
    }
}

/// The track of `channel`, its accessors checked before they are read.
fn read_track<T: ChannelOutput>(
    channel: &gltf::animation::Channel,
    buffers: &[Vec<u8>],
) -> Result<AnimationTrack<T>, String> {
    let sampler = channel.sampler();
    let (input, output) = (sampler.input(), sampler.output());
    check_accessor(&input, buffers)?;
    check_accessor(&output, buffers)?;
    if input.dimensions() != Dimensions::Scalar || input.data_type() != DataType::F32 {
        return Err(format!(
            "has key times of {:?} {:?}, not float scalars",
            input.dimensions(),
            input.data_type()
        ));
    }
    if !T::fits(&output) {
        return Err(format!(
            "has values of {:?} {:?}, which glTF does not allow for it",
            output.dimensions(),
            output.data_type()
        ));
    }
    let reader = channel.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let times: Vec<f64> = reader
        .read_inputs()
        .ok_or("has no key times")?
        .map(f64::from)
        .collect();
    let values = reader
        .read_outputs()
        .and_then(T::from_outputs)
        .ok_or("has no values")?;
    let interpolation = match sampler.interpolation() {
        Interpolation::Step => TrackInterpolation::Step,
        Interpolation::Linear => TrackInterpolation::Linear,
        Interpolation::CubicSpline => TrackInterpolation::CubicSpline,
    };
    let keys_are_values = interpolation != TrackInterpolation::CubicSpline;
    let mut key_values = values
        .iter()
        .enumerate()
        .filter(|(i, _)| keys_are_values || i % 3 == 1);
    if let Some((i, _)) = key_values.find(|(_, v)| !T::is_key(v)) {
        return Err(format!("has a zero rotation (value number {i})"));
    }
    AnimationTrack::new(interpolation, times, values)
}

#[cfg(test)]
#[path = "animation_tests.rs"]
mod tests;
