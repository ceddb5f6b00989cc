//! Material libraries: reading an MTL file for tobj, and mapping tobj's materials to
//! [`Material`]s.

use std::fmt::Write as _;
use std::fs;
use std::path::Path;

use glam::Vec3;

use super::textures::{bump_multiplier, Kind, TextureFiles};
use crate::scene::{AlphaMode, Material, SceneError};

/// The scene material of an MTL material read from `dir`: `Kd` the base colour (the
/// default's when absent; white under a `map_Kd` without `Kd`), metallic and roughness from
/// `Pm`, `Pr`, `Ks` and `Ns` (`metallic_roughness`), `Ke` the emission (0 when absent; white
/// under a `map_Ke` without `Ke`), `d` times `map_d` the coverage, cut stochastically where it
/// is below 1 (`AlphaMode::Blend`: the average over samples is the partly covered surface),
/// `map_Pr` and `map_Pm` times their factors, `norm` a tangent-space normal map (`-bm` its
/// scale). `map_Bump` is left with a notice: it is as often a height map as a normal map.
pub(super) fn convert_material(
    m: &tobj::Material,
    dir: &Path,
    files: &mut TextureFiles,
) -> Result<Material, SceneError> {
    let default = Material::default();
    let emission = m
        .emissive
        .or_else(|| m.unknown_param.get("Ke").and_then(|s| parse_colour(s).ok()));
    let name = &m.name;
    let mut texture = |value: Option<&String>, kind| match value {
        Some(value) => files.get(dir, value, kind, name),
        None => Ok(None),
    };
    let diffuse_texture = texture(m.diffuse_texture.as_ref(), Kind::Colour)?;
    let emission_texture = texture(m.unknown_param.get("map_Ke"), Kind::Colour)?;
    let alpha_texture = texture(m.dissolve_texture.as_ref(), Kind::Coverage)?;
    let alpha = m.dissolve.unwrap_or(1.0).clamp(0.0, 1.0);
    let param = |key: &str| m.unknown_param.get(key).map(String::as_str);
    let (map_pr, map_pm) = (param("map_Pr"), param("map_Pm"));
    let normal_texture = texture(m.unknown_param.get("norm"), Kind::Data)?;
    let metallic_roughness_texture = files.metallic_roughness(dir, map_pr, map_pm, name)?;
    if m.normal_texture.is_some() {
        files.notices.push(format!(
            "material {name}: renders without its map_Bump (a bump map may be a height map; \
             lensray reads tangent-space normal maps from `norm`)"
        ));
    }
    let (mut metallic, mut roughness, mut specular) = metallic_roughness(m);
    // A map without its factor is read whole (factor 1), as glTF's maps are.
    if metallic_roughness_texture.is_some() {
        specular = 1.0;
        if map_pm.is_some() && param("Pm").is_none() {
            metallic = 1.0;
        }
        if map_pr.is_some() && param("Pr").is_none() {
            roughness = 1.0;
        }
    }
    let textured_white = |texture: bool, fallback: Vec3| if texture { Vec3::ONE } else { fallback };
    Ok(Material {
        name: name.clone(),
        diffuse: m
            .diffuse
            .map(Vec3::from)
            .unwrap_or(textured_white(diffuse_texture.is_some(), default.diffuse)),
        metallic,
        roughness,
        specular,
        emission: emission
            .map(Vec3::from)
            .unwrap_or(textured_white(emission_texture.is_some(), Vec3::ZERO)),
        diffuse_texture,
        emission_texture,
        alpha_mode: if alpha < 1.0 || alpha_texture.is_some() {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        },
        alpha,
        alpha_texture,
        metallic_roughness_texture,
        normal_scale: param("norm").map_or(1.0, bump_multiplier),
        normal_texture,
        ..default
    })
}

/// The metallic, roughness and specular weight of an MTL material: the PBR extension's `Pm` and `Pr`
/// where given (a glTF material), else from the Phong terms: no `Ks` (or a black one) is a
/// Lambert surface; a `Ks` gives the dielectric's specular lobe, its roughness from the
/// shininess `Ns` as sqrt(2 / (Ns + 2)), the roughness whose Beckmann lobe the Blinn-Phong
/// exponent Ns matches (1 without `Ns`).
fn metallic_roughness(m: &tobj::Material) -> (f32, f32, f32) {
    let param = |key: &str| {
        m.unknown_param
            .get(key)
            .and_then(|s| s.trim().parse::<f32>().ok())
            .filter(|v| v.is_finite())
            .map(|v| v.clamp(0.0, 1.0))
    };
    let (pm, pr) = (param("Pm"), param("Pr"));
    let has_ks = m.specular.is_some_and(|ks| ks.iter().any(|c| *c > 0.0));
    let phong_roughness = match m.shininess {
        Some(ns) if has_ks => (2.0 / (ns.max(0.0) + 2.0)).sqrt(),
        _ => 1.0,
    };
    let specular = pm.is_some() || pr.is_some() || has_ks;
    (
        pm.unwrap_or(0.0),
        pr.unwrap_or(phong_roughness),
        if specular { 1.0 } else { 0.0 },
    )
}

/// Parses "r g b" or "v" (grey): finite, non-negative.
fn parse_colour(s: &str) -> Result<[f32; 3], ()> {
    let values: Vec<f32> = s
        .split_whitespace()
        .map(|w| w.parse::<f32>().map_err(|_| ()))
        .collect::<Result<_, _>>()?;
    let rgb = match values[..] {
        [v] => [v; 3],
        [r, g, b] => [r, g, b],
        _ => return Err(()),
    };
    if rgb.iter().all(|c| c.is_finite() && *c >= 0.0) {
        Ok(rgb)
    } else {
        Err(())
    }
}

/// Reads one material library for tobj, after checking its colours (tobj panics on a colour of
/// fewer than three numbers) and spelling a one-number colour out as three.
pub(super) fn load_mtl(
    mtl: &Path,
    obj: &Path,
    notices: &mut Vec<String>,
) -> Result<tobj::MTLLoadResult, SceneError> {
    let bytes = fs::read(mtl).map_err(|err| SceneError::MtlRead {
        mtl: mtl.to_path_buf(),
        obj: obj.to_path_buf(),
        err,
    })?;
    let text = super::decode_text(mtl, &bytes, "the material library", notices)?;
    let mut normalized = String::with_capacity(text.len());
    for (index, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        let key = trimmed.split_whitespace().next().unwrap_or("");
        if matches!(key, "Kd" | "Ke" | "Ka" | "Ks") {
            let value = trimmed[key.len()..].trim();
            let rgb = parse_colour(value).map_err(|()| SceneError::Color {
                path: mtl.to_path_buf(),
                line: index + 1,
                key: key.into(),
                value: value.into(),
            })?;
            let _ = writeln!(normalized, "{key} {} {} {}", rgb[0], rgb[1], rgb[2]);
        } else {
            normalized.push_str(line);
            normalized.push('\n');
        }
    }
    tobj::load_mtl_buf(&mut normalized.as_bytes())
        .map_err(|e| SceneError::Mtl {
            path: mtl.to_path_buf(),
            reason: e.to_string(),
        })
        .map(Ok)
}
