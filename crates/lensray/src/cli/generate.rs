//! `lensray generate default|cornell|spheres|dense|bokeh|textured|studio [--out DIR]
//! [--triangles N] [--gltf]`: writes a generated scene (or the built-in default one) as
//! `<out>/<name>.obj`, `<name>.mtl` and a scene file `<name>.toml` naming the OBJ, or with
//! `--gltf` as `<name>.gltf` and `<name>.bin` (binary data: loaded without parsing text) with
//! the scene file naming those; `textured` writes both, reading its PNGs; `studio` writes an
//! HDR environment map, `studio.hdr`.

use std::fs;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};

use lensray_core::scene::builtin::default_scene;
use lensray_core::scene::environment::studio;
use lensray_core::scene::file::write_scene_file;
use lensray_core::scene::generate::{
    bokeh, cornell_box, dense, sphere_row, DEFAULT_DENSE_TRIANGLES,
};
use lensray_core::scene::gltf_out::write_scene_gltf;
use lensray_core::scene::textured::{self, write_textured};
use lensray_core::scene::{write_obj, SceneDescription};

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Which {
    /// The built-in default scene (what `lensray render` draws without `--scene`), for other
    /// tools: the same triangles, materials and camera.
    Default,
    /// Cornell-box-style room with a box, a sphere and a ceiling light.
    Cornell,
    /// A row of coloured spheres receding in depth.
    Spheres,
    /// At least `--triangles` triangles (default 1M) of spheres on a checkerboard, for benchmarks.
    Dense,
    /// Small bright lights in front of and behind an in-focus subject: the aperture's shape.
    Bokeh,
    /// Textured cards and a leaf cut out by its alpha, as glTF and as OBJ with a scene file.
    Textured,
    /// A photographic studio as an equirectangular HDR environment (`studio.hdr`, 1024x512).
    Studio,
}

impl Which {
    /// One line on what the scene shows.
    pub fn description(self) -> &'static str {
        match self {
            Which::Default => "The built-in default scene: seven coloured spheres receding in depth on a checkerboard, the middle one in focus.",
            Which::Cornell => "A Cornell-box-style room (red left wall, green right wall) with a tall box, a sphere in focus and a ceiling light.",
            Which::Spheres => "Five coloured spheres in a row receding in depth on a grey ground, the middle one in focus.",
            Which::Dense => "A benchmark scene: a 10 x 10 grid of finely tessellated spheres on a checkerboard, focused on the middle.",
            Which::Bokeh => "Small bright lights at several depths in front of and behind an in-focus sphere on a dark background: out-of-focus highlights take the aperture's shape.",
            Which::Textured => textured::DESCRIPTION,
            Which::Studio => "An equirectangular HDR environment: a dim studio, a key, a fill and a strip softbox and seven small bright lamps (--environment FILE).",
        }
    }

    /// The file stem of the scene's files.
    pub fn name(self) -> &'static str {
        match self {
            Which::Default => "default",
            Which::Cornell => "cornell",
            Which::Spheres => "spheres",
            Which::Dense => "dense",
            Which::Bokeh => "bokeh",
            Which::Textured => textured::NAME,
            Which::Studio => "studio",
        }
    }
}

#[derive(Clone, Debug, clap::Args)]
pub struct GenerateArgs {
    /// Which scene to generate.
    #[arg(value_enum)]
    pub which: Which,
    /// Folder to write `<name>.obj`, `<name>.mtl` and `<name>.toml` into (created if missing);
    /// `textured` adds `textured.gltf`, `textured.bin` and its PNGs.
    #[arg(long, value_name = "DIR", default_value = "assets/generated")]
    pub out: PathBuf,
    /// Minimum number of triangles (dense only) [default: 1000000].
    #[arg(long, value_name = "N")]
    pub triangles: Option<usize>,
    /// Write the meshes as glTF (`<name>.gltf` + `<name>.bin`) instead of OBJ + MTL: binary
    /// vertex data, which loads without parsing text (the 1M-triangle scene's start-up).
    #[arg(long)]
    pub gltf: bool,
}

/// The file format of a generated scene's meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    Obj,
    Gltf,
}

/// Generates the scene and prints where it went.
pub fn run(args: &GenerateArgs) -> anyhow::Result<()> {
    if args.triangles.is_some() && args.which != Which::Dense {
        bail!(
            "--triangles applies only to `dense`, not `{}`",
            args.which.name()
        );
    }
    if args.gltf && args.which == Which::Studio {
        bail!("`studio` is an environment map, not meshes: leave out --gltf");
    }
    if args.gltf && args.which == Which::Textured {
        bail!("`textured` always writes glTF beside its OBJ: leave out --gltf");
    }
    let format = if args.gltf {
        MeshFormat::Gltf
    } else {
        MeshFormat::Obj
    };
    let triangles = args.triangles.unwrap_or(DEFAULT_DENSE_TRIANGLES);
    let (path, triangles) = generate_as(args.which, &args.out, triangles, format)?;
    if args.which == Which::Studio {
        println!(
            "wrote {} ({STUDIO_WIDTH}x{} environment)",
            path.display(),
            STUDIO_WIDTH / 2
        );
    } else if args.which == Which::Textured {
        let gltf = path.with_extension("gltf");
        let (path, gltf) = (path.display(), gltf.display());
        println!("wrote {path} (the OBJ's) and {gltf} ({triangles} triangles)");
    } else {
        println!("wrote {} ({triangles} triangles)", path.display());
    }
    Ok(())
}

/// First line of a generated scene file, recording how it was made.
fn header(which: Which, dense_triangles: usize) -> String {
    match which {
        Which::Dense => format!("lensray generate dense --triangles {dense_triangles}"),
        other => format!("lensray generate {}", other.name()),
    }
}

/// Writes the scene's files (three; `textured` also its glTF, buffer and PNGs) into `out` and
/// returns the scene file's path and the triangle count. Files are written into a temporary
/// folder first and then renamed into place, the scene file last, so that a complete scene file
/// means complete mesh files.
pub fn generate(
    which: Which,
    out: &Path,
    dense_triangles: usize,
) -> anyhow::Result<(PathBuf, usize)> {
    generate_as(which, out, dense_triangles, MeshFormat::Obj)
}

/// [`generate`] with the meshes in `format`.
pub fn generate_as(
    which: Which,
    out: &Path,
    dense_triangles: usize,
    format: MeshFormat,
) -> anyhow::Result<(PathBuf, usize)> {
    let description: SceneDescription = match which {
        Which::Default => default_scene(),
        Which::Cornell => cornell_box(),
        Which::Spheres => sphere_row(),
        Which::Dense => dense(dense_triangles),
        Which::Bokeh => bokeh(),
        Which::Textured => return generate_textured(out),
        Which::Studio => return generate_studio(out),
    };
    let name = which.name();
    let staging = staging(out)?;
    let (mesh, mut files) = match format {
        MeshFormat::Obj => {
            let obj = format!("{name}.obj");
            write_obj(&description.scene, &staging.path().join(&obj))
                .with_context(|| format!("cannot write {obj} into {}", out.display()))?;
            (obj, vec![format!("{name}.mtl"), format!("{name}.obj")])
        }
        MeshFormat::Gltf => {
            let files = write_scene_gltf(&description.scene, staging.path(), name)
                .with_context(|| format!("cannot write {name}.gltf into {}", out.display()))?;
            (format!("{name}.gltf"), files)
        }
    };
    let comment = format!(
        "{}\n{}\n{} triangles. Units are metres; `mesh` is relative to this file.",
        header(which, dense_triangles),
        which.description(),
        description.scene.triangle_count()
    );
    write_scene_file(
        &staging.path().join(format!("{name}.toml")),
        &mesh,
        &description.settings,
        &comment,
    )
    .with_context(|| format!("cannot write {name}.toml into {}", out.display()))?;
    files.push(format!("{name}.toml"));
    move_into(&staging, &files, out)?;
    Ok((
        out.join(format!("{name}.toml")),
        description.scene.triangle_count(),
    ))
}

/// Width of the generated studio environment (texels; half as high).
const STUDIO_WIDTH: u32 = 1024;

/// Writes `studio.hdr` into `out` (through a temporary folder, as the scenes).
fn generate_studio(out: &Path) -> anyhow::Result<(PathBuf, usize)> {
    let staging = staging(out)?;
    let file = "studio.hdr".to_string();
    studio::write_environment(&studio::studio(STUDIO_WIDTH), &staging.path().join(&file))
        .map_err(|e| anyhow::anyhow!("cannot write {file}: {e}"))?;
    move_into(&staging, std::slice::from_ref(&file), out)?;
    Ok((out.join(file), 0))
}

/// A temporary folder inside `out` (created if missing) to write a scene's files into.
fn staging(out: &Path) -> anyhow::Result<tempfile::TempDir> {
    fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    tempfile::Builder::new()
        .prefix(".lensray-generate-")
        .tempdir_in(out)
        .with_context(|| format!("cannot write into {}", out.display()))
}

/// Renames `files` from `staging` into `out`, in order.
fn move_into(staging: &tempfile::TempDir, files: &[String], out: &Path) -> anyhow::Result<()> {
    for file in files {
        fs::rename(staging.path().join(file), out.join(file))
            .with_context(|| format!("cannot move {file} into {}", out.display()))?;
    }
    Ok(())
}

/// [`generate`] for the textured scene: its PNGs, glTF and OBJ, the scene file last.
fn generate_textured(out: &Path) -> anyhow::Result<(PathBuf, usize)> {
    let staging = staging(out)?;
    let files = write_textured(staging.path())
        .with_context(|| format!("cannot write the textured scene into {}", out.display()))?;
    move_into(&staging, &files, out)?;
    let triangles = textured::textured_scene().scene.triangle_count();
    Ok((out.join(format!("{}.toml", textured::NAME)), triangles))
}

/// The dense scene's scene file in `dir`, generated only when it is missing or was made with
/// another triangle count (its first line records the count). Benchmarks call this.
pub fn ensure_dense_scene(dir: &Path, triangles: usize) -> anyhow::Result<PathBuf> {
    let toml = dir.join("dense.toml");
    let expected = format!("# {}", header(Which::Dense, triangles));
    let up_to_date = fs::File::open(&toml)
        .ok()
        .and_then(|f| BufReader::new(f).lines().next())
        .and_then(Result::ok)
        .is_some_and(|first| first == expected)
        && dir.join("dense.obj").is_file()
        && dir.join("dense.mtl").is_file();
    if up_to_date {
        return Ok(toml);
    }
    Ok(generate(Which::Dense, dir, triangles)?.0)
}
