//! `--video FILE.mp4`: a sequence's frames encoded by ffmpeg as H.264 (libx264, yuv420p), in
//! order, as they are rendered. Each frame goes to ffmpeg's stdin as raw 8-bit RGB, the bytes
//! a PNG of it holds (exposed, tone mapped, sRGB-encoded), so the video shows what PNG frames
//! show whatever `--out`'s format; a frame that `--resume` skips is read back from its file.
//! ffmpeg writes a temporary file beside the video, renamed into place once ffmpeg succeeded.

use std::io::{BufRead, BufReader, ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::thread::JoinHandle;

use anyhow::{anyhow, bail, Context, Result};
use glam::Vec3;
use tempfile::NamedTempFile;

use crate::output::{exr_scale, PendingFile, PendingOutput};
use lensray_core::film::colour::to_display_bytes_with;
use lensray_core::film::Image;
use lensray_core::settings::{Exposure, Shading};

/// Where ffmpeg comes from, for the line that says it is missing.
const INSTALL: &str = "install it (Debian/Ubuntu: sudo apt-get install ffmpeg)";

/// libx264's constant rate factor: 18 is its "visually lossless"; its default, 23, smears the
/// noise of a render of few samples into blotches.
const CRF: &str = "18";

/// A video output checked before any rendering: ffmpeg runs and has libx264, the name ends in
/// `.mp4`, and a file can be created in its folder.
pub struct VideoPlan {
    file: PendingFile,
}

impl VideoPlan {
    pub fn check(path: &Path) -> Result<Self> {
        let mp4 = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("mp4"));
        if !mp4 {
            bail!(
                "--video {}: the video is H.264 in an MP4 file: name it .mp4",
                path.display()
            );
        }
        probe_ffmpeg()?;
        Ok(Self {
            file: PendingFile::create(path)?,
        })
    }

    /// Starts ffmpeg on frames of `width` x `height` at `fps` frames per second. yuv420p stores
    /// colour at half resolution, so an odd width or height is padded by one pixel that repeats
    /// the last column or row.
    pub fn start(self, width: u32, height: u32, fps: f64) -> Result<VideoEncoder> {
        let path = self.file.path().to_owned();
        let temp = self.file.temp_file()?;
        let padded = (width + width % 2, height + height % 2);
        let mut child = Command::new("ffmpeg")
            .args(["-hide_banner", "-nostats", "-loglevel", "error"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgb24"])
            .args(["-s", &format!("{}x{}", padded.0, padded.1)])
            .args(["-r", &fps.to_string(), "-i", "-"])
            .args(["-c:v", "libx264", "-crf", CRF, "-pix_fmt", "yuv420p"])
            // BT.709's matrix, and the stream says so, so players turn it back into these RGB
            // values (swscale's default matrix is BT.601, which players assume for SD only);
            // colour averaged over each 2x2 block rather than taken from one pixel of it.
            .args([
                "-vf",
                "scale=out_color_matrix=bt709:out_range=tv:flags=area+accurate_rnd+full_chroma_int",
            ])
            .args(["-colorspace", "bt709", "-color_primaries", "bt709"])
            .args(["-color_trc", "bt709", "-f", "mp4", "-y"])
            .arg(temp.path())
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("--video {}: cannot run ffmpeg", path.display()))?;
        let stdin = child.stdin.take();
        let stderr = child.stderr.take().map(|stderr| {
            std::thread::spawn(move || {
                let lines = BufReader::new(stderr).lines().map_while(Result::ok);
                lines.filter(|l| !l.trim().is_empty()).last()
            })
        });
        Ok(VideoEncoder {
            file: Some(self.file),
            path,
            temp: Some(temp),
            child: Some(child),
            stdin,
            stderr,
            size: (width, height),
            padded,
            frame: Vec::new(),
            frames: 0,
            fps,
        })
    }
}

/// Whether ffmpeg is on PATH with libx264, in one line if not.
fn probe_ffmpeg() -> Result<()> {
    let out = Command::new("ffmpeg")
        .args(["-hide_banner", "-h", "encoder=libx264"])
        .stdin(Stdio::null())
        .output();
    let out = match out {
        Ok(out) => out,
        Err(e) if e.kind() == ErrorKind::NotFound => {
            bail!("--video encodes with ffmpeg, which is not on PATH: {INSTALL}")
        }
        Err(e) => bail!("--video encodes with ffmpeg, which does not run: {e}"),
    };
    if !String::from_utf8_lossy(&out.stdout).contains("Encoder libx264") {
        bail!("--video encodes H.264 with libx264, which this ffmpeg lacks: {INSTALL} (Debian's has it)");
    }
    Ok(())
}

/// ffmpeg encoding a sequence's frames as they come; dropped before [`VideoEncoder::finish`], it
/// stops ffmpeg and removes the temporary file.
pub struct VideoEncoder {
    file: Option<PendingFile>,
    path: PathBuf,
    temp: Option<NamedTempFile>,
    child: Option<Child>,
    stdin: Option<ChildStdin>,
    /// The thread reading ffmpeg's stderr: its last line, said when ffmpeg fails.
    stderr: Option<JoinHandle<Option<String>>>,
    size: (u32, u32),
    padded: (u32, u32),
    /// The padded frame's bytes, reused.
    frame: Vec<u8>,
    frames: usize,
    fps: f64,
}

impl VideoEncoder {
    /// Adds a rendered frame, as a PNG of it would show it.
    fn push_image(&mut self, image: &Image, shading: Shading, exposure: &Exposure) -> Result<()> {
        let bytes = to_display_bytes_with(image, shading, exposure.display);
        self.push((image.width, image.height), &bytes)
    }

    /// Writes a rendered frame to its file, where it has one, and to the video, its display
    /// bytes made once for both.
    pub fn write_frame(
        video: Option<&mut Self>,
        output: Option<PendingOutput>,
        image: &Image,
        shading: Shading,
        exposure: &Exposure,
    ) -> Result<()> {
        let mut shown = None;
        if let Some(video) = video {
            let bytes = to_display_bytes_with(image, shading, exposure.display);
            video.push((image.width, image.height), &bytes)?;
            shown = Some(bytes);
        }
        if let Some(output) = output {
            output
                .encode_shown(image, shading, exposure, shown.as_deref())?
                .commit()?;
        }
        Ok(())
    }

    /// Adds a frame read back from its complete file (`--resume`): a PNG's bytes as they are;
    /// an EXR, its exposure's scale undone, as the PNG writer would show it.
    pub fn push_file(&mut self, file: &Path, shading: Shading, exposure: &Exposure) -> Result<()> {
        let decoded = lensray_core::image_file::decode_file(file)
            .map_err(anyhow::Error::msg)
            .with_context(|| format!("--video: reading back {}", file.display()))?;
        let is_exr = file
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        if !is_exr {
            let rgb = decoded.into_rgb8();
            return self.push(rgb.dimensions(), rgb.as_raw());
        }
        let rgb = decoded.into_rgb32f();
        let scale = exr_scale(shading, exposure);
        let image = Image {
            width: rgb.width(),
            height: rgb.height(),
            pixels: rgb.pixels().map(|p| Vec3::from(p.0) / scale).collect(),
        };
        self.push_image(&image, shading, exposure)
    }

    /// Writes one frame of `size` (8-bit RGB, row by row) to ffmpeg, padded to even sides.
    fn push(&mut self, size: (u32, u32), rgb: &[u8]) -> Result<()> {
        if size != self.size {
            bail!(
                "--video {}: frame {} is {}x{}, the video's frames {}x{}",
                self.path.display(),
                self.frames + 1,
                size.0,
                size.1,
                self.size.0,
                self.size.1
            );
        }
        let frame = if self.padded == self.size {
            rgb
        } else {
            pad_to(&mut self.frame, rgb, self.size, self.padded);
            &self.frame
        };
        let written = match self.stdin.as_mut() {
            Some(stdin) => stdin.write_all(frame),
            None => Err(ErrorKind::BrokenPipe.into()),
        };
        match written {
            Ok(()) => {
                self.frames += 1;
                Ok(())
            }
            // ffmpeg stopped reading: its own message says why.
            Err(e) => Err(self.failure(&e.to_string())),
        }
    }

    /// Closes ffmpeg's input, waits for it, and renames the video into place.
    pub fn finish(mut self) -> Result<String> {
        drop(self.stdin.take());
        let status = self.child.take().map(|mut child| child.wait()).transpose();
        let last_line = self.stderr.take().and_then(|t| t.join().ok().flatten());
        let status = status.with_context(|| format!("--video {}", self.path.display()))?;
        if let Some(status) = status.filter(|s| !s.success()) {
            let why = last_line.unwrap_or_else(|| status.to_string());
            bail!("--video {}: ffmpeg failed: {why}", self.path.display());
        }
        if let (Some(file), Some(temp)) = (self.file.take(), self.temp.take()) {
            file.commit(temp)?;
        }
        let (w, h) = self.padded;
        let padding = if self.padded == self.size {
            String::new()
        } else {
            let (w0, h0) = self.size;
            format!(" ({w0}x{h0} padded to even sides)")
        };
        Ok(format!(
            "{}: {} frames at {} fps, {w}x{h} px{padding}, H.264 yuv420p (libx264, crf {CRF})",
            self.path.display(),
            self.frames,
            self.fps
        ))
    }

    /// ffmpeg's failure in one line: it is stopped and waited for, and its last stderr line
    /// (else `fallback`) says why.
    fn failure(&mut self, fallback: &str) -> anyhow::Error {
        drop(self.stdin.take());
        if let Some(mut child) = self.child.take() {
            // It may still run when it failed only to read (a closed pipe).
            let _ = child.kill();
            let _ = child.wait();
        }
        let last_line = self.stderr.take().and_then(|t| t.join().ok().flatten());
        let why = last_line.unwrap_or_else(|| fallback.to_owned());
        anyhow!("--video {}: ffmpeg failed: {why}", self.path.display())
    }
}

impl Drop for VideoEncoder {
    fn drop(&mut self) {
        drop(self.stdin.take());
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// `rgb` (`size`, 3 bytes a pixel) into `frame` at `padded` (a pixel more at most each way),
/// the last column and row repeated into the padding.
fn pad_to(frame: &mut Vec<u8>, rgb: &[u8], size: (u32, u32), padded: (u32, u32)) {
    let (row, padded_row) = (size.0 as usize * 3, padded.0 as usize * 3);
    frame.clear();
    for line in rgb.chunks_exact(row) {
        frame.extend_from_slice(line);
        frame.extend_from_slice(&line[row - 3..].repeat((padded.0 - size.0) as usize));
    }
    if padded.1 > size.1 {
        let last = frame.len() - padded_row;
        frame.extend_from_within(last..);
    }
}

#[cfg(test)]
mod tests {
    use super::pad_to;

    #[test]
    fn odd_sides_repeat_the_last_column_and_row() {
        // 3x1 pixels of grey levels 1, 2, 3 -> 4x2.
        let rgb = [1, 1, 1, 2, 2, 2, 3, 3, 3];
        let mut frame = Vec::new();
        pad_to(&mut frame, &rgb, (3, 1), (4, 2));
        let row = [1, 1, 1, 2, 2, 2, 3, 3, 3, 3, 3, 3];
        assert_eq!(frame, [row, row].concat());
        pad_to(&mut frame, &rgb, (3, 1), (3, 1));
        assert_eq!(frame, rgb);
    }
}
