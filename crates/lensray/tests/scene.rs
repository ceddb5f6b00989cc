//! Scene loading, scene files, the built-in scene, the generators and the committed assets.
//!
//! Run with `cargo test --test scene`.

use std::fs;
use std::path::{Path, PathBuf};

use lensray_core::scene::builtin::default_scene;
use lensray_core::scene::generate::{cornell_box, dense, sphere_row};
use lensray_core::scene::{load, load_obj, Scene, SceneDescription, SceneError};

#[path = "scene/assets.rs"]
mod assets;
#[path = "scene/file.rs"]
mod file;
#[path = "scene/framing.rs"]
mod framing;
#[path = "scene/generators.rs"]
mod generators;
#[path = "scene/gltf.rs"]
mod gltf;
#[path = "scene/lights.rs"]
mod lights;
#[path = "scene/obj.rs"]
mod obj;
#[path = "scene/quantized.rs"]
mod quantized;
#[path = "scene/textures.rs"]
mod textures;
#[path = "scene/units.rs"]
mod units;
#[path = "scene/writing.rs"]
mod writing;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    if let Some(parent) = path.parent() {
        fs::create_dir_all(parent).unwrap();
    }
    fs::write(&path, text).unwrap();
    path
}

fn load_ok(path: &Path) -> Scene {
    load_obj(path)
        .unwrap_or_else(|e| panic!("{} should load, got: {e}", path.display()))
        .scene
}

/// Loads `path`, expects an error, checks that its message is one line naming `names_file`.
fn load_err(path: &Path, names_file: &str) -> SceneError {
    let err = match load(path) {
        Ok(d) => panic!(
            "{} should fail to load, got a scene of {} triangles",
            path.display(),
            d.scene.triangle_count()
        ),
        Err(e) => e,
    };
    let message = err.to_string();
    assert!(
        message.contains(names_file),
        "message should name {names_file}: {message}"
    );
    assert!(
        !message.contains('\n'),
        "message should be one line: {message:?}"
    );
    err
}

/// Every generated or built-in scene.
fn all_generated() -> Vec<(&'static str, SceneDescription)> {
    vec![
        ("default", default_scene()),
        ("cornell", cornell_box()),
        ("spheres", sphere_row()),
        ("dense", dense(30_000)),
    ]
}
