//! `lensray bench`: the command line of `crate::bench`. Output files are checked writable
//! before any work and written whole at the end (temporary file, then rename).

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::Args;

use super::args::{DeviceArgs, MovementArgs};
use super::named::by_name;
use crate::bench::options::{
    BenchOptions, NamedScene, SceneChoice, SweepKind, DEFAULT_CACHE_DIR, DEFAULT_REFERENCE_SPP,
};
use crate::output::PendingFile;
use crate::paths::PathChoice;
use lensray_core::camera::flare::FlareSwitches;
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::generate::DEFAULT_DENSE_TRIANGLES;
use lensray_core::scene::units::SceneUnits;
use lensray_core::settings::{Shading, Switch};

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Paths to compare, comma-separated (listed below), or auto (the path
    /// `--path auto` picks) [default: every path this machine can run].
    #[arg(
        long,
        alias = "path",
        value_enum,
        value_delimiter = ',',
        value_name = "PATH,..."
    )]
    pub paths: Vec<PathChoice>,
    /// With `--device`: which devices the default list of paths uses: auto (the GPU paths of a
    /// usable Vulkan device, plus the CPU), gpu (the GPU paths only), cpu (the CPU path only).
    #[command(flatten)]
    pub device: DeviceArgs,
    /// A named scene [default: default]...
    #[arg(long, value_enum, conflicts_with = "scene_file")]
    pub scene: Option<NamedScene>,
    /// ...or a scene file / mesh.
    #[arg(long, value_name = "FILE")]
    pub scene_file: Option<PathBuf>,
    /// The unit of length of the scene and of --aperture-radius and --focus-distance: m, cm,
    /// mm or in [default: the scene file's `units`, else m].
    #[arg(long, value_name = "UNITS", value_parser = SceneUnits::parse)]
    pub scene_units: Option<SceneUnits>,
    /// Triangles of `--scene dense`.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_DENSE_TRIANGLES)]
    pub dense_triangles: usize,
    #[arg(long, value_name = "W", default_value_t = lensray_core::settings::DEFAULT_WIDTH)]
    pub width: u32,
    #[arg(long, value_name = "H", default_value_t = lensray_core::settings::DEFAULT_HEIGHT)]
    pub height: u32,
    /// Samples per pixel (the largest of the spp sweep).
    #[arg(long, value_name = "N", default_value_t = lensray_core::settings::DEFAULT_SPP)]
    pub spp: u32,
    /// Adaptive sampling as on `render` (--spp its cap) [default: the scene's]: the paths that
    /// cannot are left out (docs/adaptive.md); the reference stays uniform.
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub noise_threshold: Option<f64>,
    #[arg(long, value_parser = by_name::<Shading>(), default_value = Shading::Unlit.name())]
    pub shading: Shading,
    /// Lens aperture radius, in the scene's units (0 = pinhole) [default: the scene's].
    #[arg(long, value_name = "R")]
    pub aperture_radius: Option<f64>,
    /// Distance to the plane in focus, in the scene's units [default: the scene's].
    #[arg(long, value_name = "D")]
    pub focus_distance: Option<f64>,
    /// f-number: of `--sweep lens`'s real lenses (stop closed until the entrance pupil gives
    /// N) [default: each wide open], else of the scene's lens given by focal length.
    #[arg(long, value_name = "N")]
    pub f_number: Option<f64>,
    /// As on `render`; with `--sweep movements`, the shifted and tilted points' movements
    /// [default: shift 0,-0.1, tilt 82 toward 0: the default scene's plane of focus laid level].
    #[command(flatten)]
    pub movements: MovementArgs,
    /// How samples are drawn [default: the scene's, else sobol].
    #[arg(long, value_parser = by_name::<SamplerKind>())]
    pub sampler: Option<SamplerKind>,
    /// Seed of the paths' samples (the reference uses another).
    #[arg(long, value_name = "S")]
    pub seed: Option<u32>,
    /// With a real lens (the scene's): each render draws the lens's ghosts too, timed apart
    /// (on a GPU path traced on its device), against the render's time.
    #[arg(long, value_parser = by_name::<Switch>(), value_name = "on|off")]
    pub flare: Option<Switch>,
    /// With a real lens: each render draws the aperture's starburst too, timed apart.
    #[arg(long, value_parser = by_name::<Switch>(), value_name = "on|off")]
    pub starburst: Option<Switch>,
    /// Timed runs per path and point, after one warm-up run.
    #[arg(long, alias = "runs", value_name = "N", default_value_t = 5, value_parser = parse_repeat)]
    pub repeat: usize,
    /// Samples per pixel of the converged reference (CPU, rendered once and cached).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_REFERENCE_SPP)]
    pub reference_spp: u32,
    /// Where references are cached.
    #[arg(long, value_name = "DIR", default_value = DEFAULT_CACHE_DIR)]
    pub cache_dir: PathBuf,
    /// Render the reference every time instead of caching it.
    #[arg(long)]
    pub no_cache: bool,
    /// Measure over a range of work: spp (error against time), resolution, triangles
    /// (generated scenes), aperture shapes (each one's cost against the round aperture,
    /// measured in turns), real lenses (each one's cost per camera ray that reaches the
    /// scene against its first-order thin lens, and the share of camera samples it lets
    /// through; cpu, rayquery and software), or movements (the shot shifted and tilted by
    /// --shift, --tilt and --tilt-direction [default: 0,-0.1, 82 and 0: the default scene's
    /// plane of focus laid level] against the plain shot, time per sample, measured in
    /// turns). Without it, one point;
    /// `--plot` then sweeps spp.
    #[arg(long, value_enum)]
    pub sweep: Option<SweepKind>,
    /// The sweep's values instead of its defaults: "1,4,16", "160x120,640x480", "10k,1M",
    /// "hexagon,image" (of round, hexagon, curved9, squeezed, image), "thin,double-gauss-50"
    /// (built-in lenses; each comes with its thin model, "thin"), "plain,moved" (of plain,
    /// shift, tilt, moved).
    #[arg(long, value_name = "LIST")]
    pub sweep_points: Option<String>,
    /// Write every figure as JSON.
    #[arg(long, value_name = "FILE", value_parser = boxed_path())]
    pub json: Option<Box<Path>>,
    /// Draw error against time (or time against the swept quantity) as a PNG.
    #[arg(long, value_name = "FILE.png", value_parser = boxed_path())]
    pub plot: Option<Box<Path>>,
}

/// A path held in a box: the output files' (keeps `BenchArgs` small, as `Command` holds
/// the arguments of each subcommand).
fn boxed_path() -> impl clap::builder::TypedValueParser<Value = Box<Path>> {
    use clap::builder::TypedValueParser;
    clap::builder::PathBufValueParser::new().map(PathBuf::into_boxed_path)
}

fn parse_repeat(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err("the number of timed runs must be a whole number >= 1".into()),
    }
}

impl BenchArgs {
    pub fn options(&self) -> BenchOptions {
        BenchOptions {
            scene: match (&self.scene_file, self.scene) {
                (Some(file), _) => SceneChoice::File(file.clone()),
                (None, scene) => SceneChoice::Named(scene.unwrap_or(NamedScene::Default)),
            },
            dense_triangles: self.dense_triangles,
            scene_units: self.scene_units,
            paths: self.paths.clone(),
            device: self.device.device,
            gpu: self.device.gpu_options(),
            width: self.width,
            height: self.height,
            spp: self.spp,
            noise_threshold: self.noise_threshold,
            shading: self.shading,
            aperture_radius: self.aperture_radius,
            focus_distance: self.focus_distance,
            f_number: self.f_number,
            shift: self.movements.shift,
            tilt: self.movements.tilt,
            tilt_direction: self.movements.tilt_direction,
            sampler: self.sampler,
            seed: self.seed,
            repeat: self.repeat,
            reference_spp: self.reference_spp,
            cache_dir: (!self.no_cache).then(|| self.cache_dir.clone()),
            // A plot needs curves: without a sweep it sweeps spp.
            sweep: self.sweep.or(self.plot.as_ref().map(|_| SweepKind::Spp)),
            sweep_points: self.sweep_points.clone(),
            flare: FlareSwitches {
                ghosts: self.flare == Some(Switch::On),
                starburst: self.starburst == Some(Switch::On),
            },
        }
    }
}

pub fn run(args: &BenchArgs) -> Result<()> {
    if let Some(plot) = &args.plot {
        if !plot
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
        {
            bail!(
                "--plot {}: the plot is a PNG (name it .png)",
                plot.display()
            );
        }
    }
    // Fail on a bad output path before spending minutes measuring.
    let json = args.json.as_deref().map(PendingFile::create).transpose()?;
    let plot = args.plot.as_deref().map(PendingFile::create).transpose()?;
    let report = crate::bench::run(&args.options(), &mut |line| eprintln!("{line}"))?;
    print!("{}", crate::bench::table::render(&report));
    if let Some(json) = json {
        let path = json.path().display().to_string();
        json.finish(report.to_json().as_bytes())?;
        println!("wrote {path}");
    }
    if let Some(plot) = plot {
        let path = plot.path().display().to_string();
        plot.finish(&crate::bench::plot::png(&report)?)?;
        println!("wrote {path}");
    }
    Ok(())
}
