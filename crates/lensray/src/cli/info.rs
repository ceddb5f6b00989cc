//! `lensray info`: the CPU path's Embree (CPU, instruction set, threads), then the Vulkan devices
//! and whether each can run the GPU renderer.

use anyhow::{Context, Result};

use lensray_core::reference::{EmbreeReport, EmbreeSettings, EMBREE_CONFIG_VAR};
use lensray_core::settings::{DEFAULT_HEIGHT, DEFAULT_SPP, DEFAULT_WIDTH};
use lensray_vulkan::{list_devices, DeviceReport, Traversal};

use crate::paths::{calibration, PathKind};

/// Prints the CPU path's set-up, then every Vulkan device with its ray-query support, the render
/// paths it runs and the limits that matter.
pub fn run() -> Result<()> {
    let settings = EmbreeSettings::from_env()?;
    print!("{}", format_cpu(&EmbreeReport::new(settings), settings));
    let devices = list_devices().context("listing Vulkan devices")?;
    print!("\n{}", format_devices(&devices, calibrated_traversal));
    Ok(())
}

/// The fastest traversal of the device by its cached calibration, for the default shot.
fn calibrated_traversal(device: &DeviceReport) -> Option<Traversal> {
    let kinds = device
        .opened_traversals(None)
        .into_iter()
        .map(PathKind::of_traversal);
    let samples = u64::from(DEFAULT_WIDTH) * u64::from(DEFAULT_HEIGHT) * u64::from(DEFAULT_SPP);
    calibration::load(&calibration::key(device))?
        .fastest(kinds, samples)?
        .0
        .traversal()
}

/// The CPU path: the CPU, the instruction set Embree's kernels run, and the threads.
pub fn format_cpu(report: &EmbreeReport, settings: &EmbreeSettings) -> String {
    let runs: Vec<&str> = report.cpu_isas.iter().map(|i| i.name()).collect();
    let config = if settings.text.trim().is_empty() {
        format!("Embree's default; {EMBREE_CONFIG_VAR} sets it")
    } else {
        format!("{EMBREE_CONFIG_VAR}=\"{}\"", settings.text)
    };
    let hardware = std::thread::available_parallelism().map_or(1, |n| n.get());
    let build = match report.build_threads {
        0 => format!("{hardware} (every hardware thread)"),
        n => n.to_string(),
    };
    let mut out = format!("CPU path: Embree {}\n", report.version);
    out += &format!("    CPU                {}\n", report.cpu);
    out += &format!("    instruction set    {} ({config})\n", report.isa);
    out += &format!("    this CPU runs      {}\n", runs.join(", "));
    out += &format!(
        "    render threads     {} (rayon; RAYON_NUM_THREADS sets it)\n",
        rayon::current_num_threads()
    );
    out += &format!("    BVH build threads  {build}\n");
    out
}

/// The text `run` prints; `calibrated` names a device's fastest traversal by its cached
/// calibration, which the hybrid and raster paths trace with.
pub fn format_devices(
    devices: &[DeviceReport],
    calibrated: impl Fn(&DeviceReport) -> Option<Traversal>,
) -> String {
    if devices.is_empty() {
        return "no Vulkan devices found (install a Vulkan driver, e.g. Mesa's lavapipe)\n".into();
    }
    let usable = devices
        .iter()
        .filter(|d| !d.traversals().is_empty())
        .count();
    let mut out = format!(
        "{} Vulkan device(s), {usable} usable for GPU rendering:\n",
        devices.len()
    );
    for d in devices {
        out += &format!("\n[{}] {} ({})\n", d.index, d.name, d.device_type);
        out += &format!("    Vulkan API         {}\n", d.api_version);
        out += &format!(
            "    driver             {} (version {})\n",
            d.driver, d.driver_version
        );
        if d.ray_query {
            out += "    ray queries        yes\n";
        } else {
            out += &format!(
                "    ray queries        no: missing {}\n",
                d.missing.join(", ")
            );
        }
        if d.rt_pipeline {
            out += "    rt pipeline        yes\n";
        } else {
            out += &format!(
                "    rt pipeline        no: missing {}\n",
                d.missing_rt_pipeline.join(", ")
            );
        }
        let paths: Vec<&str> = d.traversals().iter().map(|t| t.name()).collect();
        out += &if paths.is_empty() {
            format!(
                "    paths              cpu only: missing {}\n",
                d.missing_software.join(", ")
            )
        } else {
            format!(
                "    paths              {}, hybrid, raster ({}), cpu\n",
                paths.join(", "),
                hybrid_traversal(d, calibrated(d))
            )
        };
        out += &format!("    max image 2D       {} px\n", d.max_image_dimension_2d);
        let [gx, gy, gz] = d.max_compute_work_group_count;
        let [sx, sy, sz] = d.max_compute_work_group_size;
        out += &format!("    compute groups     {gx} x {gy} x {gz}\n");
        out += &format!(
            "    compute group size {sx} x {sy} x {sz} ({} invocations)\n",
            d.max_compute_work_group_invocations
        );
        out += &format!(
            "    max storage buffer {} MiB\n",
            u64::from(d.max_storage_buffer_range) >> 20
        );
        out += &format!(
            "    timestamps         {}\n",
            if d.timestamps {
                format!("yes, {} ns per tick", d.timestamp_period_ns)
            } else {
                "no".into()
            }
        );
    }
    out
}

/// What the hybrid and raster paths trace with on `device`: the one traversal it opens, the
/// calibration's fastest, or the faster of its traversals by a timing at their first render
/// (`paths::auto::pick_traversal`).
fn hybrid_traversal(device: &DeviceReport, calibrated: Option<Traversal>) -> String {
    let opened = device.opened_traversals(None);
    match (opened.as_slice(), calibrated) {
        ([only], _) => format!("tracing with {}", only.name()),
        (_, Some(fastest)) => format!("tracing with {}: this device's calibration", fastest.name()),
        _ => {
            let names: Vec<&str> = opened.iter().map(|t| t.name()).collect();
            format!(
                "tracing with the faster of {}, timed at their first render",
                names.join(" and ")
            )
        }
    }
}
