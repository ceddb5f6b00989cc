//! Writing images: PNG (8-bit, sRGB-encoded colour, exposed and tone mapped) or OpenEXR (linear
//! 32-bit float, exposed only when asked: `settings::exposure`), chosen by the file's extension. The file is written to a temporary file beside the target and renamed
//! into place, so a failed or interrupted render never leaves a half-written image.

use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use tempfile::NamedTempFile;
use thiserror::Error;

use lensray_core::film::colour::to_display_bytes_with;
use lensray_core::film::Image;
use lensray_core::settings::{Exposure, Shading};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
}

#[derive(Debug, Error)]
pub enum OutputError {
    #[error("output {path}: unknown extension (use .png or .exr)")]
    UnknownExtension { path: PathBuf },
    /// `reason` is in the message and not a source, so that the one line says it once.
    #[error("output {path}: cannot write there: {reason}")]
    Unwritable {
        path: PathBuf,
        reason: std::io::Error,
    },
    #[error("output {path}: encoding failed: {message}")]
    Encode { path: PathBuf, message: String },
}

/// An output file that is known to be writable, prepared before the render starts.
pub struct PendingOutput {
    path: PathBuf,
    format: Format,
    dir: PathBuf,
}

impl PendingOutput {
    /// Checks the extension and that a temporary file can be created beside `path`, so a bad
    /// path fails before any rendering. The probe is removed at once: a render interrupted
    /// later leaves nothing behind.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let format = format_of(path)?;
        let dir = writable_dir_of(path)?;
        Ok(Self {
            path: path.to_owned(),
            format,
            dir,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Encodes the image into the temporary file and renames it over the target.
    pub fn finish(
        self,
        image: &Image,
        shading: Shading,
        exposure: &Exposure,
    ) -> Result<(), OutputError> {
        self.encode(image, shading, exposure)?.commit()
    }

    /// Encodes the image into a temporary file beside the target; nothing is at the target
    /// until [`EncodedOutput::commit`] (dropped, the temporary file is removed). A PNG shows
    /// `exposure`'s display; an EXR of a traced shading is scaled by its `exr_scale`.
    pub fn encode(
        self,
        image: &Image,
        shading: Shading,
        exposure: &Exposure,
    ) -> Result<EncodedOutput, OutputError> {
        self.encode_shown(image, shading, exposure, None)
    }

    /// As [`PendingOutput::encode`], a PNG of `shown` where given: the image's display bytes
    /// (`to_display_bytes_with` of `exposure`'s display) made already for another use too, a
    /// video's frame.
    pub fn encode_shown(
        self,
        image: &Image,
        shading: Shading,
        exposure: &Exposure,
        shown: Option<&[u8]>,
    ) -> Result<EncodedOutput, OutputError> {
        let encode_error = |message: String| OutputError::Encode {
            path: self.path.clone(),
            message,
        };
        let mut temp = temp_file_in(&self.dir).map_err(|reason| OutputError::Unwritable {
            path: self.path.clone(),
            reason,
        })?;
        let (w, h) = (image.width, image.height);
        {
            let mut writer = BufWriter::new(temp.as_file_mut());
            match self.format {
                Format::Png => {
                    let made;
                    let bytes = match shown {
                        Some(bytes) => bytes,
                        None => {
                            made = to_display_bytes_with(image, shading, exposure.display);
                            &made
                        }
                    };
                    PngEncoder::new(&mut writer)
                        .write_image(bytes, w, h, ExtendedColorType::Rgb8)
                        .map_err(|e| encode_error(e.to_string()))?;
                }
                Format::Exr => {
                    write_exr(&mut writer, image, exr_scale(shading, exposure))
                        .map_err(encode_error)?;
                }
            }
            writer.flush().map_err(|e| encode_error(e.to_string()))?;
        }
        Ok(EncodedOutput {
            path: self.path,
            temp,
        })
    }
}

/// The scale an EXR's pixels are written with: the exposure's `exr_scale` for a traced shading,
/// 1 for an AOV (a depth, normal or albedo is no light to expose).
pub fn exr_scale(shading: Shading, exposure: &Exposure) -> f32 {
    if shading.is_aov() {
        1.0
    } else {
        exposure.exr_scale
    }
}

/// An image encoded into a temporary file beside its target.
pub struct EncodedOutput {
    path: PathBuf,
    temp: NamedTempFile,
}

impl EncodedOutput {
    /// Renames the temporary file over the target.
    pub fn commit(self) -> Result<(), OutputError> {
        let path = self.path;
        self.temp
            .persist(&path)
            .map_err(|e| OutputError::Unwritable {
                path,
                reason: e.error,
            })?;
        Ok(())
    }
}

/// Any other output file (a report, a plot): checked writable up front like [`PendingOutput`],
/// then written to a temporary file beside it and renamed into place.
pub struct PendingFile {
    path: PathBuf,
    dir: PathBuf,
}

impl PendingFile {
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        Ok(Self {
            dir: writable_dir_of(path)?,
            path: path.to_owned(),
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn finish(self, bytes: &[u8]) -> Result<(), OutputError> {
        let unwritable = |reason| OutputError::Unwritable {
            path: self.path.clone(),
            reason,
        };
        let mut temp = temp_file_in(&self.dir).map_err(unwritable)?;
        temp.as_file_mut()
            .write_all(bytes)
            .and_then(|()| temp.as_file_mut().flush())
            .map_err(unwritable)?;
        self.commit(temp)
    }

    /// A temporary file beside the target, for a writer that fills it by its name (another
    /// process); [`PendingFile::commit`] renames it over the target, and dropped it is removed.
    pub fn temp_file(&self) -> Result<NamedTempFile, OutputError> {
        temp_file_in(&self.dir).map_err(|reason| OutputError::Unwritable {
            path: self.path.clone(),
            reason,
        })
    }

    /// Renames `temp` (from [`PendingFile::temp_file`]) over the target.
    pub fn commit(self, temp: NamedTempFile) -> Result<(), OutputError> {
        temp.persist(&self.path)
            .map_err(|e| OutputError::Unwritable {
                path: self.path,
                reason: e.error,
            })?;
        Ok(())
    }
}

/// The folder `path` will be written in, once a temporary file could be created there (the
/// probe is removed at once, so a run that fails later leaves nothing behind).
fn writable_dir_of(path: &Path) -> Result<PathBuf, OutputError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let unwritable = |reason| OutputError::Unwritable {
        path: path.to_owned(),
        reason,
    };
    if path.is_dir() {
        return Err(unwritable(std::io::Error::other("it is a directory")));
    }
    drop(temp_file_in(dir).map_err(unwritable)?);
    Ok(dir.to_owned())
}

/// A temporary file beside the output (same file system, so the final rename is atomic); it is
/// deleted when dropped unless persisted.
fn temp_file_in(dir: &Path) -> std::io::Result<NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".lensray-").suffix(".tmp");
    // An image is no secret: the usual rw-r--r-- rather than the temp file's private 0600.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    builder.tempfile_in(dir).map_err(|e| system_reason(e, dir))
}

/// What went wrong, without the temporary file's name that tempfile adds to its errors (the
/// message names the output the user gave).
fn system_reason(e: std::io::Error, dir: &Path) -> std::io::Error {
    use std::io::ErrorKind;
    let reason = match e.kind() {
        ErrorKind::NotFound if !dir.is_dir() => "no such folder",
        ErrorKind::NotFound => "cannot create a file in that folder",
        ErrorKind::PermissionDenied => "permission denied",
        ErrorKind::ReadOnlyFilesystem => "read-only file system",
        ErrorKind::NotADirectory => "a parent is not a folder",
        ErrorKind::StorageFull => "no space left",
        _ => return e,
    };
    std::io::Error::new(e.kind(), reason)
}

/// How EXR pixels are stored: ZIP over 16 scan lines (lossless, what compositors read fastest),
/// blocks in increasing order so that equal images are equal files.
const EXR_ENCODING: exr::image::Encoding = exr::image::Encoding {
    compression: exr::compression::Compression::ZIP16,
    blocks: exr::image::Blocks::ScanLines,
    line_order: exr::meta::attribute::LineOrder::Increasing,
};

/// Writes the image's linear RGB floats times `scale` (1: as rendered), compressing the blocks
/// on every core.
fn write_exr<W: Write + Seek>(writer: W, image: &Image, scale: f32) -> Result<(), String> {
    use exr::prelude::{SpecificChannels, Vec2, WritableImage};
    let width = image.width as usize;
    let pixels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let c = image.pixels[p.y() * width + p.x()];
        let c = if scale == 1.0 { c } else { c * scale };
        (c.x, c.y, c.z)
    });
    exr::prelude::Image::from_encoded_channels((width, image.height as usize), EXR_ENCODING, pixels)
        .write()
        .to_buffered(writer)
        .map_err(|e| e.to_string())
}

/// The format named by the extension of `path`.
pub fn format_of(path: &Path) -> Result<Format, OutputError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => Ok(Format::Png),
        Some("exr") => Ok(Format::Exr),
        _ => Err(OutputError::UnknownExtension {
            path: path.to_owned(),
        }),
    }
}
