//! Reading an aperture image (`--aperture-image`, `[camera.aperture] image`): PNG or EXR, read
//! as transmission. Each pixel's transmission is the mean of its red, green and blue values:
//! linear as stored for EXR, decoded from sRGB for PNG (as pbrt reads 8-bit images), so a
//! mid-grey PNG passes about 21 % and an EXR's 0.5 passes half. Alpha is ignored.
//!
//! A file is read once per modification time: the preview resolves its shot often.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::SystemTime;

use image::DynamicImage;

use crate::camera::aperture::ApertureImage;
use crate::film::colour::srgb_to_linear;

/// Why an aperture image could not be read, with the path.
#[derive(Debug, PartialEq, thiserror::Error)]
#[error("aperture image {}: {reason}", path.display())]
pub struct ApertureImageFileError {
    pub path: PathBuf,
    pub reason: String,
}

type Cache = Mutex<HashMap<PathBuf, (Option<SystemTime>, Arc<ApertureImage>)>>;

/// The aperture of the image file at `path` (cached while the file is unchanged).
pub fn load(path: &Path) -> Result<Arc<ApertureImage>, ApertureImageFileError> {
    let fail = |reason: String| ApertureImageFileError {
        path: path.to_path_buf(),
        reason,
    };
    let modified = std::fs::metadata(path)
        .map_err(|e| fail(e.to_string()))?
        .modified()
        .ok();
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    if let Some((when, image)) = cache.lock().expect("cache lock").get(path) {
        if *when == modified && modified.is_some() {
            return Ok(image.clone());
        }
    }
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if !matches!(extension.as_deref(), Some("png" | "exr")) {
        return Err(fail("must be a .png or .exr file".into()));
    }
    let decoded = crate::image_file::decode_file(path).map_err(fail)?;
    let image = Arc::new(transmission(&decoded).map_err(|e| fail(e.to_string()))?);
    cache
        .lock()
        .expect("cache lock")
        .insert(path.to_path_buf(), (modified, image.clone()));
    Ok(image)
}

/// The transmission map of a decoded image (see the module doc).
fn transmission(
    decoded: &DynamicImage,
) -> Result<ApertureImage, crate::camera::aperture::ApertureImageError> {
    let linear = is_float(decoded);
    let rgb = decoded.to_rgb32f();
    let values: Vec<f32> = rgb
        .pixels()
        .map(|p| {
            let c = p.0.map(|v| if linear { v } else { srgb_to_linear(v) });
            (c[0] + c[1] + c[2]) / 3.0
        })
        .collect();
    ApertureImage::new(rgb.width(), rgb.height(), &values)
}

/// Whether the image stores linear floats (EXR) rather than sRGB-encoded integers (PNG).
fn is_float(decoded: &DynamicImage) -> bool {
    matches!(
        decoded,
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_)
    )
}
