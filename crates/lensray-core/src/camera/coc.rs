//! The circle of confusion of a surface point seen through a pixel: how far, in pixels, the
//! lens rays that meet at the point spread over the film. The hybrid path's trace window, the
//! preview's CoC view and the path choice read it; `shaders/include/camera.glsl`'s
//! `coc_radius_pixels` evaluates [`CocLens::radius_pixels`] operation for operation, so host
//! and device plans agree.
//!
//! For lens point l, a point p is seen by the film point whose aperture-centre ray passes
//! p + l (n · p - F) / (F - lens_z - s · l) (`ThinLens::pinhole_from_camera`, n = (s, 1) the
//! plane of focus's normal, F the focus distance). Over an opening of reach r the offset is at
//! most r |n · p - F| / (F - lens_z - |s| r): exact for a plane that faces the camera (s = 0),
//! a bound a little over the largest offset for a tilted one, so a window sized by it holds
//! every lens ray. With p on the pinhole ray of screen point q at depth z, n · p - F is
//! z (1 + s · q) - F (perspective: p = (q z, z)) or z + s · q - F (orthographic: p = (q, z)),
//! and s · q is affine in the raster point.

use glam::Vec2;

use super::Camera;

/// What the circle of confusion of a camera depends on, as the shaders read it
/// (`GpuCocLens`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CocLens {
    pub perspective: bool,
    pub focus_distance: f32,
    /// Pixels of radius per unit of `n · p - F` (perspective: per unit of `(n · p - F) / z`):
    /// r x pixels per screen unit / (F - lens_z - |s| r).
    pub scale: f32,
    /// s · q at raster point (0, 0), and its steps per raster x and y.
    pub tilt_origin: f32,
    pub tilt_dx: f32,
    pub tilt_dy: f32,
}

impl CocLens {
    /// The circle of confusion's data of `camera`'s first-order lens.
    pub fn of(camera: &Camera) -> Self {
        let lens = camera.lens.first_order();
        let reach = lens.reach();
        let s = lens.focus_tilt;
        let depth = lens.focus_distance - camera.lens_plane_z() - s.length() * reach;
        let m = &camera.screen_from_raster;
        Self {
            perspective: !camera.is_orthographic(),
            focus_distance: lens.focus_distance,
            scale: reach * camera.pixels_per_screen_unit() / depth,
            tilt_origin: s.x * m.w_axis.x + s.y * m.w_axis.y,
            tilt_dx: s.x * m.x_axis.x,
            tilt_dy: s.y * m.y_axis.y,
        }
    }

    /// Radius, in pixels, of the circle of confusion of the surface at view depth `z` seen
    /// through raster point `p_raster` (a pixel's centre: column + 0.5, row + 0.5).
    pub fn radius_pixels(&self, p_raster: Vec2, z: f32) -> f32 {
        let tilt = self.tilt_origin + self.tilt_dx * p_raster.x + self.tilt_dy * p_raster.y;
        let off_plane = if self.perspective {
            (z * (1.0 + tilt) - self.focus_distance) / z
        } else {
            z + tilt - self.focus_distance
        };
        self.scale * off_plane.abs()
    }
}
