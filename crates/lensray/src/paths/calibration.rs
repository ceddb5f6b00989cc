//! `auto`'s cost model: how long each path takes on this machine, a fixed cost per render plus a
//! cost per pixel-sample, fitted to two calibration shots (the built-in scene, lit, at two
//! sample counts), measured once per device, driver, CPU and lensray version and cached on
//! disk. `auto` then picks a device and a traversal from a steady signal (the
//! device's type and the cached figures) instead of timing every path on every run, so the same
//! command picks the same path every time.
//!
//! The model is per machine, not per scene: on lavapipe the CPU reference's lead over the GPU
//! paths is about the same on the default scene and on a 1M-triangle one (docs/startup.md).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use super::{CpuPath, PathKind, RenderPath};
use lensray_core::film::Accumulation;
use lensray_core::settings::{RenderSettings, Shading, Shot};
use lensray_vulkan::{DeviceReport, Estimator, GpuOptions, GpuRenderer, Traversal};

/// Bumped when the calibration shot or the measurement changes: older entries are measured again.
const FORMAT: u32 = 1;
/// The calibration shots: the built-in scene and camera at this size, lit, at these sample
/// counts (two, to separate a render's fixed cost from its cost per sample).
pub const WIDTH: u32 = 320;
pub const HEIGHT: u32 = 240;
pub const SPP: [u32; 2] = [2, 8];
/// Timed renders after a warm-up; the median is kept.
const RUNS: usize = 3;

/// A path's cost: wall-clock seconds of a render of `samples` pixel-samples, `fixed +
/// per_sample * samples` (lit: a camera and a shadow ray each).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cost {
    pub fixed_seconds: f64,
    pub seconds_per_sample: f64,
}

impl Cost {
    pub fn seconds(&self, samples: u64) -> f64 {
        self.fixed_seconds + self.seconds_per_sample * samples as f64
    }
}

/// The cost model of one machine: the cost of each path it measured (the CPU reference and the
/// traversals of the device).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// What the figures are valid for (`key`).
    pub key: String,
    pub costs: BTreeMap<PathKind, Cost>,
}

impl Calibration {
    /// The fastest of `kinds` with a cost, for a render of `samples` pixel-samples, with its
    /// predicted seconds.
    pub fn fastest(
        &self,
        kinds: impl IntoIterator<Item = PathKind>,
        samples: u64,
    ) -> Option<(PathKind, f64)> {
        kinds
            .into_iter()
            .filter_map(|k| Some((k, self.costs.get(&k)?.seconds(samples))))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// The fastest traversal of the device for `samples` pixel-samples.
    pub fn fastest_traversal(&self, samples: u64) -> Option<(Traversal, f64)> {
        self.fastest(Traversal::ALL.map(PathKind::of_traversal), samples)
            .and_then(|(k, s)| Some((k.traversal()?, s)))
    }
}

/// What a calibration is valid for: lensray's version, build (a debug build's CPU reference is
/// slower) and the calibration's format, the Vulkan device (name, IDs, driver, pipeline-cache
/// UUID) and the CPU (model, threads).
pub fn key(device: &DeviceReport) -> String {
    let machine = crate::machine::describe();
    let uuid: String = device
        .pipeline_cache_uuid
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    format!(
        "lensray {} {} calibration {FORMAT}; device {} [{:04x}:{:04x}] {} ({}) {uuid}; cpu {} x{}",
        env!("CARGO_PKG_VERSION"),
        if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        },
        device.name,
        device.vendor_id,
        device.device_id,
        device.driver,
        device.driver_version,
        machine.cpu,
        machine.threads
    )
}

/// The calibrations of every machine this cache has seen, one entry per key.
#[derive(Debug, Default, Serialize, Deserialize)]
struct CacheFile {
    calibrations: Vec<Calibration>,
}

fn cache_file(dir: &Path) -> PathBuf {
    dir.join("calibration.json")
}

/// The cached calibration for `key`, if any. A file that cannot be read or parsed is ignored
/// with a notice (it is rewritten by the next calibration).
pub fn load(key: &str) -> Option<Calibration> {
    load_from(&lensray_core::cache::dir()?, key)
}

fn load_from(dir: &Path, key: &str) -> Option<Calibration> {
    let file = cache_file(dir);
    let text = match std::fs::read_to_string(&file) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return None,
        Err(e) => {
            eprintln!("notice: ignoring {}: {e}", file.display());
            return None;
        }
    };
    match serde_json::from_str::<CacheFile>(&text) {
        Ok(cache) => cache.calibrations.into_iter().find(|c| c.key == key),
        Err(e) => {
            eprintln!(
                "notice: ignoring {} (not a lensray calibration: {e})",
                file.display()
            );
            None
        }
    }
}

/// Stores `calibration` (replacing the entry of its key) and returns the file. The file is
/// written whole to a temporary file and renamed, so a reader never sees half of it.
pub fn store(calibration: &Calibration) -> Result<PathBuf> {
    let dir = lensray_core::cache::dir().context("no cache directory (set LENSRAY_CACHE_DIR)")?;
    store_in(&dir, calibration)
}

fn store_in(dir: &Path, calibration: &Calibration) -> Result<PathBuf> {
    let file = cache_file(dir);
    let mut cache = std::fs::read_to_string(&file)
        .ok()
        .and_then(|text| serde_json::from_str::<CacheFile>(&text).ok())
        .unwrap_or_default();
    cache.calibrations.retain(|c| c.key != calibration.key);
    cache.calibrations.push(calibration.clone());
    lensray_core::cache::write_whole(&file, serde_json::to_string_pretty(&cache)?.as_bytes())?;
    Ok(file)
}

/// The calibration shot: the built-in scene's camera at `WIDTH` x `HEIGHT`, lit.
fn shot() -> Result<(lensray_core::scene::Scene, Shot)> {
    let mut description = lensray_core::scene::builtin::default_scene();
    let shot = lensray_core::settings::shot(&description.settings, &description.scene)?;
    lensray_core::settings::light_scene(&description.settings, &mut description.scene)?;
    let settings = RenderSettings {
        shading: Shading::Lit,
        ..shot.render
    };
    Ok((
        description.scene,
        Shot {
            camera: shot.camera.with_resolution(WIDTH, HEIGHT),
            render: settings,
        },
    ))
}

/// The cost of `add(spp, accumulation)` (samples added, the sums read back: a render's work):
/// the median wall-clock seconds of `RUNS` renders at
/// each of `SPP` (after a warm-up, which compiles), a line through the two.
fn cost(mut add: impl FnMut(u32, &mut Accumulation) -> Result<()>) -> Result<Cost> {
    add(SPP[0], &mut Accumulation::new(WIDTH, HEIGHT))?;
    let mut points = [(0.0, 0.0); 2];
    for (point, spp) in points.iter_mut().zip(SPP) {
        let mut seconds = Vec::with_capacity(RUNS);
        for _ in 0..RUNS {
            let mut accumulation = Accumulation::new(WIDTH, HEIGHT);
            let start = Instant::now();
            add(spp, &mut accumulation)?;
            seconds.push(start.elapsed().as_secs_f64());
        }
        let samples = f64::from(WIDTH * HEIGHT * spp);
        *point = (samples, lensray_core::stats::median(&seconds));
    }
    let [(s0, t0), (s1, t1)] = points;
    let seconds_per_sample = ((t1 - t0) / (s1 - s0)).max(0.0);
    Ok(Cost {
        fixed_seconds: (t0 - seconds_per_sample * s0).max(0.0),
        seconds_per_sample,
    })
}

/// Measures the cost of the CPU reference and of every traversal of the Vulkan device `gpu`
/// opens, on the calibration shots.
pub fn measure(gpu: &GpuOptions) -> Result<Calibration> {
    let (scene, shot) = shot()?;
    let mut costs = BTreeMap::new();
    let mut cpu = CpuPath::new();
    cpu.load_scene(&scene)?;
    let cpu_cost = cost(|spp, acc| {
        cpu.add_samples(&shot, 0..spp, acc, &mut |_, _| {})?;
        cpu.read_sums(acc)
    })?;
    costs.insert(PathKind::Cpu, cpu_cost);
    let mut renderer = GpuRenderer::new(&GpuOptions {
        traversal: None,
        ..*gpu
    })?;
    let key = key(&renderer.device_report());
    renderer.load_scene(&scene)?;
    for traversal in renderer.traversals() {
        renderer.set_traversal(traversal)?;
        let traversal_cost = cost(|spp, acc| {
            renderer.add_samples(&shot, Estimator::Traced, 0..spp, acc, &mut |_, _| {})?;
            Ok(renderer.read_sums(acc)?)
        })?;
        costs.insert(PathKind::of_traversal(traversal), traversal_cost);
    }
    renderer.close()?;
    Ok(Calibration { key, costs })
}

/// Which device `auto` renders on, from the device's type and its cached calibration.
#[derive(Clone, Debug, PartialEq)]
pub enum DeviceDecision {
    /// The CPU reference, and why.
    Cpu(String),
    /// The Vulkan device, tracing with this traversal where the calibration names one (else
    /// `auto` times them), and why.
    Gpu(Option<Traversal>, String),
}

/// `auto`'s device for a render of `samples` pixel-samples: the CPU reference where the
/// calibration predicts it faster than every traversal of the device; on a CPU implementation
/// of Vulkan (lavapipe) also without a calibration, since it runs on the very cores the CPU
/// reference uses, unless a calibration predicts a GPU path faster. Otherwise the Vulkan device
/// with its fastest calibrated traversal.
pub fn decide(
    device: &DeviceReport,
    calibration: Option<&Calibration>,
    samples: u64,
) -> DeviceDecision {
    let Some(calibration) = calibration else {
        return if device.is_cpu() {
            DeviceDecision::Cpu(format!(
                "auto: {} is a CPU implementation of Vulkan, on the cores the CPU reference \
                 uses, and no calibration predicts a GPU path faster (`lensray calibrate`)",
                device.name
            ))
        } else {
            DeviceDecision::Gpu(None, String::new())
        };
    };
    let cpu = calibration
        .costs
        .get(&PathKind::Cpu)
        .map(|c| c.seconds(samples));
    match (cpu, calibration.fastest_traversal(samples)) {
        (Some(cpu), Some((traversal, gpu))) if cpu < gpu => DeviceDecision::Cpu(format!(
            "auto: the CPU reference, predicted {:.1}x faster than {} on {} by this machine's \
             calibration (cached)",
            gpu / cpu.max(1e-12),
            PathKind::of_traversal(traversal),
            device.name
        )),
        (cpu, Some((traversal, gpu))) => DeviceDecision::Gpu(
            Some(traversal),
            match cpu {
                Some(cpu) => format!(
                    "{} predicted {:.1}x faster than the CPU reference by this machine's \
                     calibration (cached)",
                    PathKind::of_traversal(traversal),
                    cpu / gpu.max(1e-12)
                ),
                None => format!("{} calibrated fastest", PathKind::of_traversal(traversal)),
            },
        ),
        (_, None) => DeviceDecision::Gpu(None, String::new()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(device_type: &str) -> DeviceReport {
        DeviceReport {
            name: "test device".into(),
            device_type: device_type.into(),
            ..DeviceReport::default()
        }
    }

    /// Costs with no fixed part: `seconds` per million samples.
    fn calibration(pairs: &[(PathKind, f64)]) -> Calibration {
        Calibration {
            key: "k".into(),
            costs: pairs
                .iter()
                .map(|&(k, s)| {
                    let cost = Cost {
                        fixed_seconds: 0.0,
                        seconds_per_sample: s * 1e-6,
                    };
                    (k, cost)
                })
                .collect(),
        }
    }

    #[test]
    fn a_cpu_device_without_a_calibration_renders_on_the_cpu() {
        assert!(matches!(
            decide(&device("CPU"), None, 1),
            DeviceDecision::Cpu(_)
        ));
        assert_eq!(
            decide(&device("discrete GPU"), None, 1),
            DeviceDecision::Gpu(None, String::new())
        );
    }

    #[test]
    fn the_calibration_decides_cpu_against_the_fastest_traversal() {
        use PathKind::*;
        let cpu_fast = calibration(&[(Cpu, 0.01), (RayQuery, 0.08), (Software, 0.05)]);
        let DeviceDecision::Cpu(why) = decide(&device("discrete GPU"), Some(&cpu_fast), 1_000_000)
        else {
            panic!("the CPU was measured 5x faster");
        };
        assert!(why.contains("5.0x faster than software"), "{why}");
        let gpu_fast = calibration(&[(Cpu, 0.05), (RayQuery, 0.01), (Software, 0.02)]);
        for ty in ["CPU", "discrete GPU"] {
            let DeviceDecision::Gpu(traversal, why) =
                decide(&device(ty), Some(&gpu_fast), 1_000_000)
            else {
                panic!("{ty}: rayquery was measured 5x faster than the CPU");
            };
            assert_eq!(traversal, Some(Traversal::RayQuery));
            assert!(why.contains("rayquery") && why.contains("5.0x"), "{why}");
        }
        // A device without ray queries, whose ray-tracing pipeline was measured the fastest.
        let pipeline_fast = calibration(&[(Cpu, 0.05), (RtPipeline, 0.01), (Software, 0.02)]);
        let DeviceDecision::Gpu(traversal, why) =
            decide(&device("discrete GPU"), Some(&pipeline_fast), 1_000_000)
        else {
            panic!("rtpipeline was measured 5x faster than the CPU");
        };
        assert_eq!(traversal, Some(Traversal::RtPipeline));
        assert!(why.contains("rtpipeline"), "{why}");
    }

    #[test]
    fn a_fixed_cost_loses_small_renders_and_wins_large_ones() {
        let mut c = calibration(&[(PathKind::Cpu, 0.1), (PathKind::Software, 0.02)]);
        c.costs.get_mut(&PathKind::Software).unwrap().fixed_seconds = 0.08;
        // Break-even at 1M samples: 0.1 s each.
        let small = decide(&device("discrete GPU"), Some(&c), 100_000);
        assert!(matches!(small, DeviceDecision::Cpu(_)), "{small:?}");
        let large = decide(&device("discrete GPU"), Some(&c), 10_000_000);
        assert!(
            matches!(large, DeviceDecision::Gpu(Some(Traversal::Software), _)),
            "{large:?}"
        );
    }

    #[test]
    fn cache_entries_round_trip_and_a_corrupt_file_is_ignored() {
        let dir = tempfile::tempdir().unwrap();
        let c = calibration(&[(PathKind::Cpu, 0.5), (PathKind::Software, 1.5)]);
        let file = store_in(dir.path(), &c).unwrap();
        assert_eq!(load_from(dir.path(), "k"), Some(c.clone()));
        assert_eq!(load_from(dir.path(), "another machine"), None);
        std::fs::write(&file, "{ not json").unwrap();
        assert_eq!(load_from(dir.path(), "k"), None);
        store_in(dir.path(), &c).unwrap();
        assert_eq!(load_from(dir.path(), "k"), Some(c));
    }
}
