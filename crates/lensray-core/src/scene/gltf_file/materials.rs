//! glTF materials as lensray's: `baseColorFactor` and `baseColorTexture` (sRGB) for the diffuse
//! colour, `emissiveFactor` x `KHR_materials_emissive_strength` and `emissiveTexture` (sRGB) for
//! the emission, the base colour's alpha (factor times texture) with `alphaMode` and
//! `alphaCutoff`, each texture with its sampler's wrap modes and `KHR_texture_transform`.
//! Images are read once each, from a buffer view, a data URI or a file beside the glTF.

use std::path::Path;

use base64::Engine;
use glam::{Affine2, Vec2, Vec3};
use gltf::texture::WrappingMode;

use super::nodes::Walk;
use crate::scene::texture::{decode_texture, Encoding, TextureRef, Wrap};
use crate::scene::{AlphaMode, Material};

impl Walk<'_> {
    /// The scene material of a glTF material (made on its first use).
    pub(super) fn material(&mut self, material: gltf::Material) -> Result<u32, String> {
        let slot = match material.index() {
            Some(i) => self.materials[i],
            None => self.default_material,
        };
        if let Some(id) = slot {
            return Ok(id);
        }
        let converted = self.convert(&material)?;
        let scene = &mut self.out.scene;
        scene.materials.push(converted);
        let id = (scene.materials.len() - 1) as u32;
        match material.index() {
            Some(i) => self.materials[i] = Some(id),
            None => self.default_material = Some(id),
        }
        Ok(id)
    }

    fn convert(&mut self, material: &gltf::Material) -> Result<Material, String> {
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, a] = pbr.base_color_factor();
        let strength = material.emissive_strength().unwrap_or(1.0);
        let name = material
            .name()
            .map(str::to_string)
            .unwrap_or_else(|| match material.index() {
                Some(i) => format!("material {i}"),
                None => "glTF default".into(),
            });
        let base = match pbr.base_color_texture() {
            Some(info) => self.texture_ref(&info)?,
            None => None,
        };
        let emissive = match material.emissive_texture() {
            Some(info) => self.texture_ref(&info)?,
            None => None,
        };
        let alpha_mode = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: material.alpha_cutoff().unwrap_or(0.5),
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        Ok(Material {
            diffuse: Vec3::new(r, g, b),
            emission: Vec3::from(material.emissive_factor()) * strength,
            diffuse_texture: base,
            emission_texture: emissive,
            alpha_mode,
            alpha: a,
            // The base colour texture's alpha is the coverage.
            alpha_texture: base,
            ..Material::new(&name, Vec3::ONE, Vec3::ZERO)
        })
    }

    /// The scene's reference to the texture of `info`: its image (decoded on first use), its
    /// sampler's wrap modes and its transform; `None` when its image file is missing.
    fn texture_ref(&mut self, info: &gltf::texture::Info) -> Result<Option<TextureRef>, String> {
        let texture = info.texture();
        let sampler = texture.sampler();
        let wrap = |mode: WrappingMode| match mode {
            WrappingMode::Repeat => Wrap::Repeat,
            WrappingMode::ClampToEdge => Wrap::ClampToEdge,
            WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        };
        let mut tex_coord = info.tex_coord();
        let mut uv_from_texcoord = Affine2::IDENTITY;
        if let Some(t) = info.texture_transform() {
            uv_from_texcoord = texture_transform(t.offset(), t.rotation(), t.scale());
            tex_coord = t.tex_coord().unwrap_or(tex_coord);
        }
        if tex_coord != 0 {
            self.other_texcoords = true;
        }
        Ok(self.image(&texture.source())?.map(|id| TextureRef {
            texture: id,
            wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
            uv_from_texcoord,
        }))
    }

    /// The scene texture of `image` (decoded on its first use; sRGB, as glTF's colour
    /// textures are); `None`, with a notice, when its file is missing: the material renders
    /// without it.
    fn image(&mut self, image: &gltf::Image) -> Result<Option<u32>, String> {
        let i = image.index();
        if let Some(id) = self.images[i] {
            return Ok(Some(id));
        }
        let name = image
            .name()
            .map_or_else(|| format!("image {i}"), str::to_string);
        let bytes = match self.image_bytes(image) {
            Ok(bytes) => bytes,
            Err(Missing::File(e)) => {
                self.out
                    .notices
                    .push(format!("{e}: its materials render without it"));
                return Ok(None);
            }
            Err(Missing::Broken(e)) => return Err(e),
        };
        let texture = decode_texture(&name, &bytes, Encoding::Srgb, &mut self.out.times)
            .map_err(|e| format!("{name} cannot be decoded: {e}"))?;
        let textures = &mut self.out.scene.textures;
        textures.push(texture);
        let id = (textures.len() - 1) as u32;
        self.images[i] = Some(id);
        Ok(Some(id))
    }

    /// The encoded bytes of `image`.
    fn image_bytes(&self, image: &gltf::Image) -> Result<Vec<u8>, Missing> {
        let what = format!("image {}", image.index());
        match image.source() {
            gltf::image::Source::View { view, .. } => {
                let buffer = self
                    .buffers
                    .get(view.buffer().index())
                    .map_or(&[][..], Vec::as_slice);
                buffer
                    .get(view.offset()..view.offset() + view.length())
                    .map(<[u8]>::to_vec)
                    .ok_or_else(|| {
                        let view = view.index();
                        Missing::Broken(format!("{what}: buffer view {view} is past its buffer"))
                    })
            }
            gltf::image::Source::Uri { uri, .. } => read_uri(uri, self.base).map_err(|e| match e {
                Missing::File(e) => Missing::File(format!("{what} ({}): {e}", shorten(uri))),
                Missing::Broken(e) => Missing::Broken(format!("{what} ({}): {e}", shorten(uri))),
            }),
        }
    }
}

/// Why an image's bytes are not there: a file that cannot be read (a warning), or a broken
/// reference (an error).
enum Missing {
    File(String),
    Broken(String),
}

/// The bytes a glTF URI names: a base64 data URI or a percent-encoded path relative to `base`.
fn read_uri(uri: &str, base: &Path) -> Result<Vec<u8>, Missing> {
    if let Some(data) = uri.strip_prefix("data:") {
        let (_, payload) = data
            .split_once(";base64,")
            .ok_or(Missing::Broken("a data URI without base64 content".into()))?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| Missing::Broken(format!("bad base64: {e}")));
    }
    let path = urlencoding::decode(uri).map_err(|e| Missing::Broken(e.to_string()))?;
    let path = base.join(path.as_ref());
    std::fs::read(&path).map_err(|e| Missing::File(format!("cannot read {}: {e}", path.display())))
}

/// A URI short enough for a message (data URIs are long).
fn shorten(uri: &str) -> String {
    if uri.chars().count() > 40 {
        format!("{}...", uri.chars().take(37).collect::<String>())
    } else {
        uri.to_string()
    }
}

/// `KHR_texture_transform`'s matrix: translation x rotation x scale (scale first, offset last),
/// with the rotation viewers apply: u' = cos u + sin v, v' = -sin u + cos v, counter-clockwise
/// in glTF's UV space, whose v axis points down. That is the glTF Sample Viewer's, three.js's,
/// Babylon.js's and Blender's convention, and what the TextureTransformTest sample's green
/// marker checks; the extension's sample GLSL (columns (cos, sin) and (-sin, cos)) is its
/// transpose, which turns the other way (KhronosGroup/glTF issue #1563).
pub(super) fn texture_transform(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Affine2 {
    let (sin, cos) = rotation.sin_cos();
    let rotate = glam::Mat2::from_cols(Vec2::new(cos, -sin), Vec2::new(sin, cos));
    let matrix = rotate * glam::Mat2::from_diagonal(Vec2::from(scale));
    Affine2::from_mat2_translation(matrix, Vec2::from(offset))
}

/// The features of the file's materials that the scene does not carry, by name.
pub(super) fn ignored_features(document: &gltf::Document) -> Vec<&'static str> {
    let mut ignored = Vec::new();
    let mut note = |used: bool, name| {
        if used && !ignored.contains(&name) {
            ignored.push(name);
        }
    };
    for m in document.materials() {
        let pbr = m.pbr_metallic_roughness();
        note(
            !m.double_sided(),
            "single-sided culling (every surface is seen from both sides)",
        );
        // What Lambert shading leaves out is the specular lobe, which a roughness under 1 or a
        // texture asks for. Fully rough, metal or not scatters close to Lambert (and glTF's
        // defaults, a material that says nothing, are metallic 1 and roughness 1).
        note(
            pbr.metallic_roughness_texture().is_some() || pbr.roughness_factor() < 1.0,
            "metallic-roughness",
        );
        note(m.normal_texture().is_some(), "normal maps");
        note(m.occlusion_texture().is_some(), "occlusion maps");
    }
    ignored
}
