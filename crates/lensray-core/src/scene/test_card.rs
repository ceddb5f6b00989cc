//! A textured test scene, every texture made here: a checker floor (repeated through a texture
//! transform, minified towards the horizon), a gradient card (clamped across, mirrored down), a
//! leaf cut out by an alpha mask, a half-covered blended pane and an emissive sign. What the
//! textured paths are compared on.

use glam::{Affine2, Vec2, Vec3};

use super::generate::quad;
use super::texture::{Encoding, TextureRef, Wrap};
use super::{AlphaMode, Material, Scene, Texture};

/// A `side` x `side` texture whose texel (x, y) is `texel(x, y)` (RGBA8).
fn procedural(name: &str, side: u32, texel: impl Fn(u32, u32) -> [u8; 4]) -> Texture {
    let rgba: Vec<u8> = (0..side * side)
        .flat_map(|i| texel(i % side, i / side))
        .collect();
    Texture::from_rgba8(name, side, side, &rgba, Encoding::Srgb)
}

fn textures() -> Vec<Texture> {
    vec![
        procedural("checker", 64, |x, y| {
            if (x / 8 + y / 8) % 2 == 0 {
                [230, 220, 200, 255]
            } else {
                [40, 60, 120, 255]
            }
        }),
        procedural("gradient", 32, |x, y| {
            [(x * 8) as u8, (255 - y * 8) as u8, 90, 255]
        }),
        // An ellipse with a notch: the leaf's coverage in alpha, its colour veined.
        procedural("leaf", 32, |x, y| {
            let p = (Vec2::new(x as f32, y as f32) + 0.5) / 16.0 - 1.0;
            let inside = p.x * p.x / 0.36 + p.y * p.y < 0.9 && !(p.y > 0.6 && p.x.abs() < 0.1);
            let vein = if p.x.abs() < 0.06 { 180 } else { 70 };
            [40, vein, 30, if inside { 255 } else { 0 }]
        }),
        procedural("sign", 16, |x, y| {
            let lit = (x + y) % 4 < 2;
            [if lit { 255 } else { 30 }, 160, 40, 255]
        }),
    ]
}

/// The scene, seen by a camera at (0, 1.2, 4) looking at (0, 0.6, 0).
pub fn test_card() -> Scene {
    let textured = |t: u32, wrap: [Wrap; 2], uv: Affine2| {
        Some(TextureRef {
            texture: t,
            wrap,
            uv_from_texcoord: uv,
            texcoord_set: 0,
        })
    };
    let leaf = textured(2, [Wrap::ClampToEdge; 2], Affine2::IDENTITY);
    let materials = vec![
        Material {
            diffuse_texture: textured(
                0,
                [Wrap::Repeat; 2],
                Affine2::from_scale_angle_translation(Vec2::splat(6.0), 0.3, Vec2::new(0.1, 0.0)),
            ),
            ..Material::new("checker floor", Vec3::ONE, Vec3::ZERO)
        },
        Material {
            diffuse_texture: textured(
                1,
                [Wrap::ClampToEdge, Wrap::MirroredRepeat],
                Affine2::from_scale_angle_translation(Vec2::new(1.5, 2.0), 0.0, Vec2::splat(-0.25)),
            ),
            ..Material::new("gradient card", Vec3::ONE, Vec3::ZERO)
        },
        Material {
            diffuse_texture: leaf,
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            alpha_texture: leaf,
            ..Material::new("leaf", Vec3::ONE, Vec3::ZERO)
        },
        Material {
            alpha_mode: AlphaMode::Blend,
            alpha: 0.5,
            ..Material::new("pane", Vec3::new(0.3, 0.5, 0.9), Vec3::ZERO)
        },
        Material {
            emission_texture: textured(3, [Wrap::Repeat; 2], Affine2::IDENTITY),
            ..Material::new("sign", Vec3::splat(0.2), Vec3::splat(2.0))
        },
    ];
    let meshes = vec![
        quad(
            "floor",
            Vec3::new(-6.0, 0.0, 3.0),
            Vec3::new(12.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -30.0),
            0,
        ),
        // Cards hang with v down their face, as images are stored.
        quad(
            "card",
            Vec3::new(-1.6, 1.6, -0.5),
            Vec3::new(1.2, 0.0, 0.0),
            Vec3::new(0.0, -1.4, 0.0),
            1,
        ),
        quad(
            "leaf",
            Vec3::new(0.2, 1.5, 0.6),
            Vec3::new(0.9, 0.0, 0.2),
            Vec3::new(0.0, -1.1, 0.1),
            2,
        ),
        quad(
            "pane",
            Vec3::new(-0.9, 1.3, 1.2),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            3,
        ),
        quad(
            "sign",
            Vec3::new(1.3, 1.9, -1.0),
            Vec3::new(0.8, 0.0, 0.0),
            Vec3::new(0.0, -0.5, 0.0),
            4,
        ),
    ];
    Scene {
        meshes,
        materials,
        textures: textures(),
        lights: Vec::new(),
        environment: None,
    }
}
