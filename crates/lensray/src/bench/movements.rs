//! The movements sweep's points: the shot plain, shifted, tilted, or both ("moved"), and what
//! each sets on the camera. Measured in turns, each moved point is weighed against the plain
//! one per sample (`runs::set_costs_vs_first`).

use serde::Serialize;

use super::options::BenchOptions;
use super::sweep::SweepValue;
use lensray_core::camera::Camera;
use lensray_core::settings::CameraSettings;

/// The moved shot's shift when `--shift` is not given: a tenth of the image height down (the
/// scene moves up; in image heights for a lens without a focal length, as the default
/// scene's). The frame trades sky for ground: what the CPU path pays for. Which way a shift
/// costs more differs by device (docs/movements-bench.md), so the sweep's `--shift` measures
/// others.
pub const DEFAULT_SHIFT: [f64; 2] = [0.0, -0.1];
/// The moved shot's tilt when `--tilt` is not given, degrees: the default scene's lens turns
/// its plane of focus by the tilt itself (no focal length), and 82 degrees toward the image's
/// bottom lays it level through the subject, 7.8 degrees below the eye: the row of spheres and
/// the horizon sharp, the near ground blurred.
pub const DEFAULT_TILT_DEGREES: f64 = 82.0;
/// The moved shot's tilt direction when `--tilt-direction` is not given: the plane comes nearer
/// toward the image's bottom, like the ground.
pub const DEFAULT_TILT_DIRECTION_DEGREES: f64 = 0.0;

/// The movements sweep's points (the plain one first: the others are weighed against it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BenchMovement {
    /// No shift, no tilt (a scene's own movements removed too).
    Plain,
    /// The shift alone.
    Shift,
    /// The tilt alone.
    Tilt,
    /// Shifted and tilted: the moved shot the cost figure compares with the plain one.
    Moved,
}

impl BenchMovement {
    pub const ALL: [BenchMovement; 4] = [
        BenchMovement::Plain,
        BenchMovement::Shift,
        BenchMovement::Tilt,
        BenchMovement::Moved,
    ];
    /// What the sweep measures without `--sweep-points`.
    pub const DEFAULT: [BenchMovement; 2] = [BenchMovement::Plain, BenchMovement::Moved];

    pub fn name(self) -> &'static str {
        match self {
            BenchMovement::Plain => "plain",
            BenchMovement::Shift => "shift",
            BenchMovement::Tilt => "tilt",
            BenchMovement::Moved => "moved",
        }
    }

    fn shifts(self) -> bool {
        matches!(self, BenchMovement::Shift | BenchMovement::Moved)
    }

    fn tilts(self) -> bool {
        matches!(self, BenchMovement::Tilt | BenchMovement::Moved)
    }

    /// Shift, tilt and tilt direction of this point: the options' values, else the defaults
    /// above, for the movements it makes.
    fn values(self, options: &BenchOptions) -> (Option<[f64; 2]>, Option<f64>, Option<f64>) {
        let tilts = self.tilts();
        (
            self.shifts()
                .then(|| options.shift.unwrap_or(DEFAULT_SHIFT)),
            tilts.then(|| options.tilt.unwrap_or(DEFAULT_TILT_DEGREES)),
            tilts.then(|| {
                options
                    .tilt_direction
                    .unwrap_or(DEFAULT_TILT_DIRECTION_DEGREES)
            }),
        )
    }
}

/// Sets the movements of the shot at `value` on `camera`: a movements point's own (the
/// options' values, else the defaults above), else the options' on top of the scene's, as
/// `render` sets them.
pub fn set(camera: &mut CameraSettings, options: &BenchOptions, value: SweepValue) {
    let SweepValue::Movements(point) = value else {
        camera.shift = options.shift.or(camera.shift);
        camera.tilt = options.tilt.or(camera.tilt);
        camera.tilt_direction = options.tilt_direction.or(camera.tilt_direction);
        return;
    };
    (camera.shift, camera.tilt, camera.tilt_direction) = point.values(options);
    // A plane of focus through three pixels is a tilt too; the sweep sets its own.
    camera.focus_plane = None;
}

/// A movements point as the report gives it: the movements asked for and what they made of
/// the camera.
#[derive(Clone, Debug, Serialize)]
pub struct MovementsPoint {
    pub point: BenchMovement,
    /// As given: mm on the film for a lens with a focal length, else image heights; +x right,
    /// +y up.
    pub shift: [f64; 2],
    pub tilt_degrees: f64,
    pub tilt_direction_degrees: f64,
    /// The film window's centre off the axis, in image heights (the shift resolved).
    pub window_shift_image_heights: [f32; 2],
    /// The plane of focus z + focus_tilt · (x, y) = focus_distance in camera space (zero:
    /// facing the camera).
    pub focus_tilt: [f32; 2],
}

impl MovementsPoint {
    /// The record of `point`, measured with `options` and rendered with `camera`.
    pub fn of(point: BenchMovement, options: &BenchOptions, camera: &Camera) -> Self {
        let (shift, tilt, tilt_direction) = point.values(options);
        let window = &camera.screen_window;
        let per_image_height = 0.5 / window.half_height;
        Self {
            point,
            shift: shift.unwrap_or([0.0, 0.0]),
            tilt_degrees: tilt.unwrap_or(0.0),
            tilt_direction_degrees: tilt_direction.unwrap_or(0.0),
            window_shift_image_heights: (window.centre * per_image_height).to_array(),
            focus_tilt: camera.lens.first_order().focus_tilt.to_array(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_set_their_movements_and_nothing_else() {
        let scene = CameraSettings {
            shift: Some([0.3, 0.0]),
            tilt: Some(5.0),
            ..CameraSettings::default()
        };
        let options = BenchOptions {
            tilt: Some(10.0),
            ..BenchOptions::default()
        };
        let at = |point| {
            let mut camera = scene.clone();
            set(&mut camera, &options, SweepValue::Movements(point));
            (camera.shift, camera.tilt, camera.tilt_direction)
        };
        assert_eq!(at(BenchMovement::Plain), (None, None, None));
        assert_eq!(at(BenchMovement::Shift), (Some(DEFAULT_SHIFT), None, None));
        assert_eq!(at(BenchMovement::Tilt), (None, Some(10.0), Some(0.0)));
        assert_eq!(
            at(BenchMovement::Moved),
            (Some(DEFAULT_SHIFT), Some(10.0), Some(0.0))
        );
        // Outside the sweep the options go on top of the scene's, as on `render`.
        let mut camera = scene.clone();
        set(&mut camera, &options, SweepValue::Spp(4));
        assert_eq!(
            (camera.shift, camera.tilt, camera.tilt_direction),
            (Some([0.3, 0.0]), Some(10.0), None)
        );
    }
}
