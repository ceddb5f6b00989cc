//! Scene files: TOML beside a mesh. The top-level key `mesh` names an OBJ or a glTF (`.gltf`,
//! `.glb`; relative to the scene file's folder, or absolute), `camera_name` one of the glTF's
//! cameras (by name or index; default: its first, if it has any), `units` the unit of length of
//! the mesh and of the file's own positions and distances ([`SceneUnits`]; default metres); the
//! sections `[camera]`, `[image]`, `[render]` and `[[light]]` (any number; one `[light]` table
//! reads as one) are those of [`Settings`], all optional; `[[keyframe]]`s move the camera over
//! a sequence's frames ([`Keyframes`]). Unknown keys are errors.
//!
//! ```toml
//! mesh = "cornell.obj"
//! # units = "mm"
//! [camera]
//! projection = "perspective"
//! eye = [0.0, 1.0, 3.6]
//! target = [0.0, 1.0, 0.0]
//! up = [0.0, 1.0, 0.0]
//! vfov_degrees = 40.0
//! aperture_radius = 0.06
//! focus_distance = 3.3
//! # Or a real lens instead of the thin one (f_number, focus_distance, sensor_height_mm):
//! # [camera.lens]
//! # prescription = "double-gauss-50"   # a built-in name, or a file beside this one
//! [image]
//! width = 640
//! height = 480
//! spp = 32
//! sampler = "sobol"
//! # fps = 24.0                      # a sequence's frames per second (glTF animation, video)
//! [render]
//! shading = "lit"
//! background = [0.0, 0.0, 0.0]
//! # environment = [0.2, 0.2, 0.2]   # a uniform sky lighting every surface, or a map:
//! # environment = "studio.hdr"       # equirectangular .hdr or .exr, beside this file
//! # environment_rotation = 90.0     # degrees, counter-clockwise seen from above
//! # environment_intensity = 1.0
//! # bounces = 1                     # surfaces a path shades; more add interreflection
//! [[light]]
//! position = [0.0, 1.9, 0.0]
//! intensity = [5.0, 5.0, 5.0]
//! [[light]]
//! type = "spot"                     # point (default), spot or directional
//! position = [1.0, 1.9, 1.0]
//! direction = [0.0, -1.0, 0.0]      # where the light travels (spot, directional)
//! intensity = [3.0, 3.0, 3.0]       # W/sr; W/m^2 for a directional light
//! inner_cone_degrees = 10.0
//! outer_cone_degrees = 25.0
//! [[keyframe]]
//! frame = 1
//! focus_distance = 1.5
//! interpolation = "smooth"          # linear (default), smooth or hold
//! [[keyframe]]
//! frame = 48
//! focus_distance = 4.0
//! ```

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::camera_animation::CameraAnimation;
use super::file_camera::{pick_camera, FileCamera};
use super::gltf_file::{load_gltf, MeshFile};
use super::motion::SceneMotion;
use super::obj::load_obj;
use super::units::SceneUnits;
use super::{LoadTimes, Scene, SceneError};
use crate::settings::{
    CameraSettings, EnvironmentSetting, ImageSettings, Keyframes, Lights, RenderStyle, Settings,
};

/// A scene with the settings that came with it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneDescription {
    pub scene: Scene,
    pub settings: Settings,
    /// Where it came from: the path given, or "built-in default" (or "generated ...").
    pub source: String,
    /// The mesh file's cameras; `settings` holds the one in use (see `camera`).
    pub cameras: Vec<FileCamera>,
    /// The index in `cameras` of the camera `settings` holds, if any.
    pub camera: Option<usize>,
    /// What the loader ignored or repaired, one line each (printed as warnings).
    pub notices: Vec<String>,
    /// The unit of length of the scene's files and of the world lengths given for it; `scene`,
    /// `settings` and `cameras` hold them converted to metres.
    pub units: SceneUnits,
    /// How long the mesh file's load took (zero for scenes made in memory).
    pub load_times: LoadTimes,
    /// The scene file's `[[keyframe]]`s, their lengths in metres like `settings`'.
    pub keyframes: Keyframes,
    /// The mesh file's animations that move no camera, as lines name them; a camera carries
    /// the one that moves it ([`FileCamera::animation`]).
    pub other_animations: Vec<String>,
    /// The meshes and lights the mesh file's animations move, if any: a sequence poses them
    /// on each frame, a still render shows them at rest.
    pub motion: Option<SceneMotion>,
}

impl SceneDescription {
    /// Uses the file's camera `choice` (a name or an index) in `settings`.
    pub fn use_camera(&mut self, choice: &str) -> Result<(), String> {
        let camera = pick_camera(&self.cameras, choice)?;
        camera.apply(&mut self.settings, &self.scene);
        self.camera = self.cameras.iter().position(|c| c == camera);
        Ok(())
    }

    /// Takes the lengths of this description to be in `units` instead of `self.units`: scales
    /// the scene, the file's cameras and the settings by the ratio, so the framing stays while
    /// the lens's physical blur follows the new size.
    pub fn set_units(&mut self, units: SceneUnits) {
        let factor = units.metres() / self.units.metres();
        if factor != 1.0 {
            self.scene.scale(factor);
            if let Some(motion) = &mut self.motion {
                motion.scale(factor);
            }
            for camera in &mut self.cameras {
                *camera = camera.scaled(factor);
            }
            self.settings = std::mem::take(&mut self.settings).scaled(factor);
            self.keyframes = std::mem::take(&mut self.keyframes).scaled(factor);
        }
        self.units = units;
    }

    /// The animation that moves the camera in use, if one does.
    pub fn camera_animation(&self) -> Option<&CameraAnimation> {
        self.cameras.get(self.camera?)?.animation.as_ref()
    }

    /// The camera in use, as "NAME (camera I of N in the file)", if it came from the file.
    pub fn camera_summary(&self) -> Option<String> {
        let i = self.camera?;
        Some(format!(
            "{} (camera {i} of {} in the file)",
            self.cameras[i].name,
            self.cameras.len()
        ))
    }

    /// The description of a mesh file read from `source` under `settings`, with its first
    /// camera (or the one `camera` names) in use.
    fn of_mesh(
        file: MeshFile,
        mut settings: Settings,
        source: String,
        camera: Option<&str>,
    ) -> Result<Self, String> {
        let mut description = SceneDescription {
            scene: file.scene,
            settings: Settings::default(),
            source,
            cameras: file.cameras,
            camera: None,
            notices: file.notices,
            units: SceneUnits::M,
            load_times: file.times,
            keyframes: Keyframes::default(),
            other_animations: file.other_animations,
            motion: file.motion,
        };
        match camera {
            Some(choice) => description.use_camera(choice)?,
            None if !description.cameras.is_empty() => description.use_camera("0")?,
            None => {}
        }
        // The scene file's own settings apply over the mesh file's camera.
        settings = std::mem::take(&mut description.settings).overridden_by(&settings);
        description.settings = settings;
        Ok(description)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    mesh: String,
    /// One of the glTF's cameras, by name or index.
    #[serde(default)]
    camera_name: Option<String>,
    /// Smooth normals, creased at this angle in degrees, for the meshes that have none.
    #[serde(default)]
    smooth_normals: Option<f64>,
    /// The unit of length of the mesh and of this file's positions and distances.
    #[serde(default)]
    units: Option<SceneUnits>,
    #[serde(default)]
    camera: CameraSettings,
    #[serde(default)]
    image: ImageSettings,
    #[serde(default)]
    render: RenderStyle,
    #[serde(default)]
    light: Lights,
    #[serde(default)]
    keyframe: Vec<toml::Table>,
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

/// What a scene file asks of its mesh besides the settings.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshOptions {
    /// The mesh file's camera to use, by name or index.
    pub camera: Option<String>,
    /// The crease angle (degrees) of smooth normals for meshes without normals.
    pub smooth_normals: Option<f64>,
    /// The unit of length of the mesh and of the file's positions and distances.
    pub units: Option<SceneUnits>,
    /// The `[[keyframe]]`s, their lengths as written.
    pub keyframes: Keyframes,
    /// What the user is told of the files the scene file names (`scene::reads`).
    pub notices: Vec<String>,
}

/// Parses a scene file's settings (its lengths as written, in its `units`) and resolves its
/// mesh path, without loading the mesh.
pub fn read_scene_file(path: &Path) -> Result<(PathBuf, Settings, MeshOptions), SceneError> {
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
        return Err(mesh_error("is empty: name an .obj, .gltf or .glb file"));
    }
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut notices = Vec::new();
    // Each file the scene file names, as `scene::reads` allows it.
    let mut named = |name: &Path| match super::reads::named_file(folder, name) {
        Ok(file) => {
            notices.extend(file.note.map(|n| format!("{}: {n}", path.display())));
            Ok(file.path)
        }
        Err(message) => Err(SceneError::Confined {
            by: path.to_path_buf(),
            message,
        }),
    };
    let mesh = named(Path::new(file.mesh.trim()))?;
    if !is_mesh_file(&mesh) {
        return Err(mesh_error("must be an .obj, .gltf or .glb file"));
    }
    let keyframes =
        Keyframes::parse(&file.keyframe, folder).map_err(|message| SceneError::Keyframe {
            path: path.to_path_buf(),
            message,
        })?;
    let mut camera = file.camera;
    if let Some(image) = camera.aperture.image.as_mut() {
        *image = named(image)?;
    }
    if let Some(lens) = camera.lens.prescription.as_mut() {
        // A built-in lens's name stays a name.
        if crate::optics::builtin::lens(lens).is_none() {
            *lens = named(Path::new(lens.as_str()))?
                .to_string_lossy()
                .into_owned();
        }
    }
    let mut render = file.render;
    if let Some(EnvironmentSetting::Map(map)) = render.environment.as_mut() {
        *map = named(map)?;
    }
    let settings = Settings {
        camera,
        image: file.image,
        render,
        light: file.light,
    };
    let options = MeshOptions {
        camera: file.camera_name,
        smooth_normals: file.smooth_normals,
        units: file.units,
        keyframes,
        notices,
    };
    Ok((mesh, settings, options))
}

/// Loads a scene file and the mesh it names, in the file's units.
pub fn load_scene_file(path: &Path) -> Result<SceneDescription, SceneError> {
    load_scene_file_in(path, None)
}

/// Loads a scene file and the mesh it names, its lengths in `units` (default: the file's
/// `units`, else metres) converted to metres.
fn load_scene_file_in(
    path: &Path,
    units: Option<SceneUnits>,
) -> Result<SceneDescription, SceneError> {
    let (mesh, settings, options) = read_scene_file(path)?;
    let mut file = load_mesh(&mesh).map_err(|err| SceneError::Mesh {
        scene: path.to_path_buf(),
        err: Box::new(err),
    })?;
    if let Some(crease) = options.smooth_normals {
        file.scene.smooth_normals(crease);
    }
    let source = path.display().to_string();
    let camera = options.camera.as_deref();
    let keyframes = options.keyframes.clone();
    let mut description =
        SceneDescription::of_mesh(file, settings, source, camera).map_err(|reason| {
            SceneError::CameraChoice {
                path: path.to_path_buf(),
                reason,
            }
        })?;
    description.keyframes = keyframes;
    description.notices.splice(0..0, options.notices);
    description.set_units(units.or(options.units).unwrap_or_default());
    Ok(description)
}

fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case(ext))
}

/// Whether `path` names a mesh file lensray reads (by its extension).
fn is_mesh_file(path: &Path) -> bool {
    ["obj", "gltf", "glb"]
        .iter()
        .any(|e| has_extension(path, e))
}

/// Reads a mesh file by its extension: OBJ, or glTF (`.gltf`, `.glb`).
fn load_mesh(path: &Path) -> Result<MeshFile, SceneError> {
    if has_extension(path, "obj") {
        load_obj(path)
    } else {
        load_gltf(path)
    }
}

/// Loads a scene by extension: `.toml` is a scene file; `.obj`, `.gltf` and `.glb` a mesh file
/// with default settings (a glTF's first camera, if it has one).
pub fn load(path: &Path) -> Result<SceneDescription, SceneError> {
    load_in(path, None)
}

/// [`load`], the scene's lengths in `units` (which wins over a scene file's `units`; default
/// metres) converted to metres.
pub fn load_in(path: &Path, units: Option<SceneUnits>) -> Result<SceneDescription, SceneError> {
    if has_extension(path, "toml") {
        load_scene_file_in(path, units)
    } else if is_mesh_file(path) {
        let file = load_mesh(path)?;
        let source = path.display().to_string();
        let mut description = SceneDescription::of_mesh(file, Settings::default(), source, None)
            .map_err(|reason| SceneError::CameraChoice {
                path: path.to_path_buf(),
                reason,
            })?;
        description.set_units(units.unwrap_or_default());
        Ok(description)
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

/// What a scene file holds, for writing: the mesh and the settings that are set.
#[derive(Serialize)]
struct SceneFileOut<'a> {
    mesh: &'a str,
    #[serde(skip_serializing_if = "CameraSettings::is_unset")]
    camera: &'a CameraSettings,
    #[serde(skip_serializing_if = "ImageSettings::is_unset")]
    image: &'a ImageSettings,
    #[serde(skip_serializing_if = "RenderStyle::is_unset")]
    render: &'a RenderStyle,
    #[serde(skip_serializing_if = "Lights::is_empty")]
    light: &'a Lights,
}

/// The text of a scene file naming `mesh` with `settings` (only the fields that are set), after
/// `comment` lines (each prefixed with `# `). [`load_scene_file`] reads it back to the same
/// settings.
pub fn scene_file_text(mesh: &str, settings: &Settings, comment: &str) -> String {
    let mut out = String::new();
    for line in comment.lines() {
        out += &format!("# {line}\n");
    }
    let file = SceneFileOut {
        mesh,
        camera: &settings.camera,
        image: &settings.image,
        render: &settings.render,
        light: &settings.light,
    };
    out += &toml::to_string(&file).expect("settings serialize to TOML");
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
