//! Image files from bytes nobody here wrote (textures, environment maps, aperture images): the
//! size a file declares is read from its header and checked before a pixel is decoded, so a
//! small, highly compressible file declaring a huge image is refused at once rather than
//! allocated, and so is a file too short to hold the pixels it declares.

use std::io::{BufRead, Cursor, Seek};
use std::path::Path;

use image::{DynamicImage, ImageDecoder, ImageFormat, ImageReader, Limits};

/// The most pixels lensray decodes from one image file: 2^26, that is 8192 x 8192, or a 2:1
/// environment map up to 11584 x 5792 (docs/untrusted.md).
#[cfg(not(fuzzing))]
pub const MAX_IMAGE_PIXELS: u64 = 1 << 26;
/// Under the fuzzers (`--cfg fuzzing`, scripts/fuzz.sh): 2^20 pixels. A few hundred bytes of
/// JPEG can declare 50 million pixels, which their instrumented build takes over their 10 s
/// limit to decode: a time-out that is no bug, and would stop every run that meets one.
#[cfg(fuzzing)]
pub const MAX_IMAGE_PIXELS: u64 = 1 << 20;

/// What a decoder may allocate: the largest image at four 32-bit floats a pixel, with room for
/// a decoder's own buffers.
const MAX_DECODE_BYTES: u64 = MAX_IMAGE_PIXELS * 16 + (64 << 20);

/// Decodes an image file's contents; the error says why in a few words.
pub fn decode_bytes(bytes: &[u8]) -> Result<DynamicImage, String> {
    check_png_palette(bytes)?;
    let reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    decode(reader, bytes.len())
}

/// Decodes the image file at `path`, its format from its contents or else its extension; the
/// error says why in a few words (without the path).
pub fn decode_file(path: &Path) -> Result<DynamicImage, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    check_png_palette(&bytes)?;
    let mut reader = ImageReader::new(Cursor::new(bytes.as_slice()));
    if let Ok(format) = ImageFormat::from_path(path) {
        reader.set_format(format);
    }
    let length = bytes.len();
    decode(
        reader.with_guessed_format().map_err(|e| e.to_string())?,
        length,
    )
}

/// A PNG's palette (PLTE) of 1 to 256 RGB entries, checked before decoding: the `png` crate
/// expands one whose length is no multiple of 3 past its end (a panic).
fn check_png_palette(bytes: &[u8]) -> Result<(), String> {
    const SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";
    if !bytes.starts_with(SIGNATURE) {
        return Ok(());
    }
    let mut at = SIGNATURE.len();
    while let Some(head) = bytes.get(at..at + 8) {
        let length = u32::from_be_bytes([head[0], head[1], head[2], head[3]]) as usize;
        match &head[4..8] {
            b"PLTE" if length % 3 != 0 || !(3..=768).contains(&length) => {
                return Err(format!(
                    "the PNG's palette (PLTE) is {length} bytes: 1 to 256 RGB entries are 3 to \
                     768 bytes, a multiple of 3"
                ))
            }
            b"IDAT" | b"IEND" => break,
            _ => {}
        }
        at = match at.checked_add(length).and_then(|end| end.checked_add(12)) {
            Some(next) => next,
            None => break,
        };
    }
    Ok(())
}

/// Decodes the file of `length` bytes that `reader` reads.
fn decode<R: BufRead + Seek>(
    mut reader: ImageReader<R>,
    length: usize,
) -> Result<DynamicImage, String> {
    let mut limits = Limits::default();
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    let format = reader.format();
    let decoder = reader.into_decoder().map_err(|e| e.to_string())?;
    let (width, height) = decoder.dimensions();
    check_size(width, height)?;
    if format == Some(ImageFormat::Jpeg) {
        check_jpeg_length(width, height, length)?;
    }
    DynamicImage::from_decoder(decoder).map_err(|e| e.to_string())
}

/// Refuses a JPEG too short for the pixels it declares. The decoder reads Huffman-coded JPEGs
/// only (baseline and progressive; arithmetic coding is refused), which spend at least one bit
/// on each 8 x 8 block of a component (its DC code, in the first scan), so `width` x `height`
/// pixels take at least one byte per 512. A shorter file is truncated or crafted, and its
/// decoder would still transform every block the header declares: seconds for a few hundred
/// bytes.
fn check_jpeg_length(width: u32, height: u32, length: usize) -> Result<(), String> {
    let blocks = u64::from(width).div_ceil(8) * u64::from(height).div_ceil(8);
    let least = blocks.div_ceil(8);
    if (length as u64) < least {
        return Err(format!(
            "the JPEG declares {width} x {height} pixels in {length} bytes: its {blocks} blocks \
             of 8 x 8 take at least a bit each, {least} bytes (a truncated or crafted file)"
        ));
    }
    Ok(())
}

/// Refuses a size of no pixels or of more than [`MAX_IMAGE_PIXELS`].
fn check_size(width: u32, height: u32) -> Result<(), String> {
    let pixels = u64::from(width) * u64::from(height);
    if pixels == 0 {
        return Err(format!("the image declares {width} x {height} pixels"));
    }
    if pixels > MAX_IMAGE_PIXELS {
        return Err(format!(
            "the image declares {width} x {height} pixels ({:.0} million); lensray decodes \
             images up to {} million pixels (8192 x 8192)",
            pixels as f64 / 1e6,
            MAX_IMAGE_PIXELS / 1_000_000
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Radiance HDR file whose header declares `width` x `height` pixels, with no pixels
    /// after it: what a decompression bomb's header says, in a few bytes.
    fn declared_hdr(width: u32, height: u32) -> Vec<u8> {
        format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n").into_bytes()
    }

    /// A file declaring more than the limit is refused from its header, naming its size; a
    /// small one decodes.
    #[test]
    fn an_image_past_the_limit_is_refused_from_its_header() {
        let e = decode_bytes(&declared_hdr(12_000, 6_000)).expect_err("72 million pixels");
        assert!(e.contains("12000 x 6000 pixels (72 million)"), "{e}");
        assert!(e.contains("up to 67 million"), "{e}");
        let mut small = declared_hdr(2, 1);
        small.extend([128, 64, 32, 129, 1, 2, 3, 128]);
        let fine = decode_bytes(&small).expect("a small image decodes");
        assert_eq!((fine.width(), fine.height()), (2, 1));
    }

    /// A JPEG whose header declares 2064 x 24592 pixels in a few hundred bytes is refused
    /// before its decoder transforms 800 000 blocks; the same file at its own size decodes.
    #[test]
    fn a_jpeg_too_short_for_its_pixels_is_refused() {
        let mut jpeg = Vec::new();
        let tile = image::RgbImage::from_pixel(16, 16, image::Rgb([200, 100, 50]));
        tile.write_to(&mut Cursor::new(&mut jpeg), ImageFormat::Jpeg)
            .unwrap();
        let fine = decode_bytes(&jpeg).expect("a 16 x 16 JPEG decodes");
        assert_eq!((fine.width(), fine.height()), (16, 16));
        // The baseline frame header (SOF0): marker, length, precision, then height and width.
        let sof = jpeg.windows(2).position(|w| w == [0xff, 0xc0]).unwrap();
        jpeg[sof + 5..sof + 7].copy_from_slice(&24592u16.to_be_bytes());
        jpeg[sof + 7..sof + 9].copy_from_slice(&2064u16.to_be_bytes());
        let start = std::time::Instant::now();
        let e = decode_bytes(&jpeg).expect_err("50 million pixels in a few hundred bytes");
        let what = format!(
            "the JPEG declares 2064 x 24592 pixels in {} bytes",
            jpeg.len()
        );
        assert!(e.contains(&what) && e.contains("793092 blocks"), "{e}");
        assert!(e.contains("99137 bytes"), "{e}");
        assert!(start.elapsed().as_secs_f64() < 0.5, "{:?}", start.elapsed());
    }

    /// A palette whose length is no multiple of 3 is refused in one line before the `png`
    /// crate expands it (fuzz/regressions/image/ holds the whole file the fuzzer found).
    #[test]
    fn a_png_palette_of_a_partial_entry_is_refused() {
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        png.extend(13u32.to_be_bytes());
        png.extend(b"IHDR");
        png.extend([0, 0, 0, 2, 0, 0, 0, 1, 8, 3, 0, 0, 0]);
        png.extend([0; 4]);
        png.extend(4u32.to_be_bytes());
        png.extend(b"PLTE");
        png.extend([255, 0, 0, 255, 0, 0, 0, 0]);
        let e = decode_bytes(&png).expect_err("4 bytes of palette");
        assert!(e.contains("palette (PLTE) is 4 bytes"), "{e}");
    }
}
