//! `lensray render`: one image, headless.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::args::{DeviceChoice, ViewArgs};
use crate::output::PendingOutput;
use crate::reference::Renderer;
use crate::resolve::{resolve, Resolved};
use crate::scene::file::SceneDescription;
use crate::settings::Settings;

pub const DEFAULT_OUTPUT: &str = "lensray.png";

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    /// Which renderer: the GPU (Vulkan ray queries) or the CPU reference.
    #[arg(long, value_enum, default_value_t = DeviceChoice::Auto)]
    pub device: DeviceChoice,
    /// Output image: .png (sRGB) or .exr (linear float).
    #[arg(long, value_name = "FILE", default_value = DEFAULT_OUTPUT)]
    pub out: PathBuf,
}

/// The scene the options name, or the built-in default scene.
pub fn load_scene(view: &ViewArgs) -> Result<SceneDescription> {
    match &view.scene {
        Some(path) => Ok(crate::scene::file::load(path)?),
        None => Ok(crate::scene::builtin::default_scene()),
    }
}

/// The scene file's settings with the command line's on top. Lens options replace the file's
/// lens as a group, so a file's aperture radius does not clash with a command-line focal length.
pub fn merged_settings(file: &Settings, view: &ViewArgs) -> Settings {
    let over = view.to_settings();
    let mut base = file.clone();
    if over.camera.focal_length_mm.is_some() {
        base.camera.aperture_radius = None;
    }
    if over.camera.aperture_radius.is_some() {
        base.camera.focal_length_mm = None;
        base.camera.f_number = None;
        base.camera.sensor_height_mm = None;
    }
    base.overridden_by(&over)
}

/// A progress bar that appears only once a render has run for a second.
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    shown: bool,
}

impl Progress {
    pub fn new(label: &str) -> Self {
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{msg} [{bar:40}] {percent:>3}% {elapsed} (eta {eta})")
                .expect("valid template")
                .progress_chars("=> "),
        );
        bar.set_message(label.to_owned());
        Self {
            bar,
            start: Instant::now(),
            shown: false,
        }
    }

    pub fn update(&mut self, done: u64, total: u64) {
        self.bar.set_length(total);
        self.bar.set_position(done);
        if !self.shown && self.start.elapsed() > Duration::from_secs(1) && done < total {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
    }

    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}

impl Default for RenderArgs {
    fn default() -> Self {
        Self {
            view: ViewArgs::default(),
            device: DeviceChoice::Auto,
            out: PathBuf::from(DEFAULT_OUTPUT),
        }
    }
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    // Fail on a bad output path before spending time on the render.
    let output = PendingOutput::create(&args.out)?;
    let description = load_scene(&args.view)?;
    let settings = merged_settings(&description.settings, &args.view);
    let Resolved { camera, render } = resolve(&settings, &description.scene)
        .with_context(|| format!("scene {}", description.source))?;

    let (image, rays, render_time, device) = match args.device {
        DeviceChoice::Gpu => anyhow::bail!(
            "--device gpu: the Vulkan renderer is not part of this build yet; use --device cpu"
        ),
        DeviceChoice::Auto | DeviceChoice::Cpu => {
            let renderer = Renderer::new(&description.scene);
            let mut progress = Progress::new("rendering (CPU)");
            let (image, stats) =
                renderer.render(&camera, &render, &mut |d, t| progress.update(d, t));
            progress.finish();
            (
                image,
                stats.rays,
                stats.elapsed,
                format!("CPU reference, {} threads", rayon::current_num_threads()),
            )
        }
    };
    output.finish(&image, render.shading)?;
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "{}: {}x{} px, {} spp, {:?} shading, {} triangles, on {}: {:.2} s total, {:.2} Mrays/s",
        args.out.display(),
        camera.width,
        camera.height,
        render.spp,
        render.shading,
        description.scene.triangle_count(),
        device,
        elapsed,
        rays as f64 / render_time.as_secs_f64().max(1e-9) / 1e6
    );
    Ok(())
}
