//! The layers glTF's material extensions put over the metallic-roughness base:
//! `KHR_materials_clearcoat` (`clearcoatFactor` times `clearcoatTexture`'s R, and
//! `clearcoatRoughnessFactor` times `clearcoatRoughnessTexture`'s G, both linear, each texture
//! with its own `texCoord` and `KHR_texture_transform`) and `KHR_materials_sheen`
//! (`sheenColorFactor` times `sheenColorTexture`'s RGB, sRGB-encoded, and
//! `sheenRoughnessFactor` times `sheenRoughnessTexture`'s alpha, linear). The `gltf` crate
//! reads none of them: they are read from the material's JSON. The coat's own normal map
//! (`clearcoatNormalTexture`, linear, with its `scale`) tilts the coat's normal only; without
//! one the coat follows the interpolated vertex normal, even over a base with a normal map.
//! `KHR_materials_transmission` (`transmissionFactor` times `transmissionTexture`'s R),
//! `KHR_materials_ior` (`ior`) and `KHR_materials_volume` (a `thicknessFactor` above 0 makes
//! the mesh a volume's boundary; `attenuationColor` and `attenuationDistance` its
//! extinction) describe what goes through a dielectric. The thickness texture is not read:
//! rays measure the volume's thickness.

use glam::Vec3;
use gltf_json::Value;

use super::materials::json_transform;
use super::nodes::Walk;
use crate::interface::DEFAULT_IOR;
use crate::scene::texture::{Encoding, TextureRef};
use crate::scene::Material;

impl Walk<'_> {
    /// `material` with the layers its extensions describe.
    pub(super) fn layers(
        &mut self,
        gltf: &gltf::Material,
        mut material: Material,
    ) -> Result<Material, String> {
        if let Some(coat) = gltf.extension_value("KHR_materials_clearcoat") {
            let factor = |key: &str| number(coat, key).unwrap_or(0.0).clamp(0.0, 1.0);
            material.clearcoat = factor("clearcoatFactor");
            material.clearcoat_roughness = factor("clearcoatRoughnessFactor");
            material.clearcoat_texture =
                self.json_texture(coat.get("clearcoatTexture"), Encoding::Linear)?;
            material.clearcoat_roughness_texture =
                self.json_texture(coat.get("clearcoatRoughnessTexture"), Encoding::Linear)?;
            let normal = coat.get("clearcoatNormalTexture");
            material.clearcoat_normal_texture = self.json_texture(normal, Encoding::Linear)?;
            material.clearcoat_normal_scale =
                normal.and_then(|n| number(n, "scale")).unwrap_or(1.0);
        }
        if let Some(sheen) = gltf.extension_value("KHR_materials_sheen") {
            let colour = sheen
                .get("sheenColorFactor")
                .and_then(Value::as_array)
                .filter(|c| c.len() == 3)
                .map(|c| {
                    Vec3::from_array(std::array::from_fn(|i| c[i].as_f64().unwrap_or(0.0) as f32))
                });
            material.sheen_colour = colour.unwrap_or(Vec3::ZERO).clamp(Vec3::ZERO, Vec3::ONE);
            material.sheen_roughness = number(sheen, "sheenRoughnessFactor")
                .unwrap_or(0.0)
                .clamp(0.0, 1.0);
            material.sheen_colour_texture =
                self.json_texture(sheen.get("sheenColorTexture"), Encoding::Srgb)?;
            material.sheen_roughness_texture =
                self.json_texture(sheen.get("sheenRoughnessTexture"), Encoding::Linear)?;
        }
        if let Some(transmission) = gltf.extension_value("KHR_materials_transmission") {
            material.transmission = number(transmission, "transmissionFactor")
                .unwrap_or(0.0)
                .clamp(0.0, 1.0);
            material.transmission_texture =
                self.json_texture(transmission.get("transmissionTexture"), Encoding::Linear)?;
        }
        if let Some(ior) = gltf.extension_value("KHR_materials_ior") {
            material.ior = number(ior, "ior")
                .unwrap_or(DEFAULT_IOR)
                .clamp(1.0, MAX_IOR);
        }
        if let Some(volume) = gltf.extension_value("KHR_materials_volume") {
            material.thin = number(volume, "thicknessFactor").unwrap_or(0.0) <= 0.0;
            material.attenuation = attenuation(volume);
            // `doubleSided` has no effect on a volume's boundary (the extension says so): a
            // ray that entered it leaves through the back faces.
            material.double_sided |= !material.thin;
        }
        Ok(material)
    }

    /// The texture a JSON `textureInfo` names, its RGB of `encoding`, with its `texCoord` and
    /// transform; `None` where there is none, its index is out of range or its image is
    /// missing.
    fn json_texture(
        &mut self,
        info: Option<&Value>,
        encoding: Encoding,
    ) -> Result<Option<TextureRef>, String> {
        let Some(info) = info else {
            return Ok(None);
        };
        let Some(texture) = info
            .get("index")
            .and_then(Value::as_u64)
            .and_then(|i| self.document.textures().nth(i as usize))
        else {
            return Ok(None);
        };
        let tex_coord = info.get("texCoord").and_then(Value::as_u64).unwrap_or(0) as u32;
        let transform = info
            .get("extensions")
            .and_then(|e| e.get("KHR_texture_transform"));
        let (tex_coord, uv_from_texcoord) = json_transform(tex_coord, transform);
        self.texture_slot(texture, tex_coord, uv_from_texcoord, encoding)
    }
}

/// The largest index of refraction drawn (a diamond's is 2.42).
const MAX_IOR: f32 = 5.0;

/// A volume's extinction per unit length: -ln(attenuationColor) / attenuationDistance per
/// channel, 0 without a finite distance (the specification's default: no attenuation); a
/// colour channel of 0 is taken as 1e-4 (it would stop all light at once).
fn attenuation(volume: &Value) -> Vec3 {
    let Some(distance) = number(volume, "attenuationDistance").filter(|d| *d > 0.0) else {
        return Vec3::ZERO;
    };
    let colour = volume
        .get("attenuationColor")
        .and_then(Value::as_array)
        .filter(|c| c.len() == 3)
        .map(|c| Vec3::from_array(std::array::from_fn(|i| c[i].as_f64().unwrap_or(1.0) as f32)))
        .unwrap_or(Vec3::ONE);
    -colour.clamp(Vec3::splat(1e-4), Vec3::ONE).ln() / distance
}

/// A finite number at `key` of a JSON object.
fn number(object: &Value, key: &str) -> Option<f32> {
    object
        .get(key)
        .and_then(Value::as_f64)
        .map(|x| x as f32)
        .filter(|x| x.is_finite())
}

#[cfg(test)]
#[path = "layers_tests.rs"]
mod tests;
