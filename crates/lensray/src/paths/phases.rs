//! Where a render's time goes, phase by phase (`lensray render --timings`, each path of
//! `lensray bench --json`): loading the files, opening the device and its pipelines, the scene
//! on it, tracing (GPU timestamps on GPU paths), the host's time beyond tracing in the sample
//! passes, the read-back, and encoding and writing the image.

use serde::Serialize;

use super::{PathReport, Startup};

/// A render's phases, wall-clock seconds but `tracing_seconds` (GPU timestamps on GPU paths,
/// the CPU reference's wall clock). A *pass* is one sample of every pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Phases {
    /// Scene and lens files read, settings merged, the shot made.
    pub load_seconds: f64,
    /// The device and its pipelines (instance, device, pipeline creation and compilation,
    /// `auto`'s choice).
    pub device_seconds: f64,
    /// Of `device_seconds`, the Vulkan instance and device alone.
    pub instance_seconds: f64,
    /// The scene on the device: upload, acceleration structures or BVH.
    pub scene_seconds: f64,
    /// Tracing, as the path measures it (the G-buffer pass for an AOV).
    pub tracing_seconds: f64,
    /// The render call's time beyond tracing and read-back: what the host does around the
    /// passes (recording, submitting, waiting) and what the device does besides tracing.
    pub beyond_tracing_seconds: f64,
    /// Sample passes of the render (its spp; 1 for an AOV).
    pub passes: u32,
    /// Queue submissions of the render (0 on the CPU): what the host's time per pass pays for.
    pub submits: u64,
    /// Bringing the sums to the host.
    pub readback_seconds: f64,
    /// The lens's own light (`--flare`, `--starburst`): the ghosts traced and drawn (on a GPU
    /// path's device), the starburst's convolution.
    pub flare_seconds: f64,
    /// Encoding the image and writing its file.
    pub write_seconds: f64,
    /// What no phase above holds (focusing, closing the device, the summary).
    pub other_seconds: f64,
    /// The whole command.
    pub total_seconds: f64,
}

impl Phases {
    /// The render call's phases: `wall` seconds around it, `done` what the path reported for
    /// it (`PathReport::since`), `passes` its sample passes, `aov` whether it was an AOV. The
    /// pipelines the call made first (the hybrid's plan pass, a driver's lazy compilation)
    /// count with the device and its pipelines, not beyond tracing.
    pub fn of_render(wall: f64, done: &PathReport, passes: u32, aov: bool) -> Self {
        let tracing_seconds = if aov {
            done.aov_seconds
        } else {
            done.trace_seconds
        };
        let compile = done.compile_seconds.clamp(0.0, wall);
        Self {
            device_seconds: compile,
            tracing_seconds,
            beyond_tracing_seconds: (wall - tracing_seconds - done.readback_seconds - compile)
                .max(0.0),
            passes,
            submits: done.submits,
            readback_seconds: done.readback_seconds,
            ..Self::default()
        }
    }

    /// With what opening the path took.
    pub fn with_startup(self, startup: Startup) -> Self {
        Self {
            device_seconds: self.device_seconds + startup.device_seconds,
            instance_seconds: startup.instance_seconds,
            scene_seconds: startup.scene_seconds,
            ..self
        }
    }

    /// Seconds beyond tracing per sample pass.
    pub fn beyond_tracing_per_pass(&self) -> f64 {
        self.beyond_tracing_seconds / f64::from(self.passes.max(1))
    }

    /// Closes the phases at `total` seconds for the whole command: `other_seconds` is what the
    /// named phases leave.
    pub fn closed(self, total: f64) -> Self {
        let named = self.load_seconds
            + self.device_seconds
            + self.scene_seconds
            + self.tracing_seconds
            + self.beyond_tracing_seconds
            + self.readback_seconds
            + self.flare_seconds
            + self.write_seconds;
        Self {
            other_seconds: (total - named).max(0.0),
            total_seconds: total,
            ..self
        }
    }

    /// One line per phase, `timings: <phase> <seconds> s`, the per-pass figure beside the time
    /// beyond tracing (the flare's only when it was drawn), then the total.
    pub fn lines(&self) -> Vec<String> {
        let per_pass = format!(
            " ({:.3} ms per pass, {} passes, {} submissions)",
            self.beyond_tracing_per_pass() * 1e3,
            self.passes,
            self.submits
        );
        let device = if self.instance_seconds > 0.0 {
            format!(
                " (instance and device {:.4} s, pipelines {:.4} s)",
                self.instance_seconds,
                self.device_seconds - self.instance_seconds
            )
        } else {
            String::new()
        };
        [
            ("load", self.load_seconds, String::new()),
            ("device and pipelines", self.device_seconds, device),
            (
                "scene upload and acceleration structures",
                self.scene_seconds,
                String::new(),
            ),
            ("tracing", self.tracing_seconds, String::new()),
            ("beyond tracing", self.beyond_tracing_seconds, per_pass),
            ("read-back", self.readback_seconds, String::new()),
            ("flare", self.flare_seconds, String::new()),
            ("encode and write", self.write_seconds, String::new()),
            ("other", self.other_seconds, String::new()),
            ("total", self.total_seconds, String::new()),
        ]
        .into_iter()
        .filter(|&(name, seconds, _)| name != "flare" || seconds > 0.0)
        .map(|(name, seconds, note)| format!("timings: {name} {seconds:.4} s{note}"))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_phases_and_other_sum_to_the_total() {
        let done = PathReport {
            trace_seconds: 0.5,
            compile_seconds: 0.04,
            submits: 3,
            readback_seconds: 0.1,
            ..PathReport::default()
        };
        let phases = Phases {
            load_seconds: 0.05,
            write_seconds: 0.02,
            ..Phases::of_render(0.84, &done, 4, false)
        }
        .with_startup(Startup {
            device_seconds: 0.2,
            instance_seconds: 0.15,
            scene_seconds: 0.03,
        })
        .closed(1.2);
        assert!((phases.device_seconds - 0.24).abs() < 1e-12);
        assert!((phases.beyond_tracing_seconds - 0.2).abs() < 1e-12);
        assert!((phases.beyond_tracing_per_pass() - 0.05).abs() < 1e-12);
        assert!((phases.other_seconds - 0.06).abs() < 1e-9);
        let lines = phases.lines();
        assert_eq!(lines.len(), 9);
        assert_eq!(
            lines[1],
            "timings: device and pipelines 0.2400 s (instance and device 0.1500 s, pipelines 0.0900 s)"
        );
        assert_eq!(
            lines[4],
            "timings: beyond tracing 0.2000 s (50.000 ms per pass, 4 passes, 3 submissions)"
        );
        assert_eq!(lines[8], "timings: total 1.2000 s");
    }
}
