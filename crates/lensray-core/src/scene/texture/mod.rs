//! Textures: 8-bit RGBA images with their mip levels, and how a renderer reads them.
//!
//! A lookup is bilinear within a level and linear between the two levels around the level of
//! detail (trilinear), in linear values: sRGB-encoded colour is decoded before it is filtered,
//! as a GPU does for an sRGB image format. The level of detail comes from the texture-space
//! footprint of one pixel (`camera::footprint`), taken at the pinhole so that a texture at the
//! focal plane is exactly as sharp through a wide aperture as through a pinhole. Alpha tests
//! read level 0, so the edge of a mask is where its texels put it, at any distance.
//!
//! shaders/include/texture.glsl mirrors this file function by function: the GPU paths read the
//! same texels from a storage buffer with the same arithmetic, so their images match the CPU's.

use glam::{Affine2, Vec2, Vec3, Vec4};

mod decode;
mod mips;

pub use decode::{coverage_from_image, decode_texture};
pub use mips::{MAX_LEVELS, MAX_SIZE};

/// What a coordinate outside [0, 1] reads (glTF's sampler wrap modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    #[default]
    Repeat,
    ClampToEdge,
    MirroredRepeat,
}

/// How the RGB channels of the texels encode colour; alpha is always linear.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    Srgb,
    Linear,
}

/// One mip level: its size and where its texels start in [`Texture::texels`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Level {
    pub width: u32,
    pub height: u32,
    pub first: u32,
}

/// An image and its mip levels, level 0 the image itself, each next level half the size
/// (rounded down, at least 1) down to 1 x 1.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    pub encoding: Encoding,
    pub levels: Vec<Level>,
    /// Every level's texels, row by row, RGBA8 packed little-endian (red in the low byte).
    pub texels: Vec<u32>,
}

/// The texture coordinate sets a mesh carries (glTF's TEXCOORD_0 and TEXCOORD_1).
pub const TEXCOORD_SETS: usize = 2;

/// A point's coordinates in each texture coordinate set: what a [`TextureRef`] picks from.
pub type TexcoordSets = [Vec2; TEXCOORD_SETS];

/// The pixel footprint in each texture coordinate set.
pub type FootprintSets = [TexcoordFootprint; TEXCOORD_SETS];

/// A material's use of a texture: which one, how it wraps, which texture coordinate set it
/// reads and the transform from that set's coordinates to the texture's (glTF's `texCoord` and
/// `KHR_texture_transform`; set 0 and identity otherwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    pub texture: u32,
    pub wrap: [Wrap; 2],
    /// The mesh's set read: 0 (`Mesh::texcoords`) or 1 (`Mesh::texcoords1`).
    pub texcoord_set: u32,
    pub uv_from_texcoord: Affine2,
}

impl TextureRef {
    pub fn new(texture: u32) -> Self {
        Self {
            texture,
            wrap: [Wrap::Repeat; 2],
            texcoord_set: 0,
            uv_from_texcoord: Affine2::IDENTITY,
        }
    }

    /// The coordinates of its set among `texcoords`.
    pub fn texcoord(&self, texcoords: &TexcoordSets) -> Vec2 {
        texcoords[self.texcoord_set as usize]
    }
}

/// The footprint of a pixel in the mesh's texture coordinates: their change for one pixel step
/// along x and along y of the image.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexcoordFootprint {
    pub dx: Vec2,
    pub dy: Vec2,
}

impl TexcoordFootprint {
    /// The footprint in texture coordinates of position moves `dp` (`Footprint::dp`) on the
    /// triangle `vertices` with texture coordinates `texcoords`: each move written in the
    /// triangle's edges (least squares, exact for a move in its plane), the edges' changes of
    /// coordinates weighted alike. Zero on a degenerate triangle.
    pub fn on_triangle(vertices: [Vec3; 3], texcoords: [Vec2; 3], dp: [Vec3; 2]) -> Self {
        let (e1, e2) = (vertices[1] - vertices[0], vertices[2] - vertices[0]);
        let (t1, t2) = (texcoords[1] - texcoords[0], texcoords[2] - texcoords[0]);
        let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let det = g11 * g22 - g12 * g12;
        if det == 0.0 || !det.is_finite() {
            return Self::default();
        }
        let along = |d: Vec3| {
            let (r1, r2) = (e1.dot(d), e2.dot(d));
            let a = (g22 * r1 - g12 * r2) / det;
            let b = (g11 * r2 - g12 * r1) / det;
            a * t1 + b * t2
        };
        Self {
            dx: along(dp[0]),
            dy: along(dp[1]),
        }
    }
}

/// sRGB-encoded 8-bit value -> linear, the IEC 61966-2-1 curve.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear -> sRGB-encoded, in [0, 1].
pub fn linear_to_srgb(l: f32) -> f32 {
    let l = l.clamp(0.0, 1.0);
    if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// The 256 sRGB-encoded byte values decoded.
fn srgb_table() -> &'static [f32; 256] {
    static TABLE: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)))
}

/// A texel's linear RGBA.
pub fn decode_texel(texel: u32, encoding: Encoding) -> Vec4 {
    let byte = |i: u32| (texel >> (8 * i)) & 0xff;
    let alpha = byte(3) as f32 / 255.0;
    match encoding {
        Encoding::Srgb => {
            let table = srgb_table();
            Vec4::new(
                table[byte(0) as usize],
                table[byte(1) as usize],
                table[byte(2) as usize],
                alpha,
            )
        }
        Encoding::Linear => Vec4::new(
            byte(0) as f32 / 255.0,
            byte(1) as f32 / 255.0,
            byte(2) as f32 / 255.0,
            alpha,
        ),
    }
}

/// Integer texel coordinate `i` of a level `size` texels wide under `wrap`.
fn wrap_texel(i: i32, size: i32, wrap: Wrap) -> i32 {
    match wrap {
        Wrap::Repeat => i.rem_euclid(size),
        Wrap::ClampToEdge => i.clamp(0, size - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * size);
            if m < size {
                m
            } else {
                2 * size - 1 - m
            }
        }
    }
}

/// A coordinate brought into a range where the texel arithmetic stays exact and in `i32`,
/// without changing what it reads: one period of a repeat, two of a mirror; a clamp reads the
/// edge anyway beyond [0, 1]. Not-a-number reads 0.
fn reduce(c: f32, wrap: Wrap) -> f32 {
    if c.is_nan() {
        return 0.0;
    }
    match wrap {
        Wrap::Repeat => c - c.floor(),
        Wrap::MirroredRepeat => c - 2.0 * (0.5 * c).floor(),
        Wrap::ClampToEdge => c.clamp(-1.0, 2.0),
    }
}

impl Texture {
    /// The image's mean colour: its last level's one texel.
    pub fn mean(&self) -> Vec4 {
        self.levels
            .last()
            .map_or(Vec4::ONE, |level| self.texel(level, 0, 0))
    }

    fn texel(&self, level: &Level, x: i32, y: i32) -> Vec4 {
        let i = level.first + y as u32 * level.width + x as u32;
        decode_texel(self.texels[i as usize], self.encoding)
    }

    /// Bilinear lookup at `uv` in level `level`: texel centres at half-integers.
    pub fn bilinear(&self, level: usize, uv: Vec2, wrap: [Wrap; 2]) -> Vec4 {
        let l = &self.levels[level];
        let (w, h) = (l.width as i32, l.height as i32);
        let x = reduce(uv.x, wrap[0]) * w as f32 - 0.5;
        let y = reduce(uv.y, wrap[1]) * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i32, y0 as i32);
        let xs = [wrap_texel(x0, w, wrap[0]), wrap_texel(x0 + 1, w, wrap[0])];
        let ys = [wrap_texel(y0, h, wrap[1]), wrap_texel(y0 + 1, h, wrap[1])];
        let top = self
            .texel(l, xs[0], ys[0])
            .lerp(self.texel(l, xs[1], ys[0]), fx);
        let bottom = self
            .texel(l, xs[0], ys[1])
            .lerp(self.texel(l, xs[1], ys[1]), fx);
        top.lerp(bottom, fy)
    }

    /// The level of detail of a footprint `duv` in this texture's coordinates: log2 of the
    /// longer of its two axes in level-0 texels (what GPUs compute from derivatives).
    pub fn level_of_detail(&self, duv: &TexcoordFootprint) -> f32 {
        let size = Vec2::new(self.levels[0].width as f32, self.levels[0].height as f32);
        let longest = (duv.dx * size)
            .length_squared()
            .max((duv.dy * size).length_squared());
        0.5 * longest.log2()
    }

    /// Trilinear lookup at `uv` with level of detail `lod` (clamped to the levels there are).
    pub fn trilinear(&self, uv: Vec2, lod: f32, wrap: [Wrap; 2]) -> Vec4 {
        let last = (self.levels.len() - 1) as f32;
        // NaN (a degenerate footprint) reads level 0.
        let lod = if lod.is_nan() {
            0.0
        } else {
            lod.clamp(0.0, last)
        };
        let l0 = lod.floor();
        let f = lod - l0;
        let below = self.bilinear(l0 as usize, uv, wrap);
        if f == 0.0 {
            return below;
        }
        below.lerp(self.bilinear(l0 as usize + 1, uv, wrap), f)
    }
}

/// Reads `texture_ref` at the mesh texture coordinates of its set among `texcoords`, filtered
/// over that set's footprint among `footprints`.
pub fn sample(
    textures: &[Texture],
    texture_ref: &TextureRef,
    texcoords: &TexcoordSets,
    footprints: &FootprintSets,
) -> Vec4 {
    let texture = &textures[texture_ref.texture as usize];
    let footprint = &footprints[texture_ref.texcoord_set as usize];
    let m = texture_ref.uv_from_texcoord.matrix2;
    let uv = texture_ref
        .uv_from_texcoord
        .transform_point2(texture_ref.texcoord(texcoords));
    let duv = TexcoordFootprint {
        dx: m * footprint.dx,
        dy: m * footprint.dy,
    };
    texture.trilinear(uv, texture.level_of_detail(&duv), texture_ref.wrap)
}

/// Reads `texture_ref` at its set among `texcoords`, at level 0, bilinearly: what alpha tests
/// see.
pub fn sample_finest(
    textures: &[Texture],
    texture_ref: &TextureRef,
    texcoords: &TexcoordSets,
) -> Vec4 {
    let texture = &textures[texture_ref.texture as usize];
    let uv = texture_ref
        .uv_from_texcoord
        .transform_point2(texture_ref.texcoord(texcoords));
    texture.bilinear(0, uv, texture_ref.wrap)
}

#[cfg(test)]
mod tests;
