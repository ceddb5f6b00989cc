//! The textures of MTL materials: `map_Kd` and `map_Ke` (sRGB colour, as glTF's base colour),
//! `map_d` (linear coverage: the image's alpha channel where it has one, else its luminance).
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
        let path = dir.join(file_name(value));
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
