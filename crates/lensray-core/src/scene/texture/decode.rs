//! Image files (PNG and JPEG, the formats glTF allows; whatever else the `image` crate reads
//! for OBJ) into textures.

use std::time::Instant;

use super::{Encoding, Texture, MAX_SIZE};
use crate::scene::load_times::LoadTimes;

/// Decodes `bytes` (an image file's contents) into a texture of `encoding`, the decode and the
/// mip levels timed into `times`; the error says why in a few words.
pub fn decode_texture(
    name: &str,
    bytes: &[u8],
    encoding: Encoding,
    times: &mut LoadTimes,
) -> Result<Texture, String> {
    let start = Instant::now();
    let image = decode(bytes)?.to_rgba8();
    let decoded = Instant::now();
    let texture = Texture::from_rgba8(
        name,
        image.width(),
        image.height(),
        image.as_raw(),
        encoding,
    );
    times.add_texture(start, decoded);
    Ok(texture)
}

/// A coverage texture (OBJ's `map_d`) from an image file's contents: alpha carries the image's
/// alpha channel where it has one, else its luminance, both linear; colour is white. The decode
/// and the mip levels are timed into `times`.
pub fn coverage_from_image(
    name: &str,
    bytes: &[u8],
    times: &mut LoadTimes,
) -> Result<Texture, String> {
    let start = Instant::now();
    let image = decode(bytes)?;
    let has_alpha = image.color().has_alpha();
    let rgba = image.to_rgba8();
    let texels: Vec<u8> = rgba
        .pixels()
        .flat_map(|p| {
            let [r, g, b, a] = p.0;
            let coverage = if has_alpha {
                a
            } else {
                let y = 0.2126 * f32::from(r) + 0.7152 * f32::from(g) + 0.0722 * f32::from(b);
                y.round().min(255.0) as u8
            };
            [255, 255, 255, coverage]
        })
        .collect();
    let decoded = Instant::now();
    let texture = Texture::from_rgba8(name, rgba.width(), rgba.height(), &texels, Encoding::Linear);
    times.add_texture(start, decoded);
    Ok(texture)
}

fn decode(bytes: &[u8]) -> Result<image::DynamicImage, String> {
    let image = crate::image_file::decode_bytes(bytes)?;
    let (w, h) = (image.width(), image.height());
    if w > MAX_SIZE || h > MAX_SIZE {
        return Err(format!(
            "the image is {w} x {h} pixels; lensray reads textures up to {MAX_SIZE} on a side"
        ));
    }
    Ok(image)
}
