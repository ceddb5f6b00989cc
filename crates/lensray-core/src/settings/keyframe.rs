//! Keyframes: a scene file's `[[keyframe]]` tables, each a frame number and camera settings
//! for that frame, and the settings of any frame between them.
//!
//! A key's `interpolation` says how each setting it gives moves on to that setting's next key:
//! `linear`, `smooth` (ease in and out: the weight of the next key is 3t^2 - 2t^3 at the
//! fraction t of the way) or `hold` (the value stays until the next key). Before its first key
//! a setting has that key's value, after its last the last key's; a setting no key gives keeps
//! the scene's value. Focus moves in dioptres, 1 / distance, as a focus puller's wheel does: a
//! pull from 1 m to 4 m is halfway in dioptres (1.6 m) a quarter of the way in distance. A lens
//! is a choice, not a number: it holds until the next key that names one.
//!
//! A glTF animation of the scene's camera may move its eye, target and up instead
//! ([`Keyframes::with_camera_timeline`], [`CameraTimeline`]).
//!
//! Focus is a distance, a world point (its depth along the view axis at that frame) or a pixel
//! (the depth of the surface seen there at that frame, found by the app's render path):
//! [`Keyframes::resolve_focus`] turns points and pixels into distances before frames are made.

use std::path::Path;

use crate::sampler::hash::hash_u32;
use crate::settings::camera_timeline::CameraTimeline;
use crate::settings::{Settings, SettingsError};

/// How a setting moves from one key to its next.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interpolation {
    #[default]
    Linear,
    /// Ease in and out: 3t^2 - 2t^3.
    Smooth,
    Hold,
}

impl Interpolation {
    pub const ALL: [Interpolation; 3] = [Self::Linear, Self::Smooth, Self::Hold];

    pub fn name(self) -> &'static str {
        match self {
            Self::Linear => "linear",
            Self::Smooth => "smooth",
            Self::Hold => "hold",
        }
    }

    /// The weight of the next key at the fraction `t` (0 to 1) of the way to it.
    pub fn weight(self, t: f64) -> f64 {
        match self {
            Self::Linear => t,
            Self::Smooth => t * t * (3.0 - 2.0 * t),
            Self::Hold => 0.0,
        }
    }
}

/// Where a key focuses.
#[derive(Clone, Debug, PartialEq)]
pub enum FocusKey {
    /// Along the view axis, in the scene's units (metres once loaded).
    Distance(f64),
    /// A world point: its depth along the view axis.
    Point([f64; 3]),
    /// A pixel (column, row): the depth of the surface seen there.
    Pixel([u32; 2]),
}

/// A setting keyframes move; several keys may set one (focus: a distance, a point, a pixel).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Channel {
    Focus,
    FNumber,
    FocalLength,
    Lens,
    Eye,
    Target,
    Up,
    Shift,
    Tilt,
    TiltDirection,
    ApertureRotation,
    Exposure,
}

const CHANNELS: [Channel; 12] = [
    Channel::Focus,
    Channel::FNumber,
    Channel::FocalLength,
    Channel::Lens,
    Channel::Eye,
    Channel::Target,
    Channel::Up,
    Channel::Shift,
    Channel::Tilt,
    Channel::TiltDirection,
    Channel::ApertureRotation,
    Channel::Exposure,
];

/// A key's value.
#[derive(Clone, Debug, PartialEq)]
enum KeyValue {
    Numbers(Vec<f64>),
    Lens(String),
    Focus(FocusKey),
}

/// What a key's value must be.
#[derive(Clone, Copy)]
enum ValueKind {
    /// `n` finite numbers.
    Numbers(usize),
    /// A positive finite number.
    Positive,
    /// A number in [0, 90).
    TiltDegrees,
    Lens,
    FocusDistance,
    FocusPoint,
    FocusPixel,
}

/// The keys a `[[keyframe]]` takes besides `frame` and `interpolation`.
const KEYS: [(&str, Channel, ValueKind); 14] = [
    ("focus_distance", Channel::Focus, ValueKind::FocusDistance),
    ("focus_point", Channel::Focus, ValueKind::FocusPoint),
    ("focus_at", Channel::Focus, ValueKind::FocusPixel),
    ("f_number", Channel::FNumber, ValueKind::Positive),
    ("focal_length_mm", Channel::FocalLength, ValueKind::Positive),
    ("lens", Channel::Lens, ValueKind::Lens),
    ("eye", Channel::Eye, ValueKind::Numbers(3)),
    ("target", Channel::Target, ValueKind::Numbers(3)),
    ("up", Channel::Up, ValueKind::Numbers(3)),
    ("shift", Channel::Shift, ValueKind::Numbers(2)),
    ("tilt", Channel::Tilt, ValueKind::TiltDegrees),
    (
        "tilt_direction",
        Channel::TiltDirection,
        ValueKind::Numbers(1),
    ),
    (
        "aperture_rotation",
        Channel::ApertureRotation,
        ValueKind::Numbers(1),
    ),
    ("exposure", Channel::Exposure, ValueKind::Numbers(1)),
];

/// One `[[keyframe]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe {
    pub frame: u32,
    pub interpolation: Interpolation,
    values: Vec<(Channel, KeyValue)>,
}

/// A scene's keyframes, in frame order, and the glTF animation that moves its camera, if any.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Keyframes {
    keys: Vec<Keyframe>,
    camera_timeline: Option<CameraTimeline>,
}

/// A sequence's frames per second when neither the scene file nor `--fps` gives one.
pub const DEFAULT_FPS: f64 = 24.0;

/// The settings' frames per second, checked (default [`DEFAULT_FPS`]).
pub fn fps(settings: &Settings) -> Result<f64, SettingsError> {
    match settings.image.fps {
        None => Ok(DEFAULT_FPS),
        Some(f) if f.is_finite() && f > 0.0 && f <= 1000.0 => Ok(f),
        Some(f) => Err(SettingsError::Fps(f)),
    }
}

/// The seed of frame `frame` of a sequence whose seed is `seed`: a frame is the same image
/// however a range is split.
pub fn frame_seed(seed: u32, frame: u32) -> u32 {
    hash_u32(seed ^ hash_u32(frame.wrapping_add(0x9e37_79b9)))
}

fn number(value: &toml::Value) -> Option<f64> {
    match value {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

fn numbers(value: &toml::Value, n: usize) -> Option<Vec<f64>> {
    match (n, value) {
        (1, v) => number(v).map(|x| vec![x]),
        (_, toml::Value::Array(a)) if a.len() == n => a.iter().map(number).collect(),
        _ => None,
    }
}

/// The value of key `name` of `kind`, or what is wrong with it. A relative lens file starts at
/// `folder`.
fn parse_value(kind: ValueKind, value: &toml::Value, folder: &Path) -> Result<KeyValue, String> {
    let finite = |n: usize, what: &str| {
        numbers(value, n)
            .filter(|v| v.iter().all(|x| x.is_finite()))
            .ok_or_else(|| format!("must be {what}, got {value}"))
    };
    let one = |what: &str, ok: fn(f64) -> bool| {
        finite(1, what).and_then(|v| match ok(v[0]) {
            true => Ok(KeyValue::Numbers(v)),
            false => Err(format!("must be {what}, got {value}")),
        })
    };
    match kind {
        ValueKind::Numbers(1) => finite(1, "a finite number").map(KeyValue::Numbers),
        ValueKind::Numbers(n) => finite(n, &format!("{n} finite numbers")).map(KeyValue::Numbers),
        ValueKind::Positive => one("a positive number", |x| x > 0.0),
        ValueKind::TiltDegrees => one("degrees from 0 to under 90", |x| (0.0..90.0).contains(&x)),
        ValueKind::FocusDistance => {
            let v = finite(1, "a positive distance")?[0];
            match v > 0.0 {
                true => Ok(KeyValue::Focus(FocusKey::Distance(v))),
                false => Err(format!("must be a positive distance, got {value}")),
            }
        }
        ValueKind::FocusPoint => finite(3, "a point [x, y, z]")
            .map(|v| KeyValue::Focus(FocusKey::Point([v[0], v[1], v[2]]))),
        ValueKind::FocusPixel => {
            let pixel = numbers(value, 2)
                .filter(|v| v.iter().all(|x| *x >= 0.0 && x.fract() == 0.0 && *x < 1e9))
                .ok_or_else(|| format!("must be a pixel [column, row], got {value}"))?;
            Ok(KeyValue::Focus(FocusKey::Pixel([
                pixel[0] as u32,
                pixel[1] as u32,
            ])))
        }
        ValueKind::Lens => match value.as_str() {
            Some(name) if !name.trim().is_empty() => {
                let name = name.trim();
                Ok(KeyValue::Lens(match crate::optics::builtin::lens(name) {
                    Some(_) => name.to_owned(),
                    None => crate::scene::reads::named_file(folder, Path::new(name))?
                        .path
                        .to_string_lossy()
                        .into_owned(),
                }))
            }
            _ => Err(format!("must be a lens's name or file, got {value}")),
        },
    }
}

/// One `[[keyframe]]` table (the `index`-th, from 1), or one line naming what is wrong.
fn parse_keyframe(index: usize, table: &toml::Table, folder: &Path) -> Result<Keyframe, String> {
    let frame = match table.get("frame") {
        Some(toml::Value::Integer(f)) if (0..=i64::from(u32::MAX)).contains(f) => *f as u32,
        Some(other) => {
            return Err(format!(
                "[[keyframe]] {index}: `frame` must be a whole number from 0, got {other}"
            ))
        }
        None => return Err(format!("[[keyframe]] {index}: no `frame`")),
    };
    let at = |key: &str, what: String| format!("keyframe at frame {frame}: `{key}` {what}");
    let interpolation = match table.get("interpolation") {
        None => Interpolation::default(),
        Some(value) => Interpolation::ALL
            .into_iter()
            .find(|i| value.as_str() == Some(i.name()))
            .ok_or_else(|| {
                at(
                    "interpolation",
                    format!("must be linear, smooth or hold, got {value}"),
                )
            })?,
    };
    let mut values: Vec<(Channel, KeyValue)> = Vec::new();
    for (key, value) in table {
        if key == "frame" || key == "interpolation" {
            continue;
        }
        let Some(&(_, channel, kind)) = KEYS.iter().find(|(name, ..)| name == key) else {
            let names: Vec<&str> = KEYS.iter().map(|(name, ..)| *name).collect();
            return Err(at(
                key,
                format!(
                    "is not a keyframe key (frame, interpolation, {})",
                    names.join(", ")
                ),
            ));
        };
        if values.iter().any(|(c, _)| *c == channel) {
            return Err(at(
                key,
                "sets focus a second time: give one of focus_distance, focus_point, focus_at"
                    .into(),
            ));
        }
        values.push((
            channel,
            parse_value(kind, value, folder).map_err(|e| at(key, e))?,
        ));
    }
    Ok(Keyframe {
        frame,
        interpolation,
        values,
    })
}

impl Keyframes {
    /// The keyframes of a scene file's `[[keyframe]]` tables, or one line naming the key and
    /// the frame that are wrong. Frames must increase from table to table.
    pub fn parse(tables: &[toml::Table], folder: &Path) -> Result<Self, String> {
        let mut keys: Vec<Keyframe> = Vec::with_capacity(tables.len());
        for (i, table) in tables.iter().enumerate() {
            let key = parse_keyframe(i + 1, table, folder)?;
            if let Some(before) = keys.last().filter(|b| b.frame >= key.frame) {
                return Err(format!(
                    "keyframe at frame {}: out of order: frames must increase, and the keyframe before it is at frame {}",
                    key.frame, before.frame
                ));
            }
            keys.push(key);
        }
        Ok(Self {
            keys,
            camera_timeline: None,
        })
    }

    /// These keyframes with `timeline` moving the camera's eye, target and up at each frame,
    /// unless a key gives eye, target or up: the keys then move the camera, the animation is
    /// not played, and the warning line returned says so.
    pub fn with_camera_timeline(mut self, timeline: CameraTimeline) -> (Self, Option<String>) {
        let keyed = self.keys.iter().find(|k| {
            k.values
                .iter()
                .any(|(c, _)| matches!(c, Channel::Eye | Channel::Target | Channel::Up))
        });
        if let Some(key) = keyed {
            let warning = format!(
                "the keyframe at frame {} moves the camera (eye, target or up), so the scene's keyframes move it and its glTF {} is not played",
                key.frame,
                timeline.animation().name
            );
            return (self, Some(warning));
        }
        self.camera_timeline = Some(timeline);
        (self, None)
    }

    /// The glTF animation that moves the camera, on the sequence's frames, if one does.
    pub fn camera_timeline(&self) -> Option<&CameraTimeline> {
        self.camera_timeline.as_ref()
    }

    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// The first and last frames that keys or the camera's animation (from its first key to
    /// its last) move.
    pub fn range(&self) -> Option<(u32, u32)> {
        let keyed = self
            .keys
            .first()
            .zip(self.keys.last())
            .map(|(a, b)| (a.frame, b.frame));
        let animated = self
            .camera_timeline
            .as_ref()
            .map(CameraTimeline::frame_range);
        match (keyed, animated) {
            (Some((a, b)), Some((c, d))) => Some((a.min(c), b.max(d))),
            (one, other) => one.or(other),
        }
    }

    /// These keyframes with their world lengths (focus distances and points, eye, target)
    /// multiplied by `factor`.
    pub fn scaled(mut self, factor: f64) -> Self {
        for (channel, value) in self.keys.iter_mut().flat_map(|k| k.values.iter_mut()) {
            match (channel, value) {
                (Channel::Focus, KeyValue::Focus(FocusKey::Distance(d))) => *d *= factor,
                (Channel::Focus, KeyValue::Focus(FocusKey::Point(p))) => {
                    p.iter_mut().for_each(|x| *x *= factor);
                }
                (Channel::Eye | Channel::Target, KeyValue::Numbers(v)) => {
                    v.iter_mut().for_each(|x| *x *= factor);
                }
                _ => {}
            }
        }
        self.camera_timeline = self.camera_timeline.map(|t| t.scaled(factor));
        self
    }

    /// The focus keys that are points or pixels, with their frames.
    pub fn unresolved_focus(&self) -> Vec<(u32, FocusKey)> {
        self.keys
            .iter()
            .flat_map(|k| k.values.iter().map(move |v| (k.frame, v)))
            .filter_map(|(frame, (_, value))| match value {
                KeyValue::Focus(f @ (FocusKey::Point(_) | FocusKey::Pixel(_))) => {
                    Some((frame, f.clone()))
                }
                _ => None,
            })
            .collect()
    }

    /// Replaces the focus key at `frame` with the distance `distance`.
    pub fn resolve_focus(&mut self, frame: u32, distance: f64) {
        let key = self.keys.iter_mut().find(|k| k.frame == frame);
        for (_, value) in key.into_iter().flat_map(|k| k.values.iter_mut()) {
            if let KeyValue::Focus(focus) = value {
                *focus = FocusKey::Distance(distance);
            }
        }
    }

    /// `base` with the keyed settings at `frame` over it, and the camera where the animation
    /// puts it, if one moves it. Focus keys still points or pixels ([`Self::resolve_focus`])
    /// are left out.
    pub fn settings_at(&self, base: &Settings, frame: u32) -> Settings {
        self.settings_at_time(base, f64::from(frame))
    }

    /// [`Self::settings_at`] a fractional frame `frame` (a time within a frame's shutter).
    pub fn settings_at_time(&self, base: &Settings, frame: f64) -> Settings {
        let mut over = Settings::default();
        for channel in CHANNELS {
            if let Some(value) = self.value_at(channel, frame) {
                set(&mut over, channel, value);
            }
        }
        let keyed = base.clone().overridden_by(&over);
        match &self.camera_timeline {
            Some(timeline) => timeline.settings_at_time(&keyed, frame),
            None => keyed,
        }
    }

    /// The value of `channel` at `frame`, if any key gives it.
    fn value_at(&self, channel: Channel, frame: f64) -> Option<KeyValue> {
        let keyed: Vec<(&Keyframe, &KeyValue)> = self
            .keys
            .iter()
            .filter_map(|k| {
                let (_, v) = k.values.iter().find(|(c, _)| *c == channel)?;
                match v {
                    KeyValue::Focus(FocusKey::Point(_) | FocusKey::Pixel(_)) => None,
                    _ => Some((k, v)),
                }
            })
            .collect();
        let after = keyed.iter().position(|(k, _)| f64::from(k.frame) > frame);
        let (from, to) = match after {
            None => return keyed.last().map(|(_, v)| (*v).clone()),
            Some(0) => return Some(keyed[0].1.clone()),
            Some(i) => (keyed[i - 1], keyed[i]),
        };
        let t = (frame - f64::from(from.0.frame)) / f64::from(to.0.frame - from.0.frame);
        let w = from.0.interpolation.weight(t);
        Some(between(from.1, to.1, w))
    }
}

/// The value a weight `w` of the way from `a` to `b`: numbers linearly, focus distances in
/// dioptres, a lens held.
fn between(a: &KeyValue, b: &KeyValue, w: f64) -> KeyValue {
    match (a, b) {
        (KeyValue::Numbers(a), KeyValue::Numbers(b)) => {
            KeyValue::Numbers(a.iter().zip(b).map(|(a, b)| a + (b - a) * w).collect())
        }
        (KeyValue::Focus(FocusKey::Distance(a)), KeyValue::Focus(FocusKey::Distance(b))) => {
            let dioptres = (1.0 - w) / a + w / b;
            KeyValue::Focus(FocusKey::Distance(1.0 / dioptres))
        }
        _ => a.clone(),
    }
}

/// Sets `channel` of `over` to `value`.
fn set(over: &mut Settings, channel: Channel, value: KeyValue) {
    let c = &mut over.camera;
    let triple = |v: &[f64]| Some([v[0], v[1], v[2]]);
    match (channel, value) {
        (Channel::Focus, KeyValue::Focus(FocusKey::Distance(d))) => c.focus_distance = Some(d),
        (Channel::Lens, KeyValue::Lens(name)) => c.lens.prescription = Some(name),
        (channel, KeyValue::Numbers(v)) => match channel {
            Channel::FNumber => c.f_number = Some(v[0]),
            Channel::FocalLength => c.focal_length_mm = Some(v[0]),
            Channel::Eye => c.eye = triple(&v),
            Channel::Target => c.target = triple(&v),
            Channel::Up => c.up = triple(&v),
            Channel::Shift => c.shift = Some([v[0], v[1]]),
            Channel::Tilt => c.tilt = Some(v[0]),
            Channel::TiltDirection => c.tilt_direction = Some(v[0]),
            Channel::ApertureRotation => c.aperture.rotation = Some(v[0]),
            Channel::Exposure => c.exposure.ev = Some(v[0]),
            Channel::Focus | Channel::Lens => {}
        },
        _ => {}
    }
}

#[cfg(test)]
#[path = "keyframe_tests.rs"]
mod tests;
