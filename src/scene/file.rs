//! Scene files: TOML beside an OBJ. The top-level key `mesh` names the OBJ (relative to the scene
//! file's folder, or absolute); the sections `[camera]`, `[image]`, `[render]` and `[light]` are
//! those of [`Settings`], all optional. Unknown keys are errors.
//!
//! ```toml
//! mesh = "cornell.obj"
//! [camera]
//! projection = "perspective"
//! eye = [0.0, 1.0, 3.6]
//! target = [0.0, 1.0, 0.0]
//! up = [0.0, 1.0, 0.0]
//! vfov_degrees = 40.0
//! aperture_radius = 0.06
//! focus_distance = 3.3
//! [image]
//! width = 640
//! height = 480
//! spp = 32
//! [render]
//! shading = "lit"
//! background = [0.0, 0.0, 0.0]
//! [light]
//! position = [0.0, 1.9, 0.0]
//! intensity = [5.0, 5.0, 5.0]
//! ```

use std::fmt::Write as _;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::obj::load_obj;
use super::{Scene, SceneError};
use crate::render::Shading;
use crate::settings::{
    CameraSettings, ImageSettings, LightSettings, ProjectionKind, RenderStyle, Settings,
};

/// A scene with the settings that came with it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDescription {
    pub scene: Scene,
    pub settings: Settings,
    /// Where it came from: the path given, or "built-in default" (or "generated ...").
    pub source: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    mesh: String,
    #[serde(default)]
    camera: CameraSettings,
    #[serde(default)]
    image: ImageSettings,
    #[serde(default)]
    render: RenderStyle,
    #[serde(default)]
    light: LightSettings,
}

/// 1-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = 1 + before.matches('\n').count();
    let column = 1 + before.rsplit('\n').next().unwrap_or("").chars().count();
    (line, column)
}

fn parse_scene_file(path: &Path, text: &str) -> Result<SceneFile, SceneError> {
    toml::from_str(text).map_err(|e: toml::de::Error| SceneError::Toml {
        path: path.to_path_buf(),
        position: e.span().map(|span| line_column(text, span.start)),
        message: e.message().trim().replace('\n', " "),
    })
}

/// Parses a scene file's settings and resolves its mesh path, without loading the mesh.
pub fn read_scene_file(path: &Path) -> Result<(PathBuf, Settings), SceneError> {
    let text = fs::read_to_string(path).map_err(|err| SceneError::Read {
        path: path.to_path_buf(),
        err,
    })?;
    let file = parse_scene_file(path, &text)?;
    let mesh_error = |reason: &str| SceneError::MeshPath {
        scene: path.to_path_buf(),
        mesh: file.mesh.clone(),
        reason: reason.into(),
    };
    if file.mesh.trim().is_empty() {
        return Err(mesh_error("is empty: name an .obj file"));
    }
    let mesh = path
        .parent()
        .unwrap_or(Path::new(""))
        .join(file.mesh.trim());
    if !has_extension(&mesh, "obj") {
        return Err(mesh_error("must be an .obj file"));
    }
    let settings = Settings {
        camera: file.camera,
        image: file.image,
        render: file.render,
        light: file.light,
    };
    Ok((mesh, settings))
}

/// Loads a scene file and the OBJ it names.
pub fn load_scene_file(path: &Path) -> Result<SceneDescription, SceneError> {
    let (mesh, settings) = read_scene_file(path)?;
    let scene = load_obj(&mesh).map_err(|err| SceneError::Mesh {
        scene: path.to_path_buf(),
        err: Box::new(err),
    })?;
    Ok(SceneDescription {
        scene,
        settings,
        source: path.display().to_string(),
    })
}

fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case(ext))
}

/// Loads a scene by extension: `.toml` is a scene file, `.obj` a bare mesh with default settings.
pub fn load(path: &Path) -> Result<SceneDescription, SceneError> {
    if has_extension(path, "toml") {
        load_scene_file(path)
    } else if has_extension(path, "obj") {
        Ok(SceneDescription {
            scene: load_obj(path)?,
            settings: Settings::default(),
            source: path.display().to_string(),
        })
    } else {
        Err(SceneError::Extension {
            path: path.to_path_buf(),
            ext: path
                .extension()
                .map(|e| format!(".{}", e.to_string_lossy()))
                .unwrap_or_default(),
        })
    }
}

fn float(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        // Debug prints the shortest form that reads back exactly, always with a `.` or exponent.
        format!("{x:?}")
    }
}

fn triple(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", float(v[0]), float(v[1]), float(v[2]))
}

fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn projection_name(p: ProjectionKind) -> &'static str {
    match p {
        ProjectionKind::Perspective => "perspective",
        ProjectionKind::Orthographic => "orthographic",
    }
}

fn shading_name(s: Shading) -> &'static str {
    match s {
        Shading::Unlit => "unlit",
        Shading::Lit => "lit",
        Shading::Depth => "depth",
        Shading::Normal => "normal",
        Shading::Albedo => "albedo",
    }
}

/// The text of a scene file naming `mesh` with `settings` (only the fields that are set), after
/// `comment` lines (each prefixed with `# `). [`load_scene_file`] reads it back to the same
/// settings.
pub fn scene_file_text(mesh: &str, settings: &Settings, comment: &str) -> String {
    let mut out = String::new();
    for line in comment.lines() {
        let _ = writeln!(out, "# {line}");
    }
    let _ = writeln!(out, "mesh = {}", toml_string(mesh));
    let mut section = |name: &str, fields: Vec<(&str, Option<String>)>| {
        let set: Vec<_> = fields
            .into_iter()
            .filter_map(|(k, v)| v.map(|v| (k, v)))
            .collect();
        if !set.is_empty() {
            let _ = writeln!(out, "\n[{name}]");
            for (k, v) in set {
                let _ = writeln!(out, "{k} = {v}");
            }
        }
    };
    // Destructured field by field so that a new setting fails to compile here until written.
    let Settings {
        camera,
        image,
        render,
        light,
    } = settings;
    let CameraSettings {
        projection,
        eye,
        target,
        up,
        vfov_degrees,
        ortho_height,
        aperture_radius,
        focus_distance,
        focal_length_mm,
        f_number,
        sensor_height_mm,
        near,
        far,
    } = camera;
    section(
        "camera",
        vec![
            (
                "projection",
                projection.map(|p| toml_string(projection_name(p))),
            ),
            ("eye", eye.map(triple)),
            ("target", target.map(triple)),
            ("up", up.map(triple)),
            ("vfov_degrees", vfov_degrees.map(float)),
            ("ortho_height", ortho_height.map(float)),
            ("aperture_radius", aperture_radius.map(float)),
            ("focus_distance", focus_distance.map(float)),
            ("focal_length_mm", focal_length_mm.map(float)),
            ("f_number", f_number.map(float)),
            ("sensor_height_mm", sensor_height_mm.map(float)),
            ("near", near.map(float)),
            ("far", far.map(float)),
        ],
    );
    let ImageSettings {
        width,
        height,
        spp,
        seed,
    } = image;
    let int = |v: &Option<u32>| v.map(|v| v.to_string());
    section(
        "image",
        vec![
            ("width", int(width)),
            ("height", int(height)),
            ("spp", int(spp)),
            ("seed", int(seed)),
        ],
    );
    let RenderStyle {
        shading,
        background,
    } = render;
    section(
        "render",
        vec![
            ("shading", shading.map(|s| toml_string(shading_name(s)))),
            ("background", background.map(triple)),
        ],
    );
    let LightSettings {
        position,
        intensity,
    } = light;
    section(
        "light",
        vec![
            ("position", position.map(triple)),
            ("intensity", intensity.map(triple)),
        ],
    );
    out
}

/// Writes [`scene_file_text`] to `path`.
pub fn write_scene_file(
    path: &Path,
    mesh: &str,
    settings: &Settings,
    comment: &str,
) -> io::Result<()> {
    fs::write(path, scene_file_text(mesh, settings, comment))
}
