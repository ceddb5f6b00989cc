//! What each fuzz target runs on one input, through the entry points the command line calls:
//! an input read as a bundle of files written to a folder of their own, the file loaded, and
//! the steps `lensray render` takes on a loaded scene. lensray-core's test
//! `fuzz_regressions` includes this file, so every checked-in input runs under `cargo test` on
//! the stable toolchain too.
//!
//! A bundle is the main file's bytes, then any number of further files, each after a line
//! `=== NAME` (see [`parts`]); the main file names the others (a glTF's buffers and images, an
//! OBJ's MTL library and textures, a scene file's mesh, lens, environment and aperture image),
//! so one input reaches every file a load reads.

use std::fs;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, UNIX_EPOCH};

use lensray_core::optics::analysis::LensData;
use lensray_core::scene::file::SceneDescription;
use lensray_core::scene::load_times::LoadTimes;
use lensray_core::scene::texture::{coverage_from_image, decode_texture, Encoding};
use lensray_core::settings::environment::load_environment;
use lensray_core::settings::{
    exposure, fps, light_scene, shot, CameraTimeline, EnvironmentSetting, Settings,
};

/// What a target runs on one input.
pub type Target = fn(&[u8]);

/// Each target's name (its folder under fuzz/corpus and fuzz/regressions) and what it runs.
pub const TARGETS: [(&str, Target); 6] = [
    ("gltf", gltf),
    ("obj", obj),
    ("scene", scene),
    ("lens", lens),
    ("environment", environment),
    ("image", image),
];

/// OpenEXR's first bytes.
const EXR_MAGIC: &[u8] = &[0x76, 0x2f, 0x31, 0x01];

/// A glTF scene as `lensray render scene.gltf` (or `.glb`) loads it: the document, its buffers
/// (data URIs, files, the GLB's binary chunk), accessors, nodes, cameras, animations and
/// textures, then the shot.
pub fn gltf(data: &[u8]) {
    let main = name_by_magic(data, b"glTF", "scene.glb", "scene.gltf");
    load_scene(&write_bundle(data, main));
}

/// An OBJ scene as `lensray render scene.obj` loads it: the OBJ, its MTL libraries and their
/// textures, then the shot.
pub fn obj(data: &[u8]) {
    load_scene(&write_bundle(data, "scene.obj"));
}

/// A scene file as `lensray render scene.toml` loads it: the TOML with its `[[keyframe]]`s,
/// the mesh it names and the files its settings name (lens prescription, environment map,
/// aperture image), then the shot and the keyframes' frames.
pub fn scene(data: &[u8]) {
    load_scene(&write_bundle(data, "scene.toml"));
}

fn load_scene(path: &Path) {
    match lensray_core::scene::file::load_in(path, None) {
        Ok(description) => prepare(description),
        Err(e) => say(&e),
    }
}

/// Prints why an input was refused where `LENSRAY_FUZZ_SAY` is set (to see what a seed
/// reaches: `LENSRAY_FUZZ_SAY=1 fuzz/target/.../gltf -runs=0 fuzz/corpus/gltf`).
fn say(refused: &dyn std::fmt::Display) {
    if std::env::var_os("LENSRAY_FUZZ_SAY").is_some() {
        eprintln!("refused: {refused}");
    }
}

/// A lens prescription as `lensray lens FILE` reads it: the rows, the checks, and the
/// first-order, real-ray and colour data.
pub fn lens(data: &[u8]) {
    let path = write_bundle(data, "lens.dat");
    match lensray_core::optics::builtin::resolve(&path.to_string_lossy()) {
        Ok(lens) => {
            let _ = lens.dispersion_notice();
            let _ = LensData::of(&lens);
        }
        Err(e) => say(&e),
    }
}

/// An environment map as a scene's `environment = "FILE"` loads it: Radiance HDR or OpenEXR
/// (by the file's first bytes), mended, turned and made into a light to sample.
pub fn environment(data: &[u8]) {
    let main = name_by_magic(data, EXR_MAGIC, "sky.exr", "sky.hdr");
    let mut settings = Settings::default();
    settings.render.environment = Some(EnvironmentSetting::Map(write_bundle(data, main)));
    if let Err(e) = load_environment(&settings) {
        say(&e);
    }
}

/// An image file as lensray reads textures (a glTF's or an MTL's: colour, data and coverage,
/// decoded and mip-mapped) and aperture images (PNG or EXR, by the file's first bytes).
pub fn image(data: &[u8]) {
    let mut times = LoadTimes::default();
    match decode_texture("fuzz", data, Encoding::Srgb, &mut times) {
        Ok(_) => drop(coverage_from_image("fuzz", data, &mut times)),
        Err(e) => say(&e),
    }
    let main = name_by_magic(data, EXR_MAGIC, "aperture.exr", "aperture.png");
    if let Err(e) = lensray_core::settings::aperture_image::load(&write_bundle(data, main)) {
        say(&e);
    }
}

/// What starts a further file in a bundle: a line `=== NAME`.
pub const SEPARATOR: &[u8] = b"\n=== ";

/// The main file's bytes and the further files (name, bytes) of bundle `data`. A name that
/// could leave the folder (absolute, `..`, empty, odd characters) drops its file.
pub fn parts(data: &[u8]) -> (&[u8], Vec<(PathBuf, &[u8])>) {
    let mut chunks = split(data, SEPARATOR).into_iter();
    let main = chunks.next().unwrap_or_default();
    let files = chunks
        .filter_map(|chunk| {
            let end = chunk
                .iter()
                .position(|&b| b == b'\n')
                .unwrap_or(chunk.len());
            let name = safe_name(&chunk[..end])?;
            Some((name, chunk.get(end + 1..).unwrap_or_default()))
        })
        .collect();
    (main, files)
}

fn split<'a>(data: &'a [u8], separator: &[u8]) -> Vec<&'a [u8]> {
    let mut chunks = Vec::new();
    let mut rest = data;
    while let Some(at) = rest.windows(separator.len()).position(|w| w == separator) {
        chunks.push(&rest[..at]);
        rest = &rest[at + separator.len()..];
    }
    chunks.push(rest);
    chunks
}

/// `name` as a relative path inside the folder, or `None`.
fn safe_name(name: &[u8]) -> Option<PathBuf> {
    let name = std::str::from_utf8(name).ok()?.trim();
    let allowed = |c: char| c.is_ascii_alphanumeric() || "._-/ ".contains(c);
    if name.is_empty() || name.len() > 128 || !name.chars().all(allowed) {
        return None;
    }
    let path = PathBuf::from(name);
    path.components()
        .all(|c| matches!(c, Component::Normal(_)))
        .then_some(path)
}

/// The process's folder for a fuzz input's files: under `LENSRAY_FUZZ_DIR` (scripts/fuzz.sh
/// makes one and removes it after), else on tmpfs where there is one. Scenes' reads are
/// confined to it (`--assets-root`), so an input naming `/dev/zero` or another file of the
/// machine reads nothing outside.
fn folder() -> &'static Path {
    static FOLDER: OnceLock<PathBuf> = OnceLock::new();
    FOLDER.get_or_init(|| {
        let shm = Path::new("/dev/shm");
        let base = match std::env::var_os("LENSRAY_FUZZ_DIR") {
            Some(dir) => PathBuf::from(dir),
            None if shm.is_dir() => shm.to_path_buf(),
            None => std::env::temp_dir(),
        };
        let folder = base.join(format!("lensray-fuzz-{}", std::process::id()));
        fs::create_dir_all(&folder).expect("the fuzz folder is made");
        lensray_core::scene::reads::confine_reads_to(&folder).expect("the fuzz folder confines");
        folder
    })
}

/// Writes bundle `data` into the process's emptied folder, its main file as `main`, and
/// returns the main file's path. Each file gets a modification time of its own, so a loader's
/// cache by path and time (aperture images) reads every input afresh.
pub fn write_bundle(data: &[u8], main: &str) -> PathBuf {
    static WRITES: AtomicU64 = AtomicU64::new(1);
    let folder = folder();
    for entry in fs::read_dir(folder)
        .expect("the fuzz folder reads")
        .flatten()
    {
        let path = entry.path();
        let _ = if path.is_dir() {
            fs::remove_dir_all(&path)
        } else {
            fs::remove_file(&path)
        };
    }
    let (main_bytes, files) = parts(data);
    let main_path = folder.join(main);
    let all = files
        .into_iter()
        .map(|(name, bytes)| (folder.join(name), bytes))
        .chain([(main_path.clone(), main_bytes)]);
    for (path, bytes) in all {
        // A file that cannot be written (its name is also a folder's, `a` and `a/b`) is left
        // out: the load then finds it missing.
        let _ = write_file(&path, bytes, WRITES.fetch_add(1, Ordering::Relaxed));
    }
    main_path
}

fn write_file(path: &Path, bytes: &[u8], seconds: u64) -> std::io::Result<()> {
    if let Some(parent) = path.parent() {
        fs::create_dir_all(parent)?;
    }
    fs::write(path, bytes)?;
    fs::File::options()
        .write(true)
        .open(path)?
        .set_modified(UNIX_EPOCH + Duration::from_secs(seconds))
}

/// The main file's name for `data`: `binary` where its bytes start with `magic`, else `text`.
fn name_by_magic<'a>(data: &[u8], magic: &[u8], binary: &'a str, text: &'a str) -> &'a str {
    if data.starts_with(magic) {
        binary
    } else {
        text
    }
}

/// What `lensray render` does with a loaded scene before it opens a device, and what a
/// sequence (`--frames`) adds: the shot and its exposure, the lights and environment, and the
/// shots of the first, middle and last frames of the keyframes and the camera animation.
fn prepare(mut description: SceneDescription) {
    let settings = description.settings.clone();
    match shot(&settings, &description.scene) {
        Ok(resolved) => drop(exposure(&settings, &resolved.camera)),
        Err(e) => say(&e),
    }
    if let Err(e) = light_scene(&settings, &mut description.scene) {
        say(&e);
    }
    let mut keyframes = std::mem::take(&mut description.keyframes);
    if let (Some(animation), Ok(rate)) = (description.camera_animation(), fps(&settings)) {
        let timeline = CameraTimeline::new(animation.clone(), rate);
        keyframes = keyframes.with_camera_timeline(timeline).0;
    }
    if let Some((first, last)) = keyframes.range() {
        let middle = first + (last - first) / 2;
        for frame in [first, middle, last] {
            let at: Settings = keyframes.settings_at(&settings, frame);
            let _ = shot(&at, &description.scene);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bundle_splits_into_named_files() {
        let data = b"main\n=== a.bin\nAB\n=== ../x\nno\n=== t/b.png\n";
        let (main, files) = parts(data);
        assert_eq!(main, b"main");
        assert_eq!(
            files,
            vec![
                (PathBuf::from("a.bin"), &b"AB"[..]),
                (PathBuf::from("t/b.png"), &b""[..])
            ]
        );
    }
}
