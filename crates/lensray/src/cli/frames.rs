//! What a sequence's options name: the frames (`--frames N`, `A-B`, `A-B:STEP`), a render
//! farm task's part of them (`--chunk INDEX/SIZE`), each frame's file (`--out` with `####` or
//! `%04d`), and whether a frame's file is complete (`--resume`).

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

/// `--frames`: from `first` to `last` (both in) every `step`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    pub first: u32,
    pub last: u32,
    pub step: u32,
}

impl FrameRange {
    pub fn frames(&self) -> Vec<u32> {
        (self.first..=self.last)
            .step_by(self.step as usize)
            .collect()
    }
}

/// Parses `N`, `A-B` or `A-B:STEP`.
pub fn parse_frames(text: &str) -> Result<FrameRange, String> {
    let bad = |why: &str| format!("`{text}`: {why} (frames are N, A-B or A-B:STEP, like 1-240)");
    let number = |s: &str, what: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| bad(&format!("{what} `{s}` is not a frame number from 0")))
    };
    let (span, step) = match text.split_once(':') {
        Some((span, step)) => (span, number(step, "the step")?),
        None => (text, 1),
    };
    if step == 0 {
        return Err(bad("the step must be at least 1"));
    }
    let (first, last) = match span.split_once('-') {
        Some((a, b)) => (number(a, "the first frame")?, number(b, "the last frame")?),
        None => {
            let n = number(span, "the frame")?;
            (n, n)
        }
    };
    if last < first {
        return Err(bad(&format!(
            "the last frame {last} is before the first {first}"
        )));
    }
    Ok(FrameRange { first, last, step })
}

/// `--chunk INDEX/SIZE`: the INDEX-th (from 0) of SIZE contiguous parts of the frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Chunk {
    pub index: u32,
    pub size: u32,
}

impl Chunk {
    /// This chunk's frames of `frames`: chunk i of n holds frames [i len / n, (i + 1) len / n),
    /// so the chunks cover every frame once and differ in length by one at most.
    pub fn of(&self, frames: &[u32]) -> Vec<u32> {
        let part = |i: u32| (i as usize * frames.len()) / self.size as usize;
        frames[part(self.index)..part(self.index + 1)].to_vec()
    }
}

/// Parses `INDEX/SIZE` (INDEX from 0, under SIZE).
pub fn parse_chunk(text: &str) -> Result<Chunk, String> {
    let bad =
        |why: &str| format!("`{text}`: {why} (a chunk is INDEX/SIZE, INDEX from 0, like 0/3)");
    let (index, size) = text.split_once('/').ok_or_else(|| bad("no `/`"))?;
    let number = |s: &str| s.trim().parse::<u32>().ok();
    let (Some(index), Some(size)) = (number(index), number(size)) else {
        return Err(bad("INDEX and SIZE must be whole numbers"));
    };
    if size == 0 {
        return Err(bad("SIZE must be at least 1"));
    }
    if index >= size {
        return Err(bad(&format!("INDEX must be under SIZE: 0 to {}", size - 1)));
    }
    Ok(Chunk { index, size })
}

/// An output path with a frame number's place: a run of `#` (as many digits, zero-padded) or
/// printf's `%d` / `%0Nd`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FramePattern {
    before: String,
    after: String,
    digits: usize,
}

impl FramePattern {
    /// The pattern in `path`, if it has one (the last run of `#`, else the first `%..d`).
    pub fn of(path: &Path) -> Option<Self> {
        let text = path.to_str()?;
        if let Some(end) = text.rfind('#') {
            let start = text[..end].trim_end_matches('#').len();
            return Some(Self {
                before: text[..start].into(),
                after: text[end + 1..].into(),
                digits: end + 1 - start,
            });
        }
        let start = text.find('%')?;
        let rest = &text[start + 1..];
        let end = rest.find('d')?;
        let width = &rest[..end];
        let digits = match width {
            "" => 1,
            w if w.starts_with('0') && w.len() > 1 => w[1..].parse().ok()?,
            _ => return None,
        };
        Some(Self {
            before: text[..start].into(),
            after: rest[end + 1..].into(),
            digits,
        })
    }

    /// The file of `frame`.
    pub fn path(&self, frame: u32) -> PathBuf {
        format!(
            "{}{frame:0digits$}{}",
            self.before,
            self.after,
            digits = self.digits
        )
        .into()
    }
}

/// The last chunk of every PNG: IEND, no data, its CRC.
const PNG_END: [u8; 12] = [0, 0, 0, 0, b'I', b'E', b'N', b'D', 0xae, 0x42, 0x60, 0x82];

/// Whether `path` holds a whole image of `width` x `height`: it decodes at that size (a PNG's
/// every chunk's CRC checked and its IEND chunk last; an EXR's every block read). A file cut
/// short, of another size or not an image is not complete.
pub fn is_complete(path: &Path, width: u32, height: u32) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => png_is_complete(path, width, height).unwrap_or(false),
        Some("exr") => exr::prelude::read_first_rgba_layer_from_file(
            path,
            |_, _| (),
            |_: &mut (), _, _: (f32, f32, f32, f32)| {},
        )
        .is_ok_and(|image| {
            let size = image.layer_data.size;
            (size.0, size.1) == (width as usize, height as usize)
        }),
        _ => false,
    }
}

fn png_is_complete(path: &Path, width: u32, height: u32) -> Option<bool> {
    let mut bytes = Vec::new();
    fs::File::open(path).ok()?.read_to_end(&mut bytes).ok()?;
    if !bytes.ends_with(&PNG_END) {
        return Some(false);
    }
    let image = lensray_core::image_file::decode_bytes(&bytes).ok()?;
    Some((image.width(), image.height()) == (width, height))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_and_chunks() {
        let range = parse_frames("1-10:3").unwrap();
        assert_eq!(range.frames(), vec![1, 4, 7, 10]);
        assert_eq!(parse_frames("7").unwrap().frames(), vec![7]);
        let frames = parse_frames("1-10").unwrap().frames();
        let chunks: Vec<Vec<u32>> = (0..3)
            .map(|index| Chunk { index, size: 3 }.of(&frames))
            .collect();
        assert_eq!(
            chunks,
            vec![vec![1, 2, 3], vec![4, 5, 6], vec![7, 8, 9, 10]]
        );
        assert_eq!(Chunk { index: 4, size: 5 }.of(&[3, 4]), vec![4]);
        assert!(Chunk { index: 0, size: 5 }.of(&[3, 4]).is_empty());
    }

    #[test]
    fn patterns() {
        let hashes = FramePattern::of(Path::new("out/shot.####.exr")).unwrap();
        assert_eq!(hashes.path(7), Path::new("out/shot.0007.exr"));
        assert_eq!(hashes.path(12345), Path::new("out/shot.12345.exr"));
        let printf = FramePattern::of(Path::new("shot_%03d.png")).unwrap();
        assert_eq!(printf.path(42), Path::new("shot_042.png"));
        assert_eq!(
            FramePattern::of(Path::new("f%d.png")).unwrap().path(5),
            Path::new("f5.png")
        );
        assert_eq!(FramePattern::of(Path::new("shot.png")), None);
    }
}
