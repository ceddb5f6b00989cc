//! The textured scene (`lensray generate textured`), written twice: as glTF (`textured.gltf`,
//! `textured.bin`) and as OBJ (`textured.obj`, `textured.mtl`, named by `textured.toml`), both
//! reading the same PNGs. Cards at four depths carry a checker (repeated), a word, a colour
//! gradient and a leaf cut out by its alpha; a checkered ground runs under them.
//!
//! The two files load to the same geometry, texture coordinates and textures, so they render
//! the same image, with one exception the formats impose: MTL has no alpha mask, and lensray
//! reads `map_d` as a stochastic cut (`AlphaMode::Blend`) where the glTF says `MASK` with cutoff
//! 0.5. The leaf's alpha is 0 or 1 in every texel, so the two agree everywhere but in the one
//! texel wide band along the leaf's edge where filtering mixes the two.
//!
//! Exactness: every normal is an axis (the loaders' normalisations leave it as it is), every
//! texture coordinate a whole number (OBJ's v is written as 1 - v and read back as 1 - that,
//! exactly), positions and factors are `f32` written in the shortest text that reads back to
//! them, and meshes, triangles and materials come in the same order in both files (a blend
//! cut's draw depends on the triangle's index).

mod gltf_out;
mod images;
mod obj_out;

use std::path::Path;

use anyhow::Context;
use glam::{Quat, Vec2, Vec3};

pub use images::ProceduralImage;

use super::file::write_scene_file;
use super::generate::quad;
use super::texture::{Encoding, TextureRef};
use super::{AlphaMode, Light, Material, Mesh, Scene, Texture};
use crate::settings::{LightSettings, Lights, Settings};

/// The file stem of the scene's files.
pub const NAME: &str = "textured";

/// The glTF camera the scene is seen through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexturedCamera {
    pub eye: Vec3,
    /// How far the view turns down from the horizon (a rotation about +x).
    pub pitch_degrees: f32,
    pub yfov_degrees: f32,
    pub aspect_ratio: f32,
    pub znear: f32,
}

impl TexturedCamera {
    /// The camera node's rotation: the view (-Z) turned down by the pitch.
    pub fn rotation(&self) -> Quat {
        Quat::from_rotation_x(-self.pitch_degrees.to_radians())
    }
}

/// The scene with the images its textures are made of (`scene.textures[i]` is `images[i]`)
/// and its camera.
#[derive(Clone, Debug, PartialEq)]
pub struct TexturedScene {
    pub scene: Scene,
    pub images: Vec<ProceduralImage>,
    pub camera: TexturedCamera,
}

/// A card of `size` upright in the plane z = `corner.z`, its lower left corner at `corner`,
/// facing +z, reading `repeats` copies of its texture across and down (v down the card, as
/// images are stored).
fn card(name: &str, corner: Vec3, size: Vec2, repeats: Vec2, material: u32) -> Mesh {
    let mut mesh = quad(name, corner, Vec3::X * size.x, Vec3::Y * size.y, material);
    for t in &mut mesh.texcoords {
        *t = Vec2::new(t.x, 1.0 - t.y) * repeats;
    }
    // Exactly +z (the normalised cross product of the edges may be an ulp short).
    mesh.normals.fill(Vec3::Z);
    mesh
}

/// A material whose diffuse colour is `factor` times texture `texture` (repeated, as the glTF's
/// sampler says and as MTL's maps do).
fn textured(name: &str, factor: Vec3, texture: u32) -> Material {
    Material {
        diffuse_texture: Some(TextureRef::new(texture)),
        ..Material::new(name, factor, Vec3::ZERO)
    }
}

/// The scene: 10 triangles, four 64-128 texel images.
pub fn textured_scene() -> TexturedScene {
    let images = vec![
        images::checker(),
        images::text(),
        images::gradient(),
        images::leaf(),
    ];
    let [checker, text, gradient, leaf] = [0, 1, 2, 3];
    let leaf_texture = Some(TextureRef::new(leaf));
    let materials = vec![
        textured("ground", Vec3::splat(0.6), checker),
        textured("checker", Vec3::ONE, checker),
        textured("text", Vec3::ONE, text),
        textured("gradient", Vec3::new(1.0, 0.9, 0.8), gradient),
        Material {
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            alpha_texture: leaf_texture,
            ..textured("leaf", Vec3::ONE, leaf)
        },
    ];
    // Facing +y: u along +x, v along -z; one checker texture per metre.
    let mut ground = quad(
        "ground",
        Vec3::new(-6.0, 0.0, 5.0),
        Vec3::X * 12.0,
        Vec3::NEG_Z * 16.0,
        0,
    );
    for t in &mut ground.texcoords {
        *t *= Vec2::new(12.0, 16.0);
    }
    ground.normals.fill(Vec3::Y);
    // Cards reach 5 cm into the ground, so that their foot is a crossing, not a shared edge.
    let meshes = vec![
        ground,
        card(
            "checker",
            Vec3::new(-2.0, -0.05, -0.5),
            Vec2::splat(1.4),
            Vec2::splat(2.0),
            1,
        ),
        card(
            "text",
            Vec3::new(-0.1, 1.4, 1.0),
            Vec2::new(1.6, 0.4),
            Vec2::ONE,
            2,
        ),
        card(
            "gradient",
            Vec3::new(0.0, -0.05, -3.5),
            Vec2::new(2.4, 1.2),
            Vec2::ONE,
            3,
        ),
        card(
            "leaf",
            Vec3::new(-1.15, 0.75, 2.4),
            Vec2::splat(0.8),
            Vec2::ONE,
            4,
        ),
    ];
    let textures = images
        .iter()
        .map(|i| Texture::from_rgba8(&i.file, i.width, i.height, &i.rgba, Encoding::Srgb))
        .collect();
    TexturedScene {
        scene: Scene {
            meshes,
            materials,
            textures,
            lights: vec![LIGHT],
            environment: None,
        },
        images,
        camera: TexturedCamera {
            eye: Vec3::new(0.0, 1.5, 5.0),
            pitch_degrees: 8.0,
            yfov_degrees: 40.0,
            aspect_ratio: 4.0 / 3.0,
            znear: 0.05,
        },
    }
}

/// The scene's light: a point light above and to the left of the camera, whose shadows fall
/// behind the cards and to the right (W/sr; the glTF's candela).
pub const LIGHT: Light = Light::point(Vec3::new(-2.0, 4.0, 4.0), Vec3::splat(40.0));

/// One line on what the scene shows.
pub const DESCRIPTION: &str = "Textured cards at four depths (a checker, a word, a colour gradient and a leaf cut out by its alpha) over a checkered ground; textured.gltf holds the same scene.";

/// Writes the scene's files into `dir`: the PNGs, `textured.gltf` and `.bin`, `textured.obj`
/// and `.mtl`, and last `textured.toml`, a scene file naming the OBJ with the glTF's camera as
/// lensray reads it (so both render the same shot). Returns the files' names in that order.
pub fn write_textured(dir: &Path) -> anyhow::Result<Vec<String>> {
    let textured = textured_scene();
    let mut written = Vec::new();
    for image in &textured.images {
        let png = image
            .png()
            .with_context(|| format!("cannot encode {}", image.file))?;
        std::fs::write(dir.join(&image.file), png)
            .with_context(|| format!("cannot write {}", image.file))?;
        written.push(image.file.clone());
    }
    let gltf = format!("{NAME}.gltf");
    written.extend(gltf_out::write_gltf(&textured, dir, NAME)?);
    written.extend(obj_out::write_obj_with_maps(&textured, dir, NAME)?);

    // The camera exactly as the glTF loader makes it, for the OBJ's scene file.
    let loaded =
        super::load_gltf(&dir.join(&gltf)).with_context(|| format!("cannot read back {gltf}"))?;
    let camera = loaded
        .cameras
        .first()
        .context("the written glTF has no camera")?;
    let mut settings = Settings::default();
    camera.apply(&mut settings, &loaded.scene);
    // The glTF's lights, as the scene file's.
    settings.light = Lights(
        loaded
            .scene
            .lights
            .iter()
            .map(|l| LightSettings {
                position: Some(l.position.as_dvec3().to_array()),
                intensity: Some(l.intensity.as_dvec3().to_array()),
                ..LightSettings::default()
            })
            .collect(),
    );
    let toml = format!("{NAME}.toml");
    let comment = format!(
        "lensray generate {NAME}\n{DESCRIPTION}\n{} triangles. Units are metres; `mesh` is relative to this file.\n\
         The camera is {gltf}'s; the OBJ's leaf is blended where the glTF's is masked (MTL has no mask).",
        textured.scene.triangle_count()
    );
    write_scene_file(
        &dir.join(&toml),
        &format!("{NAME}.obj"),
        &settings,
        &comment,
    )
    .with_context(|| format!("cannot write {toml}"))?;
    written.push(toml);
    Ok(written)
}
