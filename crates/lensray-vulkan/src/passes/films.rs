//! Accumulations kept on the device: the sums of each [`Accumulation`] a GPU path adds samples
//! to live in a device-local buffer (a film) for as long as the accumulation does, so that a
//! render continued call after call uploads nothing and reads nothing back until the host asks
//! (`read`). A film starts cleared (a new accumulation) or from the host's sums (one the CPU
//! filled, or read back and changed); the trace shader adds to a band of rows of it at a time
//! (`ensure_band`: the band's sums copied in from the film and back, `band_copy`), and at the
//! end of its call the film is copied to host-visible memory (a copy on the device, no host
//! read), so that reading the sums after a render needs no submission and no second wait.

use std::sync::{Arc, Weak};

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::recorder::Recorder;
use lensray_core::film::{Accumulation, Holder, OnDevice};

/// Bytes of one pixel's sums (`[r, g, b, n]` as f32).
const PIXEL_BYTES: u64 = 16;

/// Most pixels whose sums the shader adds to at once (64 MiB); larger images go in bands of
/// rows.
const MAX_BAND_PIXELS: u64 = 1 << 22;

/// One accumulation's sums on the device.
struct Film {
    /// Dead once the accumulation is dropped: the buffer is then reused or freed.
    key: Weak<()>,
    sums: Buffer,
}

/// What a film needs before samples are added to it, recorded at the head of the call's first
/// submission (`record_start`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Start {
    /// It holds the current sums (a continuation).
    Ready,
    /// A new accumulation: zeros, nothing uploaded.
    Clear,
    /// The host's sums, in the transfer buffer, copied up.
    Upload,
}

/// The device's films, who holds them, and the host-visible buffer of uploads and read-backs.
pub(crate) struct DeviceFilms {
    ctx: Arc<Context>,
    holder: Holder,
    films: Vec<Film>,
    /// Films of dropped accumulations, freed once the timeline passes the value (a submission
    /// not yet waited for may still use them).
    retired: Vec<(u64, Buffer)>,
    /// One image's sums, host-visible both ways; made for the size in use.
    transfer: Option<Buffer>,
    /// The film whose current sums `transfer` holds (copied at the end of the last call that
    /// added to it, and waited for).
    in_transfer: Option<Weak<()>>,
    /// The band of sums the shader adds to, for the current image size; `None` while the
    /// preview's accumulation is bound instead.
    band: Option<BandSums>,
    /// Most pixels of a band (tests lower it to force bands).
    pub max_band_pixels: u64,
}

/// The sums of one band of rows.
struct BandSums {
    buffer: Buffer,
    bytes: u64,
}

/// The copies of one band of rows between a film and the band's sums.
pub(crate) struct BandCopy<'f> {
    film: &'f Buffer,
    band: &'f Buffer,
    /// The band's bytes within the film.
    region: vk::BufferCopy,
}

impl BandCopy<'_> {
    /// Records the copy of the band's sums from the film into the band buffer.
    pub(crate) fn record_in(&self, rec: &mut Recorder<'_>) {
        let up = vk::BufferCopy::default()
            .src_offset(self.region.dst_offset)
            .dst_offset(0)
            .size(self.region.size);
        rec.copy_buffer(self.film, self.band, &[up]);
    }

    /// Records the copy of the band buffer's first `bytes` back into the film.
    pub(crate) fn record_out(&self, rec: &mut Recorder<'_>, bytes: u64) {
        rec.copy_buffer(self.band, self.film, &[self.region.size(bytes)]);
    }
}

impl DeviceFilms {
    pub(crate) fn new(ctx: &Arc<Context>) -> Self {
        Self {
            ctx: ctx.clone(),
            holder: Holder::new(),
            films: Vec::new(),
            retired: Vec::new(),
            transfer: None,
            in_transfer: None,
            band: None,
            max_band_pixels: MAX_BAND_PIXELS,
        }
    }

    /// The band buffer for a `width` x `height` image and the rows of a band, with the buffer
    /// when it is new (to bind). The shader adds to a storage buffer covering a band of rows,
    /// bounded by the device's storage-buffer range (128 MiB on lavapipe); each band is copied
    /// in from the film and back (`band_copy`).
    pub(crate) fn ensure_band(
        &mut self,
        width: u32,
        height: u32,
    ) -> Result<(u32, Option<&Buffer>), GpuError> {
        let max_band_pixels = (u64::from(self.ctx.report.max_storage_buffer_range) / PIXEL_BYTES)
            .min(self.max_band_pixels)
            .max(u64::from(width));
        let band_rows = (max_band_pixels / u64::from(width)).clamp(1, u64::from(height)) as u32;
        let bytes = u64::from(band_rows) * u64::from(width) * PIXEL_BYTES;
        if self.band.as_ref().is_some_and(|b| b.bytes == bytes) {
            return Ok((band_rows, None));
        }
        // A pending submission (the hybrid's plan) binds the old buffer: it finishes first.
        self.ctx.wait_all()?;
        self.band = None;
        let buffer = Buffer::new(
            &self.ctx,
            "trace band sums",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let band = self.band.insert(BandSums { buffer, bytes });
        Ok((band_rows, Some(&band.buffer)))
    }

    /// Frees the band buffer: the preview binds its own accumulation instead, and a later call
    /// makes and binds a band again.
    pub(crate) fn drop_band(&mut self) {
        self.band = None;
    }

    /// The copies of the band of rows `band_origin..band_origin + band_height` of an image
    /// `width` pixels wide between film `film` and the band buffer (`ensure_band` made it).
    pub(crate) fn band_copy(
        &self,
        film: usize,
        (band_origin, band_height): (u32, u32),
        width: u32,
    ) -> BandCopy<'_> {
        let band = &self.band.as_ref().expect("ensure_band made it").buffer;
        let row_bytes = u64::from(width) * PIXEL_BYTES;
        BandCopy {
            film: &self.films[film].sums,
            band,
            region: vk::BufferCopy::default()
                .src_offset(0)
                .dst_offset(u64::from(band_origin) * row_bytes)
                .size(u64::from(band_height) * row_bytes),
        }
    }

    /// The film that holds `accumulation` on this device from now on (its index) and what it
    /// needs first. An accumulation with no film here gets one, cleared when it has no samples,
    /// else with the host's sums uploaded; an error when another device holds its sums.
    pub(crate) fn take(
        &mut self,
        accumulation: &mut Accumulation,
    ) -> Result<(usize, Start), GpuError> {
        let bytes = u64::from(accumulation.width) * u64::from(accumulation.height) * PIXEL_BYTES;
        self.retire_dead(bytes)?;
        // The film changes, or the transfer buffer carries an upload.
        self.in_transfer = None;
        if let Some(key) = accumulation.held_by(self.holder) {
            if let Some(index) = self.films.iter().position(|f| f.key.ptr_eq(&key)) {
                accumulation.hold(self.holder)?;
                return Ok((index, Start::Ready));
            }
        }
        let start = if !accumulation.on_host() {
            return Err(OnDevice.into());
        } else if accumulation.is_empty() {
            Start::Clear
        } else {
            let sums = &accumulation.host()?.pixels;
            self.transfer(bytes)?.write(bytemuck::cast_slice(sums))?;
            Start::Upload
        };
        let key = accumulation.hold(self.holder)?;
        // A dead film of the same size is reused (its last use is ordered before ours by the
        // barrier of `record_start`).
        if let Some(index) = self
            .films
            .iter()
            .position(|f| f.key.strong_count() == 0 && f.sums.size == bytes)
        {
            self.films[index].key = key;
            return Ok((index, start));
        }
        let sums = Buffer::new(
            &self.ctx,
            "the image's accumulation film",
            bytes,
            vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        self.films.push(Film { key, sums });
        Ok((self.films.len() - 1, start))
    }

    /// Records what film `index` needs before samples are added (`take`'s `Start`): its sums
    /// from the transfer buffer, or zeros.
    pub(crate) fn record_start(&self, rec: &mut Recorder<'_>, index: usize, start: Start) {
        let film = &self.films[index].sums;
        match (start, &self.transfer) {
            (Start::Ready, _) => {}
            (Start::Upload, Some(transfer)) => {
                let copy = vk::BufferCopy::default().size(film.size);
                rec.copy_buffer(transfer, film, &[copy]);
            }
            _ => rec.fill_buffer(film, 0, vk::WHOLE_SIZE, 0),
        }
    }

    /// Makes the transfer buffer fit film `index`, before a call records `record_finish`.
    pub(crate) fn prepare_finish(&mut self, index: usize) -> Result<(), GpuError> {
        let bytes = self.films[index].sums.size;
        self.transfer(bytes).map(|_| ())
    }

    /// Records the copy of film `index` to the transfer buffer, after the call's last band;
    /// returns the transfer buffer, which the host reads after the submission's wait.
    pub(crate) fn record_finish(&self, rec: &mut Recorder<'_>, index: usize) -> &Buffer {
        let transfer = self.transfer.as_ref().expect("prepare_finish made it");
        self.record_copy_out(rec, &self.films[index].sums, transfer);
        transfer
    }

    /// The copy that `record_finish` recorded for film `index` was waited for: the transfer
    /// buffer holds its sums.
    pub(crate) fn finished(&mut self, index: usize) {
        self.in_transfer = Some(self.films[index].key.clone());
    }

    /// Brings `accumulation`'s sums to the host when this device holds them: the image's sums
    /// read back, with no submission when the call that last added to them copied them out
    /// (`record_finish`), else one submission and one wait. Nothing to do when the host's are
    /// current; an error when another device holds them.
    pub(crate) fn read(&mut self, accumulation: &mut Accumulation) -> Result<(), GpuError> {
        if accumulation.on_host() {
            return Ok(());
        }
        let key = accumulation.held_by(self.holder).ok_or(OnDevice)?;
        let index = self
            .films
            .iter()
            .position(|f| f.key.ptr_eq(&key))
            .ok_or(OnDevice)?;
        if !self.in_transfer.as_ref().is_some_and(|k| k.ptr_eq(&key)) {
            self.prepare_finish(index)?;
            let transfer = self.transfer.as_ref().expect("made above");
            self.ctx.submit_and_wait(|rec| {
                self.record_copy_out(rec, &self.films[index].sums, transfer);
                rec.read_on_host(&[transfer]);
                Ok(())
            })?;
            self.in_transfer = Some(key);
        }
        let transfer = self.transfer.as_ref().expect("holds the film");
        let sums: &[[f32; 4]] = bytemuck::cast_slice(transfer.read()?);
        accumulation.set_from_device(self.holder, sums);
        Ok(())
    }

    /// Records the copy of `film` into `transfer`.
    fn record_copy_out(&self, rec: &mut Recorder<'_>, film: &Buffer, transfer: &Buffer) {
        let copy = vk::BufferCopy::default().size(film.size);
        rec.copy_buffer(film, transfer, &[copy]);
    }

    /// The host-visible transfer buffer of `bytes` (made anew for another size; no submission
    /// uses the old one: uploads and read-backs are waited for by the calls that make them).
    fn transfer(&mut self, bytes: u64) -> Result<&mut Buffer, GpuError> {
        if self.transfer.as_ref().is_none_or(|t| t.size != bytes) {
            self.transfer = None;
            self.in_transfer = None;
            self.transfer = Some(Buffer::new(
                &self.ctx,
                "the image's read-back buffer",
                bytes,
                vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?);
        }
        Ok(self.transfer.as_mut().expect("made above"))
    }

    /// Retires the films of dropped accumulations but one of `bytes` (kept for reuse), and frees the retired ones the device has finished with.
    fn retire_dead(&mut self, bytes: u64) -> Result<(), GpuError> {
        let last = self.ctx.last_submitted();
        let mut spare = false;
        for film in std::mem::take(&mut self.films) {
            let dead = film.key.strong_count() == 0;
            if dead && (spare || film.sums.size != bytes) {
                self.retired.push((last, film.sums));
            } else {
                spare |= dead;
                self.films.push(film);
            }
        }
        if !self.retired.is_empty() {
            let completed = self.ctx.completed()?;
            self.retired.retain(|(value, _)| *value > completed);
        }
        Ok(())
    }
}
