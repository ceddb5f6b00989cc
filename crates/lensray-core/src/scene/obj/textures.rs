//! The textures of MTL materials: `map_Kd` and `map_Ke` (sRGB colour, as glTF's base colour),
//! `map_d` (linear coverage: the image's alpha channel where it has one, else its luminance),
//! `map_Pr` and `map_Pm` (linear roughness and metallic: each image's red channel, put in the G
//! and B channels of one texture as glTF's metallic-roughness texture has them) and `norm` (a
//! linear tangent-space normal map).
//! Paths are relative to the MTL file; options in front of the file name (`-s 1 1 1`, `-bm 0.5`,
//! `-clamp on`, ...) are skipped, backslashes read as separators. A file that is missing is a
//! notice and the material goes without it; one that cannot be decoded is an error.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::scene::texture::{coverage_from_image, decode_texture, Encoding, TextureRef};
use crate::scene::{LoadTimes, SceneError, Texture};

/// What a texture file is read as.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Kind {
    Colour,
    Coverage,
    /// Linear, as the file has it (a normal map).
    Data,
}

/// The textures read so far, each file and kind once.
pub(super) struct TextureFiles<'a> {
    pub obj: &'a Path,
    pub textures: Vec<Texture>,
    read: HashMap<(PathBuf, Kind), Option<u32>>,
    pub notices: Vec<String>,
    /// The textures' decode and mip levels.
    pub times: LoadTimes,
}

impl<'a> TextureFiles<'a> {
    pub(super) fn new(obj: &'a Path) -> Self {
        Self {
            obj,
            textures: Vec::new(),
            read: HashMap::new(),
            notices: Vec::new(),
            times: LoadTimes::default(),
        }
    }

    /// The texture of map statement value `value` (options, then the file name) of material
    /// `material`, relative to `dir`; `None` (with a notice) when the file cannot be read.
    pub(super) fn get(
        &mut self,
        dir: &Path,
        value: &str,
        kind: Kind,
        material: &str,
    ) -> Result<Option<TextureRef>, SceneError> {
        let path = self.named(dir, value)?;
        if let Some(&known) = self.read.get(&(path.clone(), kind)) {
            return Ok(known.map(TextureRef::new));
        }
        let loaded = match std::fs::read(&path) {
            Err(e) => {
                self.notices.push(format!(
                    "material {material}: cannot read texture {}: {e}; it renders without it",
                    path.display()
                ));
                None
            }
            Ok(bytes) => {
                let name = path.display().to_string();
                let texture = match kind {
                    Kind::Colour => decode_texture(&name, &bytes, Encoding::Srgb, &mut self.times),
                    Kind::Coverage => coverage_from_image(&name, &bytes, &mut self.times),
                    Kind::Data => decode_texture(&name, &bytes, Encoding::Linear, &mut self.times),
                }
                .map_err(|reason| SceneError::Texture {
                    path: path.clone(),
                    of: self.obj.to_path_buf(),
                    reason,
                })?;
                self.textures.push(texture);
                Some((self.textures.len() - 1) as u32)
            }
        };
        self.read.insert((path, kind), loaded);
        Ok(loaded.map(TextureRef::new))
    }
}

impl TextureFiles<'_> {
    /// The path of the image file of map statement value `value` in `dir` (`scene::reads`:
    /// refused outside the assets root; noted once outside `dir`).
    fn named(&mut self, dir: &Path, value: &str) -> Result<PathBuf, SceneError> {
        let file = crate::scene::reads::named_file(dir, Path::new(&file_name(value))).map_err(
            |message| SceneError::Confined {
                by: self.obj.to_path_buf(),
                message,
            },
        )?;
        if !self.read.keys().any(|(p, _)| *p == file.path) {
            self.notices.extend(file.note);
        }
        Ok(file.path)
    }

    /// The metallic-roughness texture of `map_Pr` (`roughness`) and `map_Pm` (`metallic`)
    /// statement values, relative to `dir`: G the roughness image's red channel, B the metallic
    /// image's (resized to the roughness image's size where they differ), 1 where a map is
    /// absent, so that its factor alone counts. `None` when neither file can be read.
    pub(super) fn metallic_roughness(
        &mut self,
        dir: &Path,
        roughness: Option<&str>,
        metallic: Option<&str>,
        material: &str,
    ) -> Result<Option<TextureRef>, SceneError> {
        let (r, m) = (
            self.image(dir, roughness, material)?,
            self.image(dir, metallic, material)?,
        );
        if r.is_none() && m.is_none() {
            return Ok(None);
        }
        let finest = |t: &Option<Texture>| t.as_ref().map(|t| t.levels[0]);
        let size = finest(&r)
            .or(finest(&m))
            .map_or([1, 1], |l| [l.width, l.height]);
        let channel = |t: &Option<Texture>, x: u32, y: u32| match t {
            // The nearest texel of the finest level, in [0, 255].
            Some(t) => {
                let l = t.levels[0];
                let (sx, sy) = (x * l.width / size[0], y * l.height / size[1]);
                (t.texels[(l.first + sy * l.width + sx) as usize] & 0xff) as u8
            }
            None => 255,
        };
        let mut texels = Vec::with_capacity((4 * size[0] * size[1]) as usize);
        for y in 0..size[1] {
            for x in 0..size[0] {
                texels.extend([255, channel(&r, x, y), channel(&m, x, y), 255]);
            }
        }
        let name = format!("{material} metallic-roughness");
        self.textures.push(Texture::from_rgba8(
            &name,
            size[0],
            size[1],
            &texels,
            Encoding::Linear,
        ));
        Ok(Some(TextureRef::new((self.textures.len() - 1) as u32)))
    }
}

impl TextureFiles<'_> {
    /// The image of map statement value `value`, relative to `dir`, decoded linear and not
    /// added to the scene; `None` (with a notice) when there is none or it cannot be read.
    fn image(
        &mut self,
        dir: &Path,
        value: Option<&str>,
        material: &str,
    ) -> Result<Option<Texture>, SceneError> {
        let Some(value) = value else {
            return Ok(None);
        };
        let path = self.named(dir, value)?;
        let bytes = match std::fs::read(&path) {
            Ok(bytes) => bytes,
            Err(e) => {
                self.notices.push(format!(
                    "material {material}: cannot read texture {}: {e}; it renders without it",
                    path.display()
                ));
                return Ok(None);
            }
        };
        let name = path.display().to_string();
        decode_texture(&name, &bytes, Encoding::Linear, &mut self.times)
            .map(Some)
            .map_err(|reason| SceneError::Texture {
                path,
                of: self.obj.to_path_buf(),
                reason,
            })
    }
}

/// The `-bm` (bump multiplier) option of a map statement's value, 1 without one.
pub(super) fn bump_multiplier(value: &str) -> f32 {
    let tokens: Vec<&str> = value.split_whitespace().collect();
    tokens
        .windows(2)
        .find(|w| w[0] == "-bm")
        .and_then(|w| w[1].parse::<f32>().ok())
        .filter(|v| v.is_finite())
        .unwrap_or(1.0)
}

/// Arguments of the MTL map options (`-o u v w` takes up to three numbers).
fn option_arguments(option: &str) -> usize {
    match option {
        "-o" | "-s" | "-t" => 3,
        "-mm" => 2,
        "-bm" | "-boost" | "-blendu" | "-blendv" | "-cc" | "-clamp" | "-imfchan" | "-texres"
        | "-type" => 1,
        _ => 0,
    }
}

/// The file name of a map statement's value: options and their arguments skipped, the rest
/// (which may hold spaces) with backslashes as slashes.
pub(super) fn file_name(value: &str) -> String {
    let tokens: Vec<&str> = value.split_whitespace().collect();
    let mut i = 0;
    while i < tokens.len() {
        let arguments = option_arguments(tokens[i]);
        if arguments == 0 {
            break;
        }
        i += 1;
        // Numeric options take up to their count of numbers; the others exactly one word.
        let numeric = matches!(tokens[i - 1], "-o" | "-s" | "-t" | "-mm");
        let mut taken = 0;
        while taken < arguments
            && i + 1 < tokens.len()
            && (!numeric || tokens[i].parse::<f32>().is_ok())
        {
            i += 1;
            taken += 1;
        }
    }
    tokens[i.min(tokens.len())..].join(" ").replace('\\', "/")
}

#[cfg(test)]
mod tests {
    use super::file_name;

    #[test]
    fn options_before_the_file_name_are_skipped() {
        assert_eq!(file_name("leaf.png"), "leaf.png");
        assert_eq!(
            file_name("-s 2 2 1 -bm 0.5 textures/leaf.png"),
            "textures/leaf.png"
        );
        assert_eq!(
            file_name("-o 0.5 textures\\leaf 1.png"),
            "textures/leaf 1.png"
        );
        assert_eq!(file_name("-clamp on -imfchan l mask.jpg"), "mask.jpg");
    }
}
