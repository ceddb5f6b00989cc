//! Reading an environment map from a file: Radiance RGBE (`.hdr`) or OpenEXR (`.exr`), both
//! linear, through the `image` crate.

use std::path::{Path, PathBuf};

use glam::Vec3;
use thiserror::Error;

use super::EnvironmentMap;

#[derive(Debug, Error)]
pub enum EnvironmentError {
    #[error("environment {path}: unknown extension (use .hdr or .exr, equirectangular)")]
    UnknownExtension { path: PathBuf },
    #[error("environment {path}: {message}")]
    Unreadable { path: PathBuf, message: String },
    #[error("environment {path}: {width}x{height} is not equirectangular (twice as wide as high)")]
    NotEquirectangular {
        path: PathBuf,
        width: u32,
        height: u32,
    },
}

/// What loading found and mended: texels that were not finite (set to 0) or had a negative
/// channel (clamped to 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Mended {
    pub texels: usize,
}

impl EnvironmentMap {
    /// Reads `path` (`.hdr` or `.exr`, 2:1). Texels that are not finite become 0, negative
    /// channels 0, counted in [`Mended`] for the caller's one warning.
    pub fn load(path: &Path) -> Result<(Self, Mended), EnvironmentError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("hdr" | "exr")) {
            return Err(EnvironmentError::UnknownExtension {
                path: path.to_owned(),
            });
        }
        let unreadable = |message: String| EnvironmentError::Unreadable {
            path: path.to_owned(),
            message,
        };
        let image = crate::image_file::decode_file(path)
            .map_err(unreadable)?
            .into_rgb32f();
        let (width, height) = image.dimensions();
        if width != 2 * height || height == 0 {
            return Err(EnvironmentError::NotEquirectangular {
                path: path.to_owned(),
                width,
                height,
            });
        }
        let mut mended = Mended::default();
        let texels = image
            .pixels()
            .map(|p| {
                let c = Vec3::from(p.0);
                if !c.is_finite() {
                    mended.texels += 1;
                    Vec3::ZERO
                } else if c.min_element() < 0.0 {
                    mended.texels += 1;
                    c.max(Vec3::ZERO)
                } else {
                    c
                }
            })
            .collect();
        let map =
            Self::new(width, height, texels).ok_or_else(|| unreadable("no texels".to_string()))?;
        Ok((map, mended))
    }
}
