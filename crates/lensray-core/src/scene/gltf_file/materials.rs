//! glTF materials as lensray's: `baseColorFactor` and `baseColorTexture` (sRGB) for the base
//! colour, `metallicFactor` and `roughnessFactor` times `metallicRoughnessTexture`'s B and G
//! (linear; `KHR_materials_specular`'s `specularFactor` weighs the dielectric's specular lobe),
//! `occlusionTexture`'s R with its strength (linear), `normalTexture` with its scale (linear, in
//! the frame of the mesh's tangents: `scene::tangents`), `emissiveFactor` x
//! `KHR_materials_emissive_strength` and `emissiveTexture` (sRGB) for the emission, the base
//! colour's alpha (factor times texture) with `alphaMode` and `alphaCutoff`, each texture with
//! its sampler's wrap modes, its `texCoord` set (TEXCOORD_0 or TEXCOORD_1; a higher set reads
//! TEXCOORD_0, with a notice) and its `KHR_texture_transform`, and `doubleSided` (false, glTF's
//! default: culled from behind, `Material::double_sided`). Images are read once each as colour
//! and once as data, from a buffer view, a data URI or a file beside the glTF; a missing file
//! is reported once.

use glam::{Affine2, Vec2, Vec3};
use gltf::texture::WrappingMode;

use super::nodes::Walk;
use super::{read_uri, Missing};
use crate::scene::texture::{decode_texture, Encoding, TextureRef, Wrap, TEXCOORD_SETS};
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
        if material.index().is_none() {
            // glTF's default material is a fully rough metal; a file that gives none is drawn
            // as the white Lambert surface of the other formats' files without materials,
            // single-sided as glTF's default is.
            return Ok(Material {
                double_sided: false,
                ..Material::new("glTF default", Vec3::ONE, Vec3::ZERO)
            });
        }
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
            Some(info) => self.texture_ref(&info, Encoding::Srgb)?,
            None => None,
        };
        let emissive = match material.emissive_texture() {
            Some(info) => self.texture_ref(&info, Encoding::Srgb)?,
            None => None,
        };
        let metallic_roughness = match pbr.metallic_roughness_texture() {
            Some(info) => self.texture_ref(&info, Encoding::Linear)?,
            None => None,
        };
        let occlusion = material.occlusion_texture();
        let occlusion_texture = match &occlusion {
            Some(o) => {
                let (tex_coord, uv_from_texcoord) =
                    json_transform(o.tex_coord(), o.extension_value("KHR_texture_transform"));
                self.texture_slot(o.texture(), tex_coord, uv_from_texcoord, Encoding::Linear)?
            }
            None => None,
        };
        let (normal_texture, normal_scale) = self.normal_texture(material)?;
        let alpha_mode = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: material.alpha_cutoff().unwrap_or(0.5),
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        let base = Material {
            diffuse: Vec3::new(r, g, b),
            metallic: pbr.metallic_factor().clamp(0.0, 1.0),
            roughness: pbr.roughness_factor().clamp(0.0, 1.0),
            specular: material
                .specular()
                .map_or(1.0, |s| s.specular_factor().clamp(0.0, 1.0)),
            emission: Vec3::from(material.emissive_factor()) * strength,
            diffuse_texture: base,
            emission_texture: emissive,
            alpha_mode,
            alpha: a,
            metallic_roughness_texture: metallic_roughness,
            occlusion_texture,
            occlusion_strength: occlusion.map_or(1.0, |o| o.strength().clamp(0.0, 1.0)),
            normal_texture,
            normal_scale,
            // The base colour texture's alpha is the coverage.
            alpha_texture: base,
            double_sided: material.double_sided(),
            ..Material::new(&name, Vec3::ONE, Vec3::ZERO)
        };
        self.layers(material, base)
    }

    /// The material's normal map (linear) with its transform, and its scale.
    fn normal_texture(
        &mut self,
        material: &gltf::Material,
    ) -> Result<(Option<TextureRef>, f32), String> {
        let Some(normal) = material.normal_texture() else {
            return Ok((None, 1.0));
        };
        let (tex_coord, uv_from_texcoord) = json_transform(
            normal.tex_coord(),
            normal.extension_value("KHR_texture_transform"),
        );
        let texture = normal.texture();
        let slot = self.texture_slot(texture, tex_coord, uv_from_texcoord, Encoding::Linear)?;
        Ok((slot, normal.scale()))
    }

    /// The scene's reference to the texture of `info`: its image (decoded on first use, as
    /// `encoding`), its sampler's wrap modes and its transform; `None` when its image file is
    /// missing.
    fn texture_ref(
        &mut self,
        info: &gltf::texture::Info,
        encoding: Encoding,
    ) -> Result<Option<TextureRef>, String> {
        let mut tex_coord = info.tex_coord();
        let mut uv_from_texcoord = Affine2::IDENTITY;
        if let Some(t) = info.texture_transform() {
            uv_from_texcoord = texture_transform(t.offset(), t.rotation(), t.scale());
            tex_coord = t.tex_coord().unwrap_or(tex_coord);
        }
        self.texture_slot(info.texture(), tex_coord, uv_from_texcoord, encoding)
    }

    /// The scene's reference to `texture` read at set `tex_coord` through `uv_from_texcoord`,
    /// its image decoded as `encoding`. A set past TEXCOORD_1 reads TEXCOORD_0 (the meshes carry
    /// two), with one notice for the file.
    pub(super) fn texture_slot(
        &mut self,
        texture: gltf::Texture,
        tex_coord: u32,
        uv_from_texcoord: Affine2,
        encoding: Encoding,
    ) -> Result<Option<TextureRef>, String> {
        let sampler = texture.sampler();
        let wrap = |mode: WrappingMode| match mode {
            WrappingMode::Repeat => Wrap::Repeat,
            WrappingMode::ClampToEdge => Wrap::ClampToEdge,
            WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        };
        let texcoord_set = if (tex_coord as usize) < TEXCOORD_SETS {
            tex_coord
        } else {
            self.other_texcoords.get_or_insert(tex_coord);
            0
        };
        Ok(self
            .image(&texture.source(), encoding)?
            .map(|id| TextureRef {
                texture: id,
                wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
                texcoord_set,
                uv_from_texcoord,
            }))
    }

    /// The scene texture of `image` decoded as `encoding` (on its first use so; glTF's colour
    /// textures are sRGB, its data textures linear); `None` when its file is missing: the
    /// material renders without it. The notice of a missing file comes on its first use alone,
    /// however many textures and encodings use it.
    fn image(&mut self, image: &gltf::Image, encoding: Encoding) -> Result<Option<u32>, String> {
        let i = image.index();
        let e = usize::from(encoding == Encoding::Linear);
        match self.images[i][e] {
            Some(ImageSlot::Texture(id)) => return Ok(Some(id)),
            Some(ImageSlot::Missing) => return Ok(None),
            None => {}
        }
        let name = image
            .name()
            .map_or_else(|| format!("image {i}"), str::to_string);
        let bytes = match self.image_bytes(image) {
            Ok((bytes, note)) => {
                // Once per image: the sRGB and the linear decode read the same file.
                if self.images[i][1 - e].is_none() {
                    self.out.notices.extend(note);
                }
                bytes
            }
            Err(Missing::File(e)) => {
                self.out
                    .notices
                    .push(format!("{e}: its materials render without it"));
                self.images[i] = [Some(ImageSlot::Missing); 2];
                return Ok(None);
            }
            Err(Missing::Broken(e)) => return Err(e),
        };
        let texture = decode_texture(&name, &bytes, encoding, &mut self.out.times)
            .map_err(|e| format!("{name} cannot be decoded: {e}"))?;
        let textures = &mut self.out.scene.textures;
        textures.push(texture);
        let id = (textures.len() - 1) as u32;
        self.images[i][e] = Some(ImageSlot::Texture(id));
        Ok(Some(id))
    }

    /// The encoded bytes of `image`, and the note a file outside the glTF's folder is read
    /// with.
    fn image_bytes(&self, image: &gltf::Image) -> Result<(Vec<u8>, Option<String>), Missing> {
        let what = format!("image {}", image.index());
        match image.source() {
            gltf::image::Source::View { view, .. } => {
                let buffer = self
                    .buffers
                    .get(view.buffer().index())
                    .map_or(&[][..], Vec::as_slice);
                buffer
                    .get(view.offset()..view.offset() + view.length())
                    .map(|bytes| (bytes.to_vec(), None))
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

/// A glTF image as the scene holds it, once read: a texture, or a file that is missing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum ImageSlot {
    Texture(u32),
    Missing,
}

/// A URI short enough for a message (data URIs are long).
fn shorten(uri: &str) -> String {
    if uri.chars().count() > 40 {
        format!("{}...", uri.chars().take(37).collect::<String>())
    } else {
        uri.to_string()
    }
}

/// The set and transform of a texture whose `KHR_texture_transform` is the JSON `extension`
/// (the `gltf` crate reads the extension on a material's base colour, emissive and
/// metallic-roughness textures alone): the extension's `texCoord` overrides the texture's
/// `tex_coord`.
pub(super) fn json_transform(
    tex_coord: u32,
    extension: Option<&gltf::json::Value>,
) -> (u32, Affine2) {
    let Some(t) = extension else {
        return (tex_coord, Affine2::IDENTITY);
    };
    let pair = |key: &str, default: [f32; 2]| match t
        .get(key)
        .and_then(|v| v.as_array())
        .map(|a| &a[..])
    {
        Some([a, b]) => match (a.as_f64(), b.as_f64()) {
            (Some(a), Some(b)) => [a as f32, b as f32],
            _ => default,
        },
        _ => default,
    };
    let rotation = t.get("rotation").and_then(|r| r.as_f64()).unwrap_or(0.0);
    let uv_from_texcoord = texture_transform(
        pair("offset", [0.0; 2]),
        rotation as f32,
        pair("scale", [1.0; 2]),
    );
    let set = t.get("texCoord").and_then(|c| c.as_u64());
    (set.map_or(tex_coord, |s| s as u32), uv_from_texcoord)
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
        note(
            m.specular().is_some_and(|s| {
                s.specular_texture().is_some()
                    || s.specular_color_texture().is_some()
                    || s.specular_color_factor() != [1.0; 3]
            }),
            "KHR_materials_specular's colour and textures",
        );
    }
    ignored
}

#[cfg(test)]
#[path = "texcoord_tests.rs"]
pub(super) mod texcoord_tests;
