//! The converged reference each path's error is measured against: the CPU reference renderer
//! at many samples per pixel with another seed than the paths', so their errors are not
//! correlated with its own. Rendered once and cached on disk under a key that covers all that
//! changes the image (scene, camera, render settings, samples, seed, lensray's version).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{ensure, Result};
use glam::Vec3;
use serde::Serialize;

use super::scenes::{BenchScene, Fingerprint};
use crate::paths::CpuPath;
use crate::paths::RenderPath;
use lensray_core::camera::Camera;
use lensray_core::film::compare::rmse;
use lensray_core::film::{Accumulation, Image};
use lensray_core::settings::{RenderSettings, Shot};

/// Bumped when the file layout or the meaning of the key changes.
const FORMAT: &[u8; 8] = b"LRREF001";
const HEADER_BYTES: usize = 8 + 4 * 4 + 8;

/// The reference's seed for paths rendering with `seed`: different, deterministic.
pub fn reference_seed(seed: u32) -> u32 {
    seed ^ 0x5bd1_e995
}

pub struct Reference {
    pub image: Image,
    pub info: ReferenceInfo,
}

/// What the bench reports about a reference.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceInfo {
    pub spp: u32,
    pub seed: u32,
    /// Read from the cache rather than rendered by this run.
    pub cached: bool,
    /// The cache file (`None` when caching is off).
    pub file: Option<PathBuf>,
    /// Its own error, estimated as half the RMSE between the images of its two halves of
    /// samples (exact for independent halves; an upper bound for stratified samplers).
    pub noise_rmse: f64,
    /// Seconds it took to render (when it was rendered by this run).
    pub render_seconds: Option<f64>,
}

/// The reference of `scene` rendering `shot` (its `spp` and `seed` replaced), from `cache_dir`
/// when there, else rendered and stored there. A cache that cannot be written costs a notice,
/// not the run.
pub fn obtain(
    cache_dir: Option<&Path>,
    scene: &BenchScene,
    shot: &Shot,
    spp: u32,
    log: &mut dyn FnMut(&str),
) -> Result<Reference> {
    ensure!(spp >= 2, "--reference-spp must be at least 2");
    let shot = Shot {
        camera: shot.camera.clone(),
        // Uniform: what adaptive renders are measured against converges everywhere.
        render: RenderSettings {
            spp,
            seed: reference_seed(shot.render.seed),
            noise_threshold: None,
            ..shot.render
        },
    };
    let (camera, settings) = (&shot.camera, &shot.render);
    let file = cache_dir.map(|dir| dir.join(format!("{:016x}.ref", key(scene, &shot))));
    if let Some(file) = &file {
        if let Some((image, noise_rmse)) = read(file, camera) {
            return Ok(Reference {
                image,
                info: ReferenceInfo {
                    spp,
                    seed: settings.seed,
                    cached: true,
                    file: Some(file.clone()),
                    noise_rmse,
                    render_seconds: None,
                },
            });
        }
    }
    log(&format!(
        "reference: rendering {}x{} at {spp} spp on the CPU (once: then cached)",
        camera.width, camera.height
    ));
    let start = Instant::now();
    let (image, noise_rmse) = render(scene, &shot)?;
    let render_seconds = start.elapsed().as_secs_f64();
    let mut stored = None;
    if let Some(file) = file {
        match write(&file, &image, settings, noise_rmse) {
            Ok(()) => stored = Some(file),
            Err(error) => log(&format!(
                "notice: the reference is not cached: cannot write {}: {error}",
                file.display()
            )),
        }
    }
    Ok(Reference {
        image,
        info: ReferenceInfo {
            spp,
            seed: settings.seed,
            cached: false,
            file: stored,
            noise_rmse,
            render_seconds: Some(render_seconds),
        },
    })
}

/// The cache key of `shot`. Its camera and settings enter through their `Debug` text, each
/// apart, which names every field and prints floats exactly (shortest round trip), so no field
/// can be forgotten.
fn key(scene: &BenchScene, shot: &Shot) -> u64 {
    let (camera, settings) = (&shot.camera, &shot.render);
    let mut h = Fingerprint::default();
    h.bytes(FORMAT);
    h.bytes(env!("CARGO_PKG_VERSION").as_bytes());
    h.words([scene.fingerprint as u32, (scene.fingerprint >> 32) as u32]);
    h.bytes(format!("{camera:?}").as_bytes());
    h.bytes(format!("{settings:?}").as_bytes());
    h.finish()
}

/// Renders the two halves of the samples of `shot` apart (any split gives the same sums), so
/// that the reference's own noise comes for free.
fn render(scene: &BenchScene, shot: &Shot) -> Result<(Image, f64)> {
    let (camera, settings) = (&shot.camera, &shot.render);
    let mut path = CpuPath::new();
    path.load_scene(&scene.description.scene)?;
    if settings.shading.is_aov() {
        // One deterministic ray per pixel centre: the reference is exact, without noise.
        return Ok((path.aov(shot)?, 0.0));
    }
    let half = settings.spp / 2;
    let mut halves = [
        Accumulation::new(camera.width, camera.height),
        Accumulation::new(camera.width, camera.height),
    ];
    for (accumulation, samples) in halves.iter_mut().zip([0..half, half..settings.spp]) {
        path.add_samples(shot, samples, accumulation, &mut |_, _| {})?;
    }
    let [first, second] = halves.each_ref().map(|h| h.host());
    let (mut whole, second) = (first?.clone(), second?);
    let noise_rmse = 0.5 * rmse(&whole.image(), &second.image());
    whole.add(second);
    Ok((whole.image(), noise_rmse))
}

/// The cached image, or `None` when the file is missing, of another size or damaged.
fn read(file: &Path, camera: &Camera) -> Option<(Image, f64)> {
    let bytes = std::fs::read(file).ok()?;
    let (header, body) = bytes.split_at_checked(HEADER_BYTES)?;
    let word = |i: usize| u32::from_le_bytes(header[8 + 4 * i..12 + 4 * i].try_into().unwrap());
    let (width, height) = (word(0), word(1));
    let pixels = width as usize * height as usize;
    if &header[..8] != FORMAT
        || (width, height) != (camera.width, camera.height)
        || body.len() != pixels * 12
    {
        return None;
    }
    let noise_rmse = f64::from_le_bytes(header[24..32].try_into().unwrap());
    let floats: Vec<f32> = body
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let pixels = floats.chunks_exact(3).map(Vec3::from_slice).collect();
    Some((
        Image {
            width,
            height,
            pixels,
        },
        noise_rmse,
    ))
}

/// Writes the file atomically (a temporary file renamed into place), so a run interrupted
/// while writing never leaves a damaged reference behind.
fn write(file: &Path, image: &Image, settings: &RenderSettings, noise_rmse: f64) -> Result<()> {
    let dir = file.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let mut bytes = Vec::with_capacity(HEADER_BYTES + image.pixels.len() * 12);
    bytes.extend_from_slice(FORMAT);
    for word in [image.width, image.height, settings.spp, settings.seed] {
        bytes.extend_from_slice(&word.to_le_bytes());
    }
    bytes.extend_from_slice(&noise_rmse.to_le_bytes());
    for p in &image.pixels {
        for c in p.to_array() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    let mut temp = tempfile::Builder::new()
        .prefix(".lensray-reference-")
        .tempfile_in(dir)?;
    temp.write_all(&bytes)?;
    temp.persist(file)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reference_is_rendered_once_then_read_back_exactly() {
        let description = lensray_core::scene::builtin::default_scene();
        let scene = BenchScene::new(description, "default".into()).unwrap();
        let mut settings = scene.description.settings.clone();
        settings.image.width = Some(12);
        settings.image.height = Some(8);
        let resolved = lensray_core::settings::shot(&settings, &scene.description.scene).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let reference =
            |spp| obtain(Some(dir.path()), &scene, &resolved, spp, &mut |_| {}).unwrap();
        let first = reference(4);
        assert!(!first.info.cached && first.info.file.is_some());
        assert!(first.info.noise_rmse > 0.0 && first.info.noise_rmse.is_finite());
        let second = reference(4);
        assert!(second.info.cached);
        assert_eq!(second.image, first.image);
        assert_eq!(second.info.noise_rmse, first.info.noise_rmse);
        // Another sample count is another reference.
        let other = reference(8);
        assert!(!other.info.cached);
    }
}
