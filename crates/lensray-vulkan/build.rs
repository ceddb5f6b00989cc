//! Compiles the GLSL shaders in `shaders/` to SPIR-V (Vulkan 1.2, SPIR-V 1.4) with shaderc.
//! `shaders/` has the layers of `lensray-vulkan/src/`: `include/` (what the shaders share: camera, sampler,
//! scene, shading), `passes/` (the renderer's passes), `present/` (the preview window's) and
//! `probes/` (tests' and benchmarks', compiled only with the `probes` feature, as their Rust
//! side). Each `shaders/LAYER/NAME.{vert,frag,comp}` becomes `$OUT_DIR/NAME.STAGE.spv`, embedded
//! by `lensray-vulkan/src/core/shader.rs` with `include_bytes!`. `#include "x.glsl"` resolves in
//! `shaders/include/`. A shader listed in `VARIANTS` is compiled once per variant instead, with
//! that variant's macros defined, into `$OUT_DIR/VARIANT.STAGE.spv`.
//! A compile error fails the build with the file and line of every message.
//!
//! First it writes `$OUT_DIR/interface.glsl` and a `$OUT_DIR/set_<name>.glsl` per pipeline's
//! descriptor set from the `lensray-interface` crate, the one definition of what the host and
//! the shaders share, and fails if Rust lays out a shared struct differently from GLSL.

// Brings in the glslang / SPIRV-Tools libraries that Debian's libshaderc needs (see its build.rs).
extern crate lensray_shaderc_link;

use std::path::{Path, PathBuf};

const INTERFACE_HEADER: &str = "interface.glsl";

/// A variant of a shader: its output name and the macros it defines.
type Variant = (&'static str, &'static [&'static str]);

/// Shaders compiled more than once: file name, then its variants; a variant's stage is its
/// output name's extension. trace.comp: one closest-hit implementation each
/// (lensray-vulkan/src/passes/trace.rs picks the pipeline), the ray-tracing pipeline's as its
/// ray generation stage. The ray-tracing pipeline's any-hit and miss stages: one per kind of
/// ray (shaders/include/hit_rtpipeline.glsl). The raster
/// stages: as written, and with PLAIN_SURFACES, which draws the surfaces with none of the bits
/// the pass is specialized on (untextured and opaque; the visibility pass: not alpha-tested),
/// without the inputs only those bits' code reads. The G-buffer's vertex stage and the view
/// pass's fragment stage: once per view of the view pass (SHOWN_*) too, each passing only what
/// the view reads (shaders/include/surface_varyings.glsl).
const VARIANTS: &[(&str, &[Variant])] = &[
    (
        "trace.comp",
        &[
            ("trace_rayquery.comp", &["TRAVERSAL_RAY_QUERY"]),
            ("trace_software.comp", &["TRAVERSAL_SOFTWARE"]),
            ("trace_rtpipeline.rgen", &["TRAVERSAL_RT_PIPELINE"]),
        ],
    ),
    (
        "rt_hit.rahit",
        &[("rt_hit.rahit", &[]), ("rt_shadow.rahit", &["SHADOW_RAY"])],
    ),
    (
        "rt_miss.rmiss",
        &[("rt_miss.rmiss", &[]), ("rt_shadow.rmiss", &["SHADOW_RAY"])],
    ),
    (
        "gbuffer.vert",
        &[
            ("gbuffer.vert", &[]),
            ("gbuffer_plain.vert", PLAIN),
            ("view_albedo.vert", &["SHOWN_ALBEDO"]),
            (
                "view_albedo_plain.vert",
                &["SHOWN_ALBEDO", "PLAIN_SURFACES"],
            ),
            ("view_normal.vert", &["SHOWN_NORMAL"]),
            (
                "view_normal_plain.vert",
                &["SHOWN_NORMAL", "PLAIN_SURFACES"],
            ),
            ("view_depth.vert", &["SHOWN_DEPTH"]),
            ("view_depth_plain.vert", &["SHOWN_DEPTH", "PLAIN_SURFACES"]),
            ("view_coc.vert", &["SHOWN_COC"]),
            ("view_coc_plain.vert", &["SHOWN_COC", "PLAIN_SURFACES"]),
        ],
    ),
    (
        "gbuffer.frag",
        &[("gbuffer.frag", &[]), ("gbuffer_plain.frag", PLAIN)],
    ),
    (
        "view.frag",
        &[
            ("view_albedo.frag", &["SHOWN_ALBEDO"]),
            (
                "view_albedo_plain.frag",
                &["SHOWN_ALBEDO", "PLAIN_SURFACES"],
            ),
            ("view_normal.frag", &["SHOWN_NORMAL"]),
            (
                "view_normal_plain.frag",
                &["SHOWN_NORMAL", "PLAIN_SURFACES"],
            ),
            ("view_depth.frag", &["SHOWN_DEPTH"]),
            ("view_depth_plain.frag", &["SHOWN_DEPTH", "PLAIN_SURFACES"]),
            ("view_coc.frag", &["SHOWN_COC"]),
            ("view_coc_plain.frag", &["SHOWN_COC", "PLAIN_SURFACES"]),
        ],
    ),
    (
        "visibility.vert",
        &[("visibility.vert", &[]), ("visibility_plain.vert", PLAIN)],
    ),
    (
        "visibility.frag",
        &[("visibility.frag", &[]), ("visibility_plain.frag", PLAIN)],
    ),
];
const PLAIN: &[&str] = &["PLAIN_SURFACES"];

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR"));
    let shader_dir = manifest.join("shaders");
    println!("cargo:rerun-if-changed=shaders");

    if let Err(errors) = lensray_interface::check_layouts() {
        panic!("shared structs differ from their GLSL layout:\n{errors}");
    }
    std::fs::write(out.join(INTERFACE_HEADER), lensray_interface::glsl_header())
        .expect("write interface.glsl");
    // Each pipeline's descriptor set (lensray-interface's bindings.rs): `set_<name>.glsl`.
    for set in lensray_interface::SETS {
        let file = format!("set_{}.glsl", set.name);
        std::fs::write(out.join(&file), lensray_interface::set_glsl(set))
            .unwrap_or_else(|e| panic!("write {file}: {e}"));
    }

    let compiler = shaderc::Compiler::new().expect("shaderc: cannot create a compiler");
    let mut layers = vec!["passes", "present"];
    if std::env::var_os("CARGO_FEATURE_PROBES").is_some() {
        layers.push("probes");
    }
    let mut entries: Vec<PathBuf> = Vec::new();
    for layer in layers {
        let dir = shader_dir.join(layer);
        entries.extend(
            std::fs::read_dir(&dir)
                .unwrap_or_else(|e| panic!("read {}: {e}", dir.display()))
                .map(|e| e.expect("read shaders/").path()),
        );
    }
    entries.sort();
    let include_dir = shader_dir.join("include");

    let mut failures = Vec::new();
    for path in entries {
        println!("cargo:rerun-if-changed={}", path.display());
        // Includes (*.glsl) are compiled as part of their users.
        if stage_of(&path).is_none() {
            continue;
        }
        let source = std::fs::read_to_string(&path).expect("read shader");
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let variants: Vec<(String, &[&str])> = match VARIANTS.iter().find(|(file, _)| *file == name)
        {
            Some((_, list)) => list
                .iter()
                .map(|(out_name, defines)| (out_name.to_string(), *defines))
                .collect(),
            None => vec![(name.clone(), &[])],
        };
        for (out_name, defines) in variants {
            let kind = stage_of(Path::new(&out_name)).expect("a variant names its stage");
            let options = compile_options(&include_dir, &out, defines);
            match compiler.compile_into_spirv(&source, kind, &name, "main", Some(&options)) {
                Ok(artifact) => {
                    if artifact.get_num_warnings() > 0 {
                        println!("cargo:warning={}", artifact.get_warning_messages());
                    }
                    let target = out.join(format!("{out_name}.spv"));
                    std::fs::write(&target, artifact.as_binary_u8()).expect("write SPIR-V");
                }
                Err(e) => failures.push(format!("{} ({out_name}):\n{e}", path.display())),
            }
        }
    }
    if !failures.is_empty() {
        for f in &failures {
            for line in f.lines() {
                println!("cargo:warning={line}");
            }
        }
        panic!("shader compilation failed:\n{}", failures.join("\n"));
    }
}

/// The stage of a shader named `path`, by its extension (`None`: an include).
fn stage_of(path: &Path) -> Option<shaderc::ShaderKind> {
    Some(match path.extension().and_then(|e| e.to_str())? {
        "vert" => shaderc::ShaderKind::Vertex,
        "frag" => shaderc::ShaderKind::Fragment,
        "comp" => shaderc::ShaderKind::Compute,
        "rgen" => shaderc::ShaderKind::RayGeneration,
        "rchit" => shaderc::ShaderKind::ClosestHit,
        "rahit" => shaderc::ShaderKind::AnyHit,
        "rmiss" => shaderc::ShaderKind::Miss,
        _ => return None,
    })
}

/// Vulkan 1.2 / SPIR-V 1.4, unoptimised, warnings as errors, includes from `shaders/include/` (and
/// the generated headers from `$OUT_DIR`), `defines` set.
///
/// The drivers optimise SPIR-V themselves; spirv-opt's inlining before them only makes the
/// module larger. Measured on lavapipe (docs/performance.md, "Shader compile"): the trace
/// pipeline's creation takes 2.4 to 3.1 s from unoptimised SPIR-V (333 KB) against 4.4 to 5.3 s
/// from spirv-opt's (591 KB), and traces as fast or faster.
fn compile_options<'a>(
    include_dir: &Path,
    out: &Path,
    defines: &[&str],
) -> shaderc::CompileOptions<'a> {
    let mut options = shaderc::CompileOptions::new().expect("shaderc options");
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_target_spirv(shaderc::SpirvVersion::V1_4);
    options.set_optimization_level(shaderc::OptimizationLevel::Zero);
    options.set_warnings_as_errors();
    for define in defines {
        options.add_macro_definition(define, None);
    }
    let include_dir = include_dir.to_path_buf();
    let generated_dir = out.to_path_buf();
    options.set_include_callback(move |requested, _kind, requester, _depth| {
        let dir = if is_generated(requested) {
            &generated_dir
        } else {
            &include_dir
        };
        resolve_include(dir, requested, requester)
    });
    options
}

/// Whether `requested` is a header this script writes (the interface, a set's bindings).
fn is_generated(requested: &str) -> bool {
    requested == INTERFACE_HEADER || (requested.starts_with("set_") && requested.ends_with(".glsl"))
}

fn resolve_include(
    dir: &Path,
    requested: &str,
    requester: &str,
) -> Result<shaderc::ResolvedInclude, String> {
    let path = dir.join(requested);
    // The generated headers are written by this script, after cargo noted its start: watching
    // them would make every build run the script again. Their source, lensray-interface, is a
    // dependency of the script.
    if !is_generated(requested) {
        println!("cargo:rerun-if-changed={}", path.display());
    }
    let content = std::fs::read_to_string(&path)
        .map_err(|e| format!("{requester}: cannot include {}: {e}", path.display()))?;
    Ok(shaderc::ResolvedInclude {
        resolved_name: requested.to_string(),
        content,
    })
}
