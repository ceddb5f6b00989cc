//! The rendered image: linear float RGB, row 0 at the top.

use glam::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// Row-major, `width * height` entries.
    pub pixels: Vec<Vec3>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    pub fn get(&self, column: u32, row: u32) -> Vec3 {
        self.pixels[(row * self.width + column) as usize]
    }

    pub fn set(&mut self, column: u32, row: u32, value: Vec3) {
        self.pixels[(row * self.width + column) as usize] = value;
    }
}
