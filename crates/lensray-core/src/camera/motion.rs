//! The camera moving while the shutter is open: motion blur and rolling shutter.
//!
//! A frame's exposure spans from the first row's opening to the last row's closing. Each row is
//! open for the exposure and opens later than the row above it by its share of the readout
//! (a rolling shutter; none: every row at once). The camera's pose is known at
//! [`MOTION_STEPS`] times evenly spaced over that span; between two it moves as pbrt-v4's
//! `AnimatedTransform` does, the eye linearly and the rotation by slerp. A sample's moment in
//! the span is `time * exposure_share + row_share * rolling_share`, where `time` is its
//! shutter sample in [0, 1) and `row_share` how far down the image its film point lies.
//!
//! Only the pose moves within a frame: the lens (focus, aperture, focal length) is the frame's.

use glam::{Mat3, Quat, Vec3};

use super::look_at::CameraFrame;
use crate::interface::MOTION_STEPS;

/// The camera's world pose at one moment: its eye and the rotation that takes the camera's
/// right-handed axes (right, up, backward) to world space. Camera space is left-handed
/// (`look_at`), so world_from_camera is this rotation with its third column negated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidPose {
    pub eye: Vec3,
    pub rotation: Quat,
}

impl RigidPose {
    pub fn of(frame: &CameraFrame) -> Self {
        let rotation =
            Quat::from_mat3(&Mat3::from_cols(frame.right, frame.true_up, -frame.forward));
        Self {
            eye: frame.eye,
            rotation: rotation.normalize(),
        }
    }

    /// A camera-space point to world space.
    pub fn world_point(&self, p: Vec3) -> Vec3 {
        self.eye + self.world_vector(p)
    }

    /// A camera-space vector to world space: the rotation applied to (x, y, -z).
    pub fn world_vector(&self, v: Vec3) -> Vec3 {
        self.rotation * Vec3::new(v.x, v.y, -v.z)
    }
}

/// Slerp from `a` to `b` (unit quaternions) by `f` in [0, 1], along the shorter arc; nearly
/// equal rotations are blended linearly and normalized, where slerp's division loses precision.
/// camera.glsl's `slerp` does the same.
pub fn slerp(a: Quat, b: Quat, f: f32) -> Quat {
    let mut cos = a.dot(b);
    let b = if cos < 0.0 {
        cos = -cos;
        -b
    } else {
        b
    };
    if cos > 0.9995 {
        return (a * (1.0 - f) + b * f).normalize();
    }
    let angle = cos.acos();
    let inverse_sin = 1.0 / angle.sin();
    a * (((1.0 - f) * angle).sin() * inverse_sin) + b * ((f * angle).sin() * inverse_sin)
}

/// Where `moment` in [0, 1] (clamped) falls among `count` (at least 2) steps evenly spaced
/// over the span: the step before it and the fraction of the way to the next. Everything that
/// moves over the shutter (the camera, meshes, lights; and the GLSL mirrors) interpolates so.
pub fn step_at(moment: f32, count: usize) -> (usize, f32) {
    let s = moment.clamp(0.0, 1.0) * (count - 1) as f32;
    let i = (s as usize).min(count - 2);
    (i, s - i as f32)
}

/// The camera's poses over a frame's exposure, and how a sample's time and row place it there.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraMotion {
    /// [`MOTION_STEPS`] poses, the first at the first row's opening, the last at the last row's
    /// closing.
    pub poses: Vec<RigidPose>,
    /// The exposure over the span: 1 without a rolling shutter, 0 for a rolling shutter
    /// without motion blur (each row an instant).
    pub exposure_share: f32,
    /// The readout over the span: how much later the bottom row opens than the top.
    pub rolling_share: f32,
}

impl CameraMotion {
    /// The motion through `frames` (one per step, evenly spaced over the span), or `None`
    /// when the camera stays put (every pose the same), when no sample would move.
    pub fn new(frames: &[CameraFrame], exposure_share: f32, rolling_share: f32) -> Option<Self> {
        let motion = Self::through(frames, exposure_share, rolling_share);
        (!motion.stands_still()).then_some(motion)
    }

    /// The motion through `frames` even where the camera stays put: its samples still take
    /// their moments, at which the scene's moving objects are met.
    pub fn through(frames: &[CameraFrame], exposure_share: f32, rolling_share: f32) -> Self {
        assert_eq!(frames.len(), MOTION_STEPS as usize, "one frame per step");
        Self {
            poses: frames.iter().map(RigidPose::of).collect(),
            exposure_share,
            rolling_share,
        }
    }

    /// Whether every pose is the same.
    pub fn stands_still(&self) -> bool {
        self.poses.iter().all(|p| *p == self.poses[0])
    }

    /// The moment in the span, in [0, 1], of shutter sample `time` in [0, 1) at raster row
    /// `row` of an image `height` rows high.
    pub fn moment(&self, time: f32, row: f32, height: u32) -> f32 {
        let row_share = (row / height as f32).clamp(0.0, 1.0);
        (time * self.exposure_share + row_share * self.rolling_share).clamp(0.0, 1.0)
    }

    /// The pose at `moment` in [0, 1]: between the two steps around it.
    pub fn pose_at(&self, moment: f32) -> RigidPose {
        let (i, f) = step_at(moment, self.poses.len());
        let (a, b) = (self.poses[i], self.poses[i + 1]);
        RigidPose {
            eye: a.eye + (b.eye - a.eye) * f,
            rotation: slerp(a.rotation, b.rotation, f),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(eye: Vec3, target: Vec3) -> CameraFrame {
        CameraFrame::look_at(eye, target, Vec3::Y).unwrap()
    }

    #[test]
    fn a_pose_maps_like_world_from_camera() {
        let f = frame(Vec3::new(1.0, 2.0, 3.0), Vec3::new(-2.0, 0.5, -4.0));
        let pose = RigidPose::of(&f);
        let m = f.world_from_camera();
        for p in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.3, -0.7, 2.5)] {
            let d = pose.world_point(p) - m.transform_point3(p);
            assert!(d.length() < 1e-6, "{p}: off by {d}");
            let d = pose.world_vector(p) - m.transform_vector3(p);
            assert!(d.length() < 1e-6, "{p}: off by {d}");
        }
    }

    #[test]
    fn a_still_camera_has_no_motion() {
        let f = frame(Vec3::ZERO, Vec3::Z);
        assert!(CameraMotion::new(&[f; MOTION_STEPS as usize], 1.0, 0.0).is_none());
    }

    #[test]
    fn a_slide_and_a_pan_interpolate_as_the_course_would() {
        // Eye from x = 0 to x = 7 over the steps, looking down +z, while turning about y by
        // 0.1 rad a step: the pose at a moment is the pose of the lerped eye and angle.
        let n = MOTION_STEPS as usize;
        let at = |k: f32| {
            let angle = 0.1 * k;
            let eye = Vec3::new(k, 0.0, 0.0);
            frame(eye, eye + Vec3::new(angle.sin(), 0.0, angle.cos()))
        };
        let frames: Vec<CameraFrame> = (0..n).map(|k| at(k as f32)).collect();
        let motion = CameraMotion::new(&frames, 1.0, 0.0).unwrap();
        for moment in [0.0, 0.1, 0.5, 0.73, 1.0] {
            let k = moment * (n - 1) as f32;
            let want = RigidPose::of(&at(k));
            let got = motion.pose_at(moment);
            assert!(
                (got.eye - want.eye).length() < 1e-5,
                "{moment}: eye {got:?}"
            );
            let angle = got.rotation.angle_between(want.rotation);
            assert!(angle < 1e-3, "{moment}: rotation off by {angle} rad");
        }
    }

    #[test]
    fn rows_open_later_by_their_share_of_the_readout() {
        let n = MOTION_STEPS as usize;
        let frames: Vec<CameraFrame> = (0..n)
            .map(|k| frame(Vec3::new(k as f32, 0.0, 0.0), Vec3::new(k as f32, 0.0, 1.0)))
            .collect();
        let motion = CameraMotion::new(&frames, 0.75, 0.25).unwrap();
        assert_eq!(motion.moment(0.0, 0.0, 100), 0.0);
        assert_eq!(motion.moment(1.0, 0.0, 100), 0.75);
        assert_eq!(motion.moment(0.0, 100.0, 100), 0.25);
        assert_eq!(motion.moment(1.0, 100.0, 100), 1.0);
        assert!((motion.moment(0.5, 50.0, 100) - 0.5).abs() < 1e-7);
    }
}
