//! Materials: glTF's metallic-roughness model (a base colour, metallic and roughness; the BRDF
//! is `reference::brdf`) and an emission, each a factor times an optional texture, and how much
//! of a surface is there (alpha).

use glam::Vec3;

use crate::interface::DEFAULT_IOR;

use super::texture::{sample, sample_finest, FootprintSets, TexcoordSets, Texture, TextureRef};

/// How a material's alpha (its factor times its coverage texture's alpha) decides whether a ray
/// that meets the surface stops there (glTF's `alphaMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is everywhere.
    #[default]
    Opaque,
    /// The surface is where alpha >= the cutoff.
    Mask { cutoff: f32 },
    /// A ray stops with probability alpha (a stochastic cut, drawn per ray and surface): the
    /// average of the samples is the surface blended over what lies behind it, without sorting.
    Blend,
}

/// Linear RGB base colour and emission of a surface, with their textures, and its metallic and
/// roughness.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// The base colour: `Kd` / `baseColorFactor` (what `unlit` shows).
    pub diffuse: Vec3,
    /// 0: a dielectric; 1: a metal (`metallicFactor`; `Pm`).
    pub metallic: f32,
    /// Perceptual roughness in [0, 1] (`roughnessFactor`; `Pr`).
    pub roughness: f32,
    /// The weight in [0, 1] of a dielectric's specular lobe (`KHR_materials_specular`'s
    /// `specularFactor`): 1 in glTF's materials; 0, a Lambert surface, in materials that say
    /// nothing of specular reflection (an MTL without `Ks`, the built-in scenes).
    pub specular: f32,
    /// `Ke` / `emissiveFactor` x strength.
    pub emission: Vec3,
    /// Multiplies `diffuse` (`map_Kd`, `baseColorTexture`).
    pub diffuse_texture: Option<TextureRef>,
    /// Multiplies `emission` (`map_Ke`, `emissiveTexture`).
    pub emission_texture: Option<TextureRef>,
    /// Linear; its blue channel multiplies `metallic` and its green `roughness`
    /// (`metallicRoughnessTexture`).
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Linear; its red channel R is the share of the environment's light that reaches the
    /// surface, 1 + `occlusion_strength` (R - 1) (`occlusionTexture`). The scene's lights are
    /// not weighed: their shadow rays find what blocks them.
    pub occlusion_texture: Option<TextureRef>,
    pub occlusion_strength: f32,
    /// Linear; a tangent-space normal map (`normalTexture`, MTL's `norm`): RGB in [0, 1] is
    /// the normal 2 RGB - 1 in the frame (tangent, bitangent, normal) of the mesh's `tangents`.
    pub normal_texture: Option<TextureRef>,
    /// Multiplies the normal map's x and y (`normalTexture.scale`).
    pub normal_scale: f32,
    /// `KHR_materials_clearcoat`'s `clearcoatFactor`: the weight in [0, 1] of a clear coat
    /// over the surface (0: none; `reference::clearcoat`).
    pub clearcoat: f32,
    /// Linear; its red channel multiplies `clearcoat` (`clearcoatTexture`).
    pub clearcoat_texture: Option<TextureRef>,
    /// The coat's perceptual roughness in [0, 1] (`clearcoatRoughnessFactor`).
    pub clearcoat_roughness: f32,
    /// Linear; its green channel multiplies `clearcoat_roughness`
    /// (`clearcoatRoughnessTexture`).
    pub clearcoat_roughness_texture: Option<TextureRef>,
    /// Linear; the coat's own tangent-space normal map (`clearcoatNormalTexture`), read as
    /// `normal_texture` is. Without it the coat follows the interpolated vertex normal, not
    /// the base's normal map, as the extension says.
    pub clearcoat_normal_texture: Option<TextureRef>,
    /// Multiplies the coat's normal map's x and y (`clearcoatNormalTexture.scale`).
    pub clearcoat_normal_scale: f32,
    /// `KHR_materials_transmission`'s `transmissionFactor`: the share in [0, 1] of the
    /// dielectric's unreflected light that goes through the surface instead of diffusing
    /// (`reference::transmission`).
    pub transmission: f32,
    /// Linear; its red channel multiplies `transmission` (`transmissionTexture`).
    pub transmission_texture: Option<TextureRef>,
    /// The dielectric's index of refraction (`KHR_materials_ior`, `DEFAULT_IOR` without).
    pub ior: f32,
    /// Whether the surface is a thin wall, which transmits without refracting: glTF's
    /// default; `KHR_materials_volume` with a thickness makes the mesh a volume's boundary.
    pub thin: bool,
    /// The volume's extinction per unit length, -ln(attenuationColor) / attenuationDistance
    /// per channel (0: clear); light that crosses the volume keeps exp(-attenuation d).
    pub attenuation: Vec3,
    /// `KHR_materials_sheen`'s `sheenColorFactor`: the linear colour of a sheen over the
    /// surface (black: none; `reference::sheen`).
    pub sheen_colour: Vec3,
    /// sRGB; its RGB multiplies `sheen_colour` (`sheenColorTexture`).
    pub sheen_colour_texture: Option<TextureRef>,
    /// The sheen's perceptual roughness in [0, 1] (`sheenRoughnessFactor`).
    pub sheen_roughness: f32,
    /// Linear; its alpha channel multiplies `sheen_roughness` (`sheenRoughnessTexture`).
    pub sheen_roughness_texture: Option<TextureRef>,
    pub alpha_mode: AlphaMode,
    /// `d` / the base colour factor's alpha.
    pub alpha: f32,
    /// Its alpha channel multiplies `alpha` (`map_d`; glTF: the base colour texture).
    pub alpha_texture: Option<TextureRef>,
    /// Seen from both sides (glTF's `doubleSided`; OBJ and the built-in scenes: always). A
    /// single-sided surface is culled from behind on every path, for every ray: a ray whose
    /// direction d meets a triangle (v0, v1, v2) with d . ((v1 - v0) x (v2 - v0)) > 0, that is
    /// one that sees the triangle clockwise, reaches its back face and passes through it
    /// ([`crate::reference::is_back_face`]).
    pub double_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self::new("default", Vec3::splat(0.8), Vec3::ZERO)
    }
}

impl Material {
    /// An opaque, untextured Lambert surface (a dielectric without specular reflection).
    pub fn new(name: &str, diffuse: Vec3, emission: Vec3) -> Self {
        Self {
            name: name.into(),
            diffuse,
            metallic: 0.0,
            roughness: 1.0,
            specular: 0.0,
            emission,
            diffuse_texture: None,
            emission_texture: None,
            metallic_roughness_texture: None,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            normal_texture: None,
            normal_scale: 1.0,
            clearcoat: 0.0,
            clearcoat_texture: None,
            clearcoat_roughness: 0.0,
            clearcoat_roughness_texture: None,
            clearcoat_normal_texture: None,
            clearcoat_normal_scale: 1.0,
            transmission: 0.0,
            transmission_texture: None,
            ior: DEFAULT_IOR,
            thin: true,
            attenuation: Vec3::ZERO,
            sheen_colour: Vec3::ZERO,
            sheen_colour_texture: None,
            sheen_roughness: 0.0,
            sheen_roughness_texture: None,
            alpha_mode: AlphaMode::Opaque,
            alpha: 1.0,
            alpha_texture: None,
            double_sided: true,
        }
    }

    /// The diffuse colour at texture coordinates `texcoords`, filtered over `footprints`.
    pub fn diffuse_at(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        footprints: &FootprintSets,
    ) -> Vec3 {
        match &self.diffuse_texture {
            Some(t) => self.diffuse * sample(textures, t, texcoords, footprints).truncate(),
            None => self.diffuse,
        }
    }

    /// The emission at texture coordinates `texcoords`, filtered over `footprints`.
    pub fn emission_at(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        footprints: &FootprintSets,
    ) -> Vec3 {
        match &self.emission_texture {
            Some(t) if self.emission != Vec3::ZERO => {
                self.emission * sample(textures, t, texcoords, footprints).truncate()
            }
            _ => self.emission,
        }
    }

    /// Metallic and roughness at texture coordinates `texcoords`, filtered over `footprints`.
    pub fn metallic_roughness_at(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        footprints: &FootprintSets,
    ) -> (f32, f32) {
        match &self.metallic_roughness_texture {
            Some(t) => {
                let texel = sample(textures, t, texcoords, footprints);
                (self.metallic * texel.z, self.roughness * texel.y)
            }
            None => (self.metallic, self.roughness),
        }
    }

    /// The share of the environment's light that reaches the surface at texture coordinates
    /// `texcoords`, filtered over `footprints`.
    pub fn occlusion_at(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        footprints: &FootprintSets,
    ) -> f32 {
        match &self.occlusion_texture {
            Some(t) => {
                let r = sample(textures, t, texcoords, footprints).x;
                1.0 + self.occlusion_strength * (r - 1.0)
            }
            None => 1.0,
        }
    }

    /// The clear coat (weight, roughness) at texture coordinates `texcoords`, filtered over
    /// `footprints`.
    pub fn clearcoat_at(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        footprints: &FootprintSets,
    ) -> (f32, f32) {
        let weight = match &self.clearcoat_texture {
            Some(t) if self.clearcoat > 0.0 => {
                self.clearcoat * sample(textures, t, texcoords, footprints).x
            }
            _ => self.clearcoat,
        };
        let roughness = match &self.clearcoat_roughness_texture {
            Some(t) if weight > 0.0 => {
                self.clearcoat_roughness * sample(textures, t, texcoords, footprints).y
            }
            _ => self.clearcoat_roughness,
        };
        (weight, roughness)
    }

    /// The transmission's share at texture coordinates `texcoords`, filtered over
    /// `footprints`.
    pub fn transmission_at(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        footprints: &FootprintSets,
    ) -> f32 {
        match &self.transmission_texture {
            Some(t) if self.transmission > 0.0 => {
                self.transmission * sample(textures, t, texcoords, footprints).x
            }
            _ => self.transmission,
        }
    }

    /// The sheen (colour, roughness) at texture coordinates `texcoords`, filtered over
    /// `footprints`; the textures are read only where the factor leaves a sheen.
    pub fn sheen_at(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        footprints: &FootprintSets,
    ) -> (Vec3, f32) {
        let colour = match &self.sheen_colour_texture {
            Some(t) if self.sheen_colour.max_element() > 0.0 => {
                self.sheen_colour * sample(textures, t, texcoords, footprints).truncate()
            }
            _ => self.sheen_colour,
        };
        let roughness = match &self.sheen_roughness_texture {
            Some(t) if colour.max_element() > 0.0 => {
                self.sheen_roughness * sample(textures, t, texcoords, footprints).w
            }
            _ => self.sheen_roughness,
        };
        (colour, roughness)
    }

    /// The base's normal map and its scale; `None` without one.
    pub fn normal_map(&self) -> Option<(TextureRef, f32)> {
        self.normal_texture.map(|t| (t, self.normal_scale))
    }

    /// The clear coat's own normal map and its scale; `None` without one.
    pub fn clearcoat_normal_map(&self) -> Option<(TextureRef, f32)> {
        self.clearcoat_normal_texture
            .map(|t| (t, self.clearcoat_normal_scale))
    }

    /// Whether any of the colours `lit` shading reads comes from a texture.
    pub fn is_textured(&self) -> bool {
        self.diffuse_texture.is_some()
            || self.emission_texture.is_some()
            || self.metallic_roughness_texture.is_some()
            || self.occlusion_texture.is_some()
            || self.normal_texture.is_some()
            || self.clearcoat_texture.is_some()
            || self.clearcoat_roughness_texture.is_some()
            || self.clearcoat_normal_texture.is_some()
            || self.transmission_texture.is_some()
            || self.sheen_colour_texture.is_some()
            || self.sheen_roughness_texture.is_some()
    }

    /// Whether rays may pass through the surface somewhere: what acceleration structures mark
    /// as not opaque.
    pub fn is_alpha_tested(&self) -> bool {
        self.alpha_mode != AlphaMode::Opaque
    }

    /// Alpha at texture coordinates `texcoords`, read at the finest level.
    pub fn alpha_at(&self, textures: &[Texture], texcoords: &TexcoordSets) -> f32 {
        match &self.alpha_texture {
            Some(t) => self.alpha * sample_finest(textures, t, texcoords).w,
            None => self.alpha,
        }
    }

    /// Whether a ray stops at the surface at `texcoords`; `threshold` in [0, 1) is the ray's
    /// draw for `Blend` (`blend_threshold`).
    pub fn stops_ray(
        &self,
        textures: &[Texture],
        texcoords: &TexcoordSets,
        threshold: f32,
    ) -> bool {
        match self.alpha_mode {
            AlphaMode::Opaque => true,
            AlphaMode::Mask { cutoff } => self.alpha_at(textures, texcoords) >= cutoff,
            AlphaMode::Blend => self.alpha_at(textures, texcoords) > threshold,
        }
    }
}

/// Salts of the blend draws of camera and shadow rays (apart from each other and from the
/// sampler's uses of the sample key).
pub use crate::interface::{AOV_BLEND_THRESHOLD, BLEND_CAMERA_SALT, BLEND_SHADOW_SALT};

/// The draw in [0, 1) that decides whether the ray of `ray_key` stops at `Blend` triangle
/// `triangle` (the global triangle index of the GPU's flattened scene): independent between
/// surfaces along one ray, the same on every path.
pub fn blend_threshold(ray_key: u32, triangle: u32) -> f32 {
    use crate::sampler::{hash_u32, unit_float};
    unit_float(hash_u32(ray_key ^ hash_u32(triangle)))
}

/// The key of the camera ray (`BLEND_CAMERA_SALT`) or shadow ray (`BLEND_SHADOW_SALT`) of
/// sample `sample_index` of pixel `pixel_index`. The AOVs' aperture-centre ray draws nothing:
/// a `Blend` surface stops it where alpha > `AOV_BLEND_THRESHOLD`.
pub fn ray_key(seed: u32, pixel_index: u32, sample_index: u32, salt: u32) -> u32 {
    crate::sampler::sample_key(seed, pixel_index, sample_index) ^ salt
}
