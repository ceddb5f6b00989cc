//! A camera moved by a glTF animation: the node chain from a scene root down to the camera's
//! node, each node's local transform at rest or moved by the animation's channels (translation,
//! rotation, scale), evaluated at a time in seconds on the file's timeline.
//!
//! The samplers are glTF 2.0's (Appendix C): `STEP` holds a key's value until the next key;
//! `LINEAR` interpolates vectors linearly and rotations by spherical linear interpolation along
//! the shorter arc; `CUBICSPLINE` is the cubic Hermite spline through the keys, its in- and
//! out-tangents (per second) scaled by the interval between the two keys, a rotation normalized
//! after. Before a track's first key its first value holds, after its last key its last.

use glam::{DMat4, DQuat, DVec3, DVec4};

/// How a track's values move between its keys (glTF's `sampler.interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackInterpolation {
    Step,
    Linear,
    CubicSpline,
}

/// A value an animation track moves: a vector (translation, scale) or a rotation.
pub trait TrackValue: Copy {
    /// The value a fraction `u` of the way from `a` to `b` (`LINEAR`).
    fn lerp(a: Self, b: Self, u: f64) -> Self;
    /// The cubic Hermite spline's value at `u` with the Hermite basis weights `h` of `v0`, the
    /// out-tangent `b0` times the interval, `v1` and the in-tangent `a1` times the interval.
    fn hermite(v0: Self, b0: Self, v1: Self, a1: Self, h: [f64; 4]) -> Self;
    /// Whether every component is finite.
    fn is_valid(&self) -> bool;
}

impl TrackValue for DVec3 {
    fn lerp(a: Self, b: Self, u: f64) -> Self {
        a + (b - a) * u
    }

    fn hermite(v0: Self, b0: Self, v1: Self, a1: Self, h: [f64; 4]) -> Self {
        v0 * h[0] + b0 * h[1] + v1 * h[2] + a1 * h[3]
    }

    fn is_valid(&self) -> bool {
        self.is_finite()
    }
}

impl TrackValue for DQuat {
    /// glTF's slerp: along the shorter arc, nearly equal rotations linearly then normalized.
    fn lerp(a: Self, b: Self, u: f64) -> Self {
        let (a, mut b) = (DVec4::from(a), DVec4::from(b));
        let mut d = a.dot(b);
        if d < 0.0 {
            b = -b;
            d = -d;
        }
        let q = if d > 0.9995 {
            a + (b - a) * u
        } else {
            let angle = d.acos();
            (a * ((1.0 - u) * angle).sin() + b * (u * angle).sin()) / angle.sin()
        };
        DQuat::from_vec4(q.normalize())
    }

    fn hermite(v0: Self, b0: Self, v1: Self, a1: Self, h: [f64; 4]) -> Self {
        let q = DVec4::from(v0) * h[0]
            + DVec4::from(b0) * h[1]
            + DVec4::from(v1) * h[2]
            + DVec4::from(a1) * h[3];
        DQuat::from_vec4(q.normalize())
    }

    fn is_valid(&self) -> bool {
        self.is_finite()
    }
}

/// One animated property of a node: key times in seconds and the values at them (for
/// `CUBICSPLINE`, three per key: in-tangent, value, out-tangent).
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationTrack<T> {
    interpolation: TrackInterpolation,
    times: Vec<f64>,
    values: Vec<T>,
}

impl<T: TrackValue> AnimationTrack<T> {
    /// A track, or what is wrong with its keys: no keys, a count of values that does not match
    /// the keys', times that are not finite or do not increase, values that are not finite.
    pub fn new(
        interpolation: TrackInterpolation,
        times: Vec<f64>,
        values: Vec<T>,
    ) -> Result<Self, String> {
        let per_key = match interpolation {
            TrackInterpolation::CubicSpline => 3,
            _ => 1,
        };
        if times.is_empty() {
            return Err("has no keys".into());
        }
        if values.len() != times.len() * per_key {
            return Err(format!(
                "has {} key times but {} values ({per_key} per key expected)",
                times.len(),
                values.len()
            ));
        }
        if let Some(t) = times.iter().find(|t| !t.is_finite()) {
            return Err(format!("has a key time {t} that is not finite"));
        }
        if let Some(w) = times.windows(2).find(|w| w[1] <= w[0]) {
            return Err(format!(
                "has key times that do not increase ({} then {})",
                w[0], w[1]
            ));
        }
        if let Some(i) = values.iter().position(|v| !v.is_valid()) {
            return Err(format!("has a value (number {i}) that is not finite"));
        }
        Ok(Self {
            interpolation,
            times,
            values,
        })
    }

    /// The first and last key times.
    pub fn time_range(&self) -> (f64, f64) {
        (self.times[0], self.times[self.times.len() - 1])
    }

    /// The value of key `k` (for `CUBICSPLINE`, the middle of its three).
    fn key(&self, k: usize) -> T {
        match self.interpolation {
            TrackInterpolation::CubicSpline => self.values[3 * k + 1],
            _ => self.values[k],
        }
    }

    /// The value at `time` seconds.
    pub fn at(&self, time: f64) -> T {
        let last = self.times.len() - 1;
        if time <= self.times[0] {
            return self.key(0);
        }
        if time >= self.times[last] {
            return self.key(last);
        }
        let k = self.times.partition_point(|&t| t <= time) - 1;
        let interval = self.times[k + 1] - self.times[k];
        let u = (time - self.times[k]) / interval;
        match self.interpolation {
            TrackInterpolation::Step => self.key(k),
            TrackInterpolation::Linear => T::lerp(self.key(k), self.key(k + 1), u),
            TrackInterpolation::CubicSpline => {
                let (u2, u3) = (u * u, u * u * u);
                let h = [
                    2.0 * u3 - 3.0 * u2 + 1.0,
                    (u3 - 2.0 * u2 + u) * interval,
                    -2.0 * u3 + 3.0 * u2,
                    (u3 - u2) * interval,
                ];
                let out_tangent = self.values[3 * k + 2];
                let in_tangent = self.values[3 * (k + 1)];
                T::hermite(self.key(k), out_tangent, self.key(k + 1), in_tangent, h)
            }
        }
    }
}

/// A node of the chain: its transform at rest and the tracks that move it.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimatedNode {
    /// The node's local transform at rest (its matrix, or its TRS composed).
    pub rest: DMat4,
    /// The node's translation, rotation and scale at rest, where tracks replace some of them.
    pub rest_trs: (DVec3, DQuat, DVec3),
    pub translation: Option<AnimationTrack<DVec3>>,
    pub rotation: Option<AnimationTrack<DQuat>>,
    pub scale: Option<AnimationTrack<DVec3>>,
}

impl AnimatedNode {
    pub(crate) fn is_animated(&self) -> bool {
        self.translation.is_some() || self.rotation.is_some() || self.scale.is_some()
    }

    /// The node's local transform (`parent_from_node`) at `time`: T R S, each from its track
    /// where one moves it.
    pub(crate) fn parent_from_node(&self, time: f64) -> DMat4 {
        if !self.is_animated() {
            return self.rest;
        }
        let (t, r, s) = self.rest_trs;
        let t = self.translation.as_ref().map_or(t, |k| k.at(time));
        let r = self.rotation.as_ref().map_or(r, |k| k.at(time));
        let s = self.scale.as_ref().map_or(s, |k| k.at(time));
        DMat4::from_scale_rotation_translation(s, r.normalize(), t)
    }
}

/// The earliest and latest key times of the tracks of `chain`, seconds.
pub(crate) fn chain_time_range(chain: &[AnimatedNode]) -> (f64, f64) {
    let ranges = chain.iter().flat_map(|n| {
        [
            n.translation.as_ref().map(AnimationTrack::time_range),
            n.rotation.as_ref().map(AnimationTrack::time_range),
            n.scale.as_ref().map(AnimationTrack::time_range),
        ]
    });
    ranges
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (s, e)| {
            (a.min(s), b.max(e))
        })
}

/// The last node of `chain` (a scene root first) at `time` seconds in a world scaled by
/// `world_scale`: the scale times the nodes' local transforms, root first.
pub(crate) fn world_from_chain(world_scale: f64, chain: &[AnimatedNode], time: f64) -> DMat4 {
    chain
        .iter()
        .fold(DMat4::from_scale(DVec3::splat(world_scale)), |m, n| {
            m * n.parent_from_node(time)
        })
}

/// Where a camera is at one time, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    pub eye: DVec3,
    /// The node's -Z axis, unit length.
    pub forward: DVec3,
    /// The node's +Y axis, unit length.
    pub up: DVec3,
}

impl CameraPose {
    /// The pose of a glTF camera node placed by `world_from_camera`: the eye at its origin, the
    /// view along its -Z axis, up its +Y axis (glTF's camera axes).
    pub fn of(world_from_camera: &DMat4) -> Self {
        Self {
            eye: world_from_camera.transform_point3(DVec3::ZERO),
            forward: world_from_camera
                .transform_vector3(DVec3::NEG_Z)
                .normalize_or_zero(),
            up: world_from_camera
                .transform_vector3(DVec3::Y)
                .normalize_or_zero(),
        }
    }
}

/// The animation that moves a file's camera: the chain of nodes from a scene root (first) to
/// the camera's node (last).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraAnimation {
    /// The animation as a line names it: "animation I ('NAME')".
    pub name: String,
    chain: Vec<AnimatedNode>,
    /// The world's scale after the chain (the scene's units in metres).
    world_scale: f64,
}

impl CameraAnimation {
    /// The animation `name` of the chain `chain`, root first; `None` when no node of it moves.
    pub fn new(name: String, chain: Vec<AnimatedNode>) -> Option<Self> {
        chain.iter().any(AnimatedNode::is_animated).then_some(Self {
            name,
            chain,
            world_scale: 1.0,
        })
    }

    /// The earliest and latest key times of its tracks, seconds.
    pub fn time_range(&self) -> (f64, f64) {
        chain_time_range(&self.chain)
    }

    /// The camera node's world transform at `time` seconds.
    pub fn world_from_camera(&self, time: f64) -> DMat4 {
        world_from_chain(self.world_scale, &self.chain, time)
    }

    /// The camera's eye, view direction and up at `time` seconds (glTF's camera axes).
    pub fn pose_at(&self, time: f64) -> CameraPose {
        CameraPose::of(&self.world_from_camera(time))
    }

    /// This animation in a world scaled by `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            world_scale: self.world_scale * factor,
            ..self.clone()
        }
    }
}
