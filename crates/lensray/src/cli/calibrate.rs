//! `lensray calibrate`: measures this machine's paths on the calibration shot and caches the
//! figures `--path auto` decides from (`paths::calibration`).

use anyhow::{Context, Result};
use clap::Args;

use crate::paths::calibration::{self, DeviceDecision};
use lensray_vulkan::GpuOptions;

#[derive(Args, Debug, Default)]
pub struct CalibrateArgs {
    /// Calibrate this Vulkan device (index from `lensray info`).
    #[arg(long, value_name = "INDEX")]
    pub gpu: Option<usize>,
    /// Turn on the Vulkan validation layer; any warning or error fails the command.
    #[arg(long)]
    pub validate: bool,
    /// Act as if the Vulkan device had no ray-tracing support (ray queries, the ray-tracing
    /// pipeline).
    #[arg(long)]
    pub hide_ray_query: bool,
}

pub fn run(args: &CalibrateArgs) -> Result<()> {
    let gpu = GpuOptions {
        validate: args.validate,
        device_index: args.gpu,
        hide_ray_query: args.hide_ray_query,
        traversal: None,
        first_use_notice: true,
    };
    let measured = calibration::measure(&gpu).context("calibrating")?;
    let file = calibration::store(&measured)?;
    println!(
        "calibration shots: the built-in scene, {}x{}, {} and {} spp, lit (medians):",
        calibration::WIDTH,
        calibration::HEIGHT,
        calibration::SPP[0],
        calibration::SPP[1]
    );
    // The default render's size, to say what `auto` does with it.
    let default_samples = 640 * 480 * 16;
    for (kind, cost) in &measured.costs {
        println!(
            "  {:<9} {:7.1} ms + {:6.1} ns per pixel-sample ({:6.0} ms for 640x480 at 16 spp)",
            kind.name(),
            cost.fixed_seconds * 1e3,
            cost.seconds_per_sample * 1e9,
            cost.seconds(default_samples) * 1e3
        );
    }
    let device = lensray_vulkan::preferred_device(&gpu)?;
    let choice = match calibration::decide(&device, Some(&measured), default_samples) {
        DeviceDecision::Cpu(why) => format!("the CPU reference ({why})"),
        DeviceDecision::Gpu(_, why) => format!("{} ({why})", device.name),
    };
    println!("--path auto renders 640x480 at 16 spp on {choice}");
    println!("cached in {}", file.display());
    Ok(())
}
