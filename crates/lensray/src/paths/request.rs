//! What `--path` (or bench's `--paths`), `--device` and the Vulkan options ask for together,
//! checked in one place for `render`, `preview` and `bench`: a GPU path on `--device cpu`, the
//! CPU path on `--device gpu`, and a Vulkan option (`--validate`, `--gpu`) with the CPU are
//! errors naming both sides.

use anyhow::{bail, Result};

use super::path::{Choice, DeviceChoice, DeviceKind, PathChoice, PathKind};
use lensray_vulkan::GpuOptions;

/// How to open a path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PathOptions {
    pub path: PathChoice,
    pub device: DeviceChoice,
    /// Validation and device index of the Vulkan device.
    pub gpu: GpuOptions,
}

/// A Vulkan option given on the command line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpuOption {
    /// The flag as typed (`--validate`, `--gpu 1`).
    pub flag: String,
    /// What it does, for messages.
    pub what: &'static str,
}

impl PathOptions {
    /// The Vulkan option asked for, if any (`--validate` first).
    pub fn gpu_option(&self) -> Option<GpuOption> {
        if self.gpu.validate {
            Some(GpuOption {
                flag: "--validate".into(),
                what: "checks the Vulkan renderer",
            })
        } else {
            self.gpu.device_index.map(|index| GpuOption {
                flag: format!("--gpu {index}"),
                what: "picks a Vulkan device",
            })
        }
    }

    /// The device these options run on: the path's or `--device`'s when either names one, else
    /// `auto`. `path_flag` names the path option in messages (`--path`, `--paths`).
    pub fn device_to_use(&self, path_flag: &str) -> Result<DeviceChoice> {
        let path_device = self.path.only().map(PathKind::device);
        match (path_device, self.device) {
            (Some(DeviceKind::Gpu), Choice::Only(DeviceKind::Cpu)) => bail!(
                "{path_flag} {} runs on a Vulkan device: it cannot be used with --device cpu",
                self.path
            ),
            (Some(DeviceKind::Cpu), Choice::Only(DeviceKind::Gpu)) => {
                bail!("{path_flag} cpu runs on the CPU: it cannot be used with --device gpu")
            }
            _ => {}
        }
        let device = path_device.map_or(self.device, Choice::Only);
        if device == Choice::Only(DeviceKind::Cpu) {
            if let Some(option) = self.gpu_option() {
                let by = if path_device.is_some() {
                    format!("{path_flag} cpu")
                } else {
                    "--device cpu".to_string()
                };
                bail!(
                    "{} {}: it cannot be used with {by}",
                    option.flag,
                    option.what
                );
            }
        }
        Ok(device)
    }
}
