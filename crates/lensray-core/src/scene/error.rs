//! Everything that can go wrong while loading a scene. Each message is one line and names the
//! file (and the line in it, where known).

use std::path::{Path, PathBuf};

use thiserror::Error;

#[derive(Debug, Error)]
pub enum SceneError {
    /// The file could not be opened or read (missing, a directory, no permission, ...).
    #[error("cannot read {}: {err}", path.display())]
    Read { path: PathBuf, err: std::io::Error },

    /// The OBJ parser (tobj) rejected the file; tobj does not say where.
    #[error("{}: malformed OBJ: {reason}", path.display())]
    Obj { path: PathBuf, reason: String },

    /// A malformed OBJ statement found at a known line.
    #[error("{}:{line}: malformed OBJ: {reason}", path.display())]
    ObjLine {
        path: PathBuf,
        line: usize,
        reason: String,
    },

    /// A vertex position or normal that is NaN or infinite.
    #[error("{}:{line}: {what} is not finite: `{text}`", path.display())]
    NonFinite {
        path: PathBuf,
        line: usize,
        what: &'static str,
        text: String,
    },

    /// A face refers to a vertex, texture coordinate or normal that does not exist.
    #[error(
        "{}:{line}: {kind} index {index} is out of range (the file has {count} {kind}s; OBJ indices start at 1, negative ones count back)",
        path.display()
    )]
    IndexOutOfRange {
        path: PathBuf,
        line: usize,
        kind: &'static str,
        index: i64,
        count: usize,
    },

    /// A `mtllib` that could not be read.
    #[error("cannot read material library {} (mtllib of {}): {err}", mtl.display(), obj.display())]
    MtlRead {
        mtl: PathBuf,
        obj: PathBuf,
        err: std::io::Error,
    },

    /// The MTL parser (tobj) rejected a material library.
    #[error("{}: malformed MTL: {reason}", path.display())]
    Mtl { path: PathBuf, reason: String },

    /// A colour (`Kd`, `Ke`, `Ka`, `Ks`) that is not 1 or 3 finite numbers (non-negative for Kd/Ke).
    #[error(
        "{}:{line}: malformed {key} value `{value}`: expected 1 or 3 finite, non-negative numbers",
        path.display()
    )]
    Color {
        path: PathBuf,
        line: usize,
        key: String,
        value: String,
    },

    /// A mesh file without a single triangle.
    /// A texture file that exists but cannot be decoded.
    #[error("texture {} (of {}): {reason}", path.display(), of.display())]
    Texture {
        path: PathBuf,
        of: PathBuf,
        reason: String,
    },
    #[error("{} contains no triangles", path.display())]
    NoTriangles { path: PathBuf },

    /// TOML syntax or type error in a scene file.
    #[error("{}: {message}", location(path, *position))]
    Toml {
        path: PathBuf,
        /// 1-based line and column, when toml reports a position.
        position: Option<(usize, usize)>,
        message: String,
    },

    /// A scene file whose `mesh` key is unusable.
    #[error("{}: mesh `{mesh}`: {reason}", scene.display())]
    MeshPath {
        scene: PathBuf,
        mesh: String,
        reason: String,
    },

    /// The mesh a scene file refers to failed to load.
    #[error("{}: {err}", scene.display())]
    Mesh {
        scene: PathBuf,
        err: Box<SceneError>,
    },

    /// A `[[keyframe]]` that is out of order or has an unknown key or a bad value.
    #[error("{}: {message}", path.display())]
    Keyframe { path: PathBuf, message: String },

    /// A camera of the mesh file that cannot be used, or does not exist.
    #[error("{}: {reason}", path.display())]
    CameraChoice { path: PathBuf, reason: String },

    /// A glTF file that cannot be read as one (its JSON, a buffer, an accessor, an extension).
    #[error("{}: glTF: {reason}", path.display())]
    Gltf { path: PathBuf, reason: String },

    /// `load` was given a file that is neither a scene file nor a mesh.
    #[error(
        "{}: unsupported scene file extension `{ext}`: expected .toml (scene file), .gltf, .glb or .obj (a mesh)",
        path.display()
    )]
    Extension { path: PathBuf, ext: String },

    /// A file names another outside the assets root (`scene::reads`).
    #[error("{}: {message}", by.display())]
    Confined { by: PathBuf, message: String },
}

fn location(path: &Path, position: Option<(usize, usize)>) -> String {
    match position {
        Some((line, column)) => format!("{}:{line}:{column}", path.display()),
        None => path.display().to_string(),
    }
}

impl SceneError {
    /// The innermost error: for a scene file's mesh, the mesh's own error.
    pub fn root(&self) -> &SceneError {
        match self {
            SceneError::Mesh { err, .. } => err.root(),
            other => other,
        }
    }
}
