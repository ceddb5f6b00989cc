//! The `lensray` command.

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use lensray::cli;

#[derive(Parser)]
#[command(
    name = "lensray",
    version,
    about = "Thin-lens depth of field: CPU reference and Vulkan ray queries",
    // A later repetition of an option wins, as in most renderers' command lines.
    args_override_self = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Read only files inside DIR: a file a scene names outside it (by `..`, an absolute path
    /// or a link) is refused. Default: the environment's LENSRAY_ASSETS_ROOT, else no limit.
    #[arg(long, global = true, value_name = "DIR")]
    assets_root: Option<std::path::PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Render an image headless (default: the built-in scene to lensray.png).
    Render(Box<cli::render::RenderArgs>),
    /// A window to frame the shot and pick the focus, with ray-traced depth of field converging
    /// live (controls below, and H in the window).
    Preview(Box<cli::preview::PreviewArgs>),
    /// Compare the render paths: time, rays/s, memory and error against a converged reference.
    Bench(Box<cli::bench::BenchArgs>),
    /// Measure this machine's paths once and cache the figures `--path auto` decides from.
    Calibrate(cli::calibrate::CalibrateArgs),
    /// Write a generated scene (OBJ + MTL + scene file).
    Generate(cli::generate::GenerateArgs),
    /// List the Vulkan devices, their ray-query support and the limits that matter.
    Info,
    /// A lens's first-order data (focal lengths, principal planes, pupils, f-number) and
    /// real-ray data (chief rays, spherical aberration), from its prescription.
    Lens(cli::lens::LensArgs),
}

fn main() -> ExitCode {
    // The preview's controls come from its key-binding table, listed after its options.
    let command = Cli::command().mut_subcommand("preview", |c| {
        c.after_help(format!("Controls:\n{}", lensray::preview::controls_help()))
    });
    let cli = match command
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m))
    {
        Ok(cli) => cli,
        Err(error) if !error.use_stderr() => error.exit(), // --help, --version
        Err(error) => {
            // One line naming the problem (clap adds usage lines after it).
            let text = error.render().to_string();
            eprintln!(
                "{}",
                text.lines().next().unwrap_or("error: bad command line")
            );
            return ExitCode::from(2);
        }
    };
    // Embree's configuration comes from the environment; a bad one stops every command here, in
    // one line, rather than inside a render.
    if let Err(error) = lensray_core::reference::EmbreeSettings::from_env() {
        eprintln!("error: {error}");
        return ExitCode::from(2);
    }
    let root = cli.assets_root.clone().or_else(|| {
        std::env::var_os("LENSRAY_ASSETS_ROOT")
            .filter(|v| !v.is_empty())
            .map(Into::into)
    });
    if let Some(root) = root {
        if let Err(error) = lensray_core::scene::reads::confine_reads_to(&root) {
            eprintln!("error: {error}");
            return ExitCode::from(2);
        }
    }
    let result = match &cli.command {
        None => {
            // No subcommand at all: render the default scene with every default.
            cli::sequence::run(&cli::render::RenderArgs::default())
        }
        Some(Command::Render(args)) => cli::sequence::run(args),
        Some(Command::Preview(args)) => cli::preview::run(args),
        Some(Command::Bench(args)) => cli::bench::run(args),
        Some(Command::Calibrate(args)) => cli::calibrate::run(args),
        Some(Command::Generate(args)) => cli::generate::run(args),
        Some(Command::Info) => cli::info::run(),
        Some(Command::Lens(args)) => cli::lens::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // One line: the context chain joined, as "scene x.toml: camera: focus ...".
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
