//! The Vulkan pipeline cache, kept on disk so that pipelines are compiled once per device and
//! driver, not once per run. One file per device, driver and set of shaders (named by its
//! vendor and device IDs, its pipeline-cache UUID, which drivers change when their compiled code
//! would, and the shaders' hash), in
//! `lensray_core::cache::dir()`. Before the data reaches the driver its header
//! (VkPipelineCacheHeaderVersionOne) is checked against the device: a file of another device
//! or driver, or a damaged one, is ignored with a notice and replaced at the end of the run.

use std::path::PathBuf;

use ash::vk;

use crate::core::adapter::DeviceReport;

/// `VkPipelineCacheHeaderVersionOne`: header length, version, vendor ID, device ID, UUID.
const HEADER_BYTES: usize = 16 + 16;

/// What to create the device's pipeline cache from, and where to save it.
pub(crate) struct PipelineCacheFile {
    pub path: Option<PathBuf>,
    /// The data a previous run saved, checked against the device (empty: none usable).
    pub data: Vec<u8>,
}

impl PipelineCacheFile {
    /// Whether this device and driver are used for the first time: a cache file can be kept, and
    /// none usable is there yet.
    pub(crate) fn is_first_use(&self) -> bool {
        self.path.is_some() && self.data.is_empty()
    }
}

/// The cache file of `device` for the shaders whose hash is `shaders_hash`, and its data when it
/// belongs to this device and driver.
pub(crate) fn load(device: &DeviceReport, shaders_hash: u64) -> PipelineCacheFile {
    let Some(dir) = lensray_core::cache::dir() else {
        return PipelineCacheFile {
            path: None,
            data: Vec::new(),
        };
    };
    let uuid: String = device
        .pipeline_cache_uuid
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let path = dir.join(format!(
        "pipelines-{:04x}-{:04x}-{uuid}-{:016x}.bin",
        device.vendor_id, device.device_id, shaders_hash
    ));
    let data = match std::fs::read(&path) {
        Ok(data) => match check_header(&data, device) {
            Ok(()) => data,
            Err(why) => {
                eprintln!(
                    "notice: ignoring the pipeline cache {}: {why}",
                    path.display()
                );
                Vec::new()
            }
        },
        Err(_) => Vec::new(),
    };
    PipelineCacheFile {
        path: Some(path),
        data,
    }
}

/// Whether `data` starts with the header of a cache made by `device`'s driver.
fn check_header(data: &[u8], device: &DeviceReport) -> Result<(), String> {
    if data.len() < HEADER_BYTES {
        return Err(format!("{} bytes, shorter than a header", data.len()));
    }
    let word = |i: usize| u32::from_le_bytes(data[4 * i..4 * i + 4].try_into().expect("4 bytes"));
    let (length, version) = (word(0), word(1));
    if length as usize != HEADER_BYTES
        || version != vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32
    {
        return Err(format!(
            "not a Vulkan pipeline cache (header {length} bytes, version {version})"
        ));
    }
    if (word(2), word(3)) != (device.vendor_id, device.device_id)
        || data[16..32] != device.pipeline_cache_uuid
    {
        return Err("made by another device or driver".into());
    }
    Ok(())
}

/// Saves `data` (the driver's current cache) to `file` when it differs from what was loaded.
/// (Some drivers keep their compiled code elsewhere and return the header alone: lavapipe has
/// Mesa's own shader cache. The header is saved all the same, so the next run checks it.)
/// A cache that cannot be written is a notice: the next run compiles again.
pub(crate) fn save(file: &PipelineCacheFile, data: &[u8]) {
    let Some(path) = &file.path else { return };
    if data.len() < HEADER_BYTES || data == file.data.as_slice() {
        return;
    }
    if let Err(e) = lensray_core::cache::write_whole(path, data) {
        eprintln!("notice: the pipeline cache was not saved: {e:#}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device() -> DeviceReport {
        DeviceReport {
            vendor_id: 0x10005,
            device_id: 7,
            pipeline_cache_uuid: [9; 16],
            ..DeviceReport::default()
        }
    }

    fn header(vendor: u32, device: u32, uuid: [u8; 16]) -> Vec<u8> {
        let mut data = Vec::new();
        for word in [32u32, 1, vendor, device] {
            data.extend_from_slice(&word.to_le_bytes());
        }
        data.extend_from_slice(&uuid);
        data.extend_from_slice(b"driver data");
        data
    }

    #[test]
    fn only_this_devices_cache_is_used() {
        assert_eq!(
            check_header(&header(0x10005, 7, [9; 16]), &device()),
            Ok(())
        );
        for (data, why) in [
            (header(0x10005, 7, [8; 16]), "another device or driver"),
            (header(0x10de, 7, [9; 16]), "another device or driver"),
            (b"garbage".to_vec(), "shorter than a header"),
            (vec![0u8; 64], "not a Vulkan pipeline cache"),
        ] {
            let error = check_header(&data, &device()).unwrap_err();
            assert!(error.contains(why), "{error}");
        }
    }
}
