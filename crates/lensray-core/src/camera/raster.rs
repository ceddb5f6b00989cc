//! Screen -> NDC -> raster (pbrt's chain): the screen window is mapped to [0, 1]^2 with the
//! origin at the top-left, then scaled to pixels. Depth passes through unchanged.

use glam::{Mat4, Vec2, Vec3};

/// The visible rectangle of the screen plane: x in [centre.x - half_width, centre.x +
/// half_width], y likewise. A centred window looks along the view axis; a shifted one
/// (`centre` not zero: a shift lens's film moved off the axis, see `movements`) keeps the
/// image plane facing the same way, so lines parallel to it stay parallel in the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenWindow {
    pub half_width: f32,
    pub half_height: f32,
    /// The window's centre on the screen plane (screen units; +x right, +y up).
    pub centre: Vec2,
}

impl ScreenWindow {
    /// The window of half height `half_height` and the image's aspect, centred at `centre`.
    pub fn new(half_height: f32, width: u32, height: u32, centre: Vec2) -> Self {
        let aspect = width as f32 / height as f32;
        Self {
            half_width: half_height * aspect,
            half_height,
            centre,
        }
    }

    /// The course's xStart/xStop, yStart/yStop: x grows to the right, y grows up.
    pub fn x_start(&self) -> f32 {
        self.centre.x - self.half_width
    }
    pub fn x_stop(&self) -> f32 {
        self.centre.x + self.half_width
    }
    pub fn y_start(&self) -> f32 {
        self.centre.y - self.half_height
    }
    pub fn y_stop(&self) -> f32 {
        self.centre.y + self.half_height
    }

    /// x_ndc = (x - xStart) / (xStop - xStart), y_ndc = (yStop - y) / (yStop - yStart).
    pub fn ndc_from_screen(&self) -> Mat4 {
        let width = self.x_stop() - self.x_start();
        let height = self.y_stop() - self.y_start();
        Mat4::from_scale(Vec3::new(1.0 / width, -1.0 / height, 1.0))
            * Mat4::from_translation(Vec3::new(-self.x_start(), -self.y_stop(), 0.0))
    }

    /// The course's front-plane map: x = xStart + s (xStop - xStart), y = yStop + t (yStart - yStop).
    pub fn screen_from_ndc(&self) -> Mat4 {
        let width = self.x_stop() - self.x_start();
        let height = self.y_stop() - self.y_start();
        Mat4::from_translation(Vec3::new(self.x_start(), self.y_stop(), 0.0))
            * Mat4::from_scale(Vec3::new(width, -height, 1.0))
    }
}

/// NDC [0, 1]^2 -> pixels: x = column, y = row.
pub fn raster_from_ndc(width: u32, height: u32) -> Mat4 {
    Mat4::from_scale(Vec3::new(width as f32, height as f32, 1.0))
}

/// Pixels -> NDC: the course's (s, t) = (i / width, j / height).
pub fn ndc_from_raster(width: u32, height: u32) -> Mat4 {
    Mat4::from_scale(Vec3::new(1.0 / width as f32, 1.0 / height as f32, 1.0))
}

/// NDC -> Vulkan clip space: x, y from [0, 1] to [-1, 1] (both already point right and down),
/// depth unchanged (Vulkan's [0, 1] is the course's depth range).
pub fn clip_from_ndc() -> Mat4 {
    Mat4::from_translation(Vec3::new(-1.0, -1.0, 0.0)) * Mat4::from_scale(Vec3::new(2.0, 2.0, 1.0))
}
