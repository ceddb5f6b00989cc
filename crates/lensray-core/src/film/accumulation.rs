//! Per-pixel sums of samples: the state every render path adds samples to, so a render can be
//! continued (samples 0..8, then 8..16, give the image of 0..16 exactly).
//!
//! The sums live where the last samples were added. A GPU path keeps them on its device between
//! calls (`RenderPath::add_samples`) and brings them to the host only when asked
//! (`RenderPath::read_sums`), so a render continued call after call reads the image back once.
//! The host copy is then stale, and reading it is an error ([`OnDevice`]) rather than old
//! numbers.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Weak};

use glam::Vec3;

use super::Image;

/// The host's view of an accumulation whose current sums are held by a device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the accumulation's sums are on the device that added them: read them back with that \
     path's read_sums first"
)]
pub struct OnDevice;

/// Who holds an accumulation's sums: one per device-side store (a GPU renderer's films), never
/// reused in a process.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Holder(u64);

impl Holder {
    pub fn new() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        Holder(NEXT.fetch_add(1, Ordering::Relaxed))
    }
}

impl Default for Holder {
    fn default() -> Self {
        Self::new()
    }
}

/// A device's copy of the sums: `key` lives as long as the accumulation, so the holder keeps a
/// `Weak` of it and frees its copy once the accumulation is gone.
#[derive(Debug)]
struct Held {
    holder: Holder,
    key: Arc<()>,
    /// The host's sums are the device's too (just read back).
    host_current: bool,
}

/// The host's per-pixel sums: row-major, one `[r, g, b, n]` per pixel, the sum of the pixel's
/// samples and how many there are (a float, as the GPU keeps it: exact up to 2^24 samples).
#[derive(Clone, Debug, PartialEq)]
pub struct Sums {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl Sums {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![[0.0; 4]; width as usize * height as usize],
        }
    }

    /// The samples every pixel has (0 for an empty image).
    pub fn samples(&self) -> u32 {
        self.pixels.iter().map(|s| s[3] as u32).min().unwrap_or(0)
    }

    /// The mean of each pixel's samples (black where there are none).
    pub fn image(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: self
                .pixels
                .iter()
                .map(|&[r, g, b, n]| {
                    if n > 0.0 {
                        Vec3::new(r, g, b) / n
                    } else {
                        Vec3::ZERO
                    }
                })
                .collect(),
        }
    }

    /// Adds `other`'s sums, pixel by pixel (renders of disjoint sample ranges).
    pub fn add(&mut self, other: &Sums) {
        for (sum, more) in self.pixels.iter_mut().zip(&other.pixels) {
            for (a, b) in sum.iter_mut().zip(more) {
                *a += b;
            }
        }
    }
}

/// An image's sums, where the last samples were added: on the host ([`Sums`]) or held by the
/// device of a GPU path, whose copy the host reads on request.
#[derive(Debug)]
pub struct Accumulation {
    pub width: u32,
    pub height: u32,
    host: Sums,
    /// No samples added yet: a device starts from a cleared buffer, nothing uploaded.
    empty: bool,
    held: Option<Held>,
}

impl Accumulation {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            host: Sums::new(width, height),
            empty: true,
            held: None,
        }
    }

    /// Whether the host's sums are current (else a device holds them).
    pub fn on_host(&self) -> bool {
        self.held.as_ref().is_none_or(|h| h.host_current)
    }

    /// The sums, when the host's are current.
    pub fn host(&self) -> Result<&Sums, OnDevice> {
        if self.on_host() {
            Ok(&self.host)
        } else {
            Err(OnDevice)
        }
    }

    /// The sums to change on the host (the CPU adding samples): a device's copy is dropped.
    pub fn host_mut(&mut self) -> Result<&mut Sums, OnDevice> {
        if !self.on_host() {
            return Err(OnDevice);
        }
        self.held = None;
        self.empty = false;
        Ok(&mut self.host)
    }

    /// The mean of each pixel's samples, when the host's sums are current.
    pub fn image(&self) -> Result<Image, OnDevice> {
        Ok(self.host()?.image())
    }

    /// No samples were ever added (all sums zero).
    pub fn is_empty(&self) -> bool {
        self.empty
    }

    /// Whether `holder` has a copy of the current sums (one it can add to without an upload).
    pub fn held_by(&self, holder: Holder) -> Option<Weak<()>> {
        self.held
            .as_ref()
            .filter(|h| h.holder == holder)
            .map(|h| Arc::downgrade(&h.key))
    }

    /// `holder` takes the sums, to add samples on its device: the host's copy is stale from now
    /// on. Returns the key whose `Weak` tells the holder that the accumulation still exists.
    /// An error when another device holds the current sums.
    pub fn hold(&mut self, holder: Holder) -> Result<Weak<()>, OnDevice> {
        match &mut self.held {
            Some(h) if h.holder == holder => h.host_current = false,
            Some(h) if !h.host_current => return Err(OnDevice),
            _ => {
                self.held = Some(Held {
                    holder,
                    key: Arc::new(()),
                    host_current: false,
                })
            }
        }
        self.empty = false;
        Ok(Arc::downgrade(&self.held.as_ref().expect("held above").key))
    }

    /// The holder's sums, read back: the host's copy is current again (the holder keeps its
    /// own, so that a continuation uploads nothing).
    pub fn set_from_device(&mut self, holder: Holder, sums: &[[f32; 4]]) {
        debug_assert_eq!(sums.len(), self.host.pixels.len());
        self.host.pixels.copy_from_slice(sums);
        if let Some(h) = self.held.as_mut().filter(|h| h.holder == holder) {
            h.host_current = true;
        }
    }
}
