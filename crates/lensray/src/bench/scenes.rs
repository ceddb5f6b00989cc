//! The scenes a bench renders, and a fingerprint of each for the reference cache.

use anyhow::Result;

use super::options::{NamedScene, SceneChoice};
use lensray_core::scene::file::SceneDescription;
use lensray_core::scene::units::SceneUnits;
use lensray_core::scene::Scene;

/// A scene ready to bench: its description, a short name and its fingerprint.
pub struct BenchScene {
    pub description: SceneDescription,
    /// "default", "dense", "cornell", "terrain", the file's path, or "generated dense" for a sweep.
    pub name: String,
    pub triangles: usize,
    pub fingerprint: u64,
}

impl BenchScene {
    /// The scene lit as its settings say (`settings::light_scene`), as `render` lights it.
    pub fn new(mut description: SceneDescription, name: String) -> Result<Self> {
        lensray_core::settings::light_scene(&description.settings, &mut description.scene)?;
        Ok(Self {
            triangles: description.scene.triangle_count(),
            fingerprint: fingerprint(&description.scene),
            description,
            name,
        })
    }
}

/// The scene `choice` names, its lengths in `units` (default: a scene file's own, else metres)
/// scaled to metres. Generated scenes are built in memory (no files written).
pub fn load(
    choice: &SceneChoice,
    dense_triangles: usize,
    units: Option<SceneUnits>,
) -> Result<BenchScene> {
    let (description, name) = match choice {
        SceneChoice::File(path) => (
            lensray_core::scene::file::load_in(path, units)?,
            path.display().to_string(),
        ),
        SceneChoice::Named(named) => {
            let mut description = named_scene(*named, dense_triangles);
            description.set_units(units.unwrap_or_default());
            (description, named.name().into())
        }
    };
    BenchScene::new(description, name)
}

fn named_scene(named: NamedScene, dense_triangles: usize) -> SceneDescription {
    match named {
        NamedScene::Default => lensray_core::scene::builtin::default_scene(),
        NamedScene::Dense => lensray_core::scene::generate::dense(dense_triangles),
        NamedScene::Cornell => lensray_core::scene::generate::cornell_box(),
        NamedScene::Terrain => lensray_core::scene::terrain::terrain(),
    }
}

/// The generated dense scene of at least `triangles` triangles (the triangle sweep's scenes),
/// taken to be in `units`.
pub fn dense(triangles: usize, units: Option<SceneUnits>) -> Result<BenchScene> {
    let mut description = lensray_core::scene::generate::dense(triangles);
    description.set_units(units.unwrap_or_default());
    BenchScene::new(description, "generated dense".into())
}

/// A 64-bit FNV-1a-style hash over 32-bit words: stable across runs, platforms and Rust
/// versions (std's hasher promises none of that), fast enough for millions of triangles.
#[derive(Clone, Copy, Debug)]
pub struct Fingerprint(u64);

impl Default for Fingerprint {
    fn default() -> Self {
        Fingerprint(0xcbf2_9ce4_8422_2325)
    }
}

impl Fingerprint {
    pub fn word(&mut self, word: u32) {
        self.0 = (self.0 ^ u64::from(word)).wrapping_mul(0x0000_0100_0000_01b3);
    }

    pub fn words(&mut self, words: impl IntoIterator<Item = u32>) {
        for w in words {
            self.word(w);
        }
    }

    pub fn bytes(&mut self, bytes: &[u8]) {
        self.word(bytes.len() as u32);
        self.words(bytes.iter().map(|&b| u32::from(b)));
    }

    pub fn finish(self) -> u64 {
        // A final mix, so that the low bits (the file name) depend on every word.
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^ (h >> 33)
    }
}

/// Everything of a scene that changes its image: geometry, normals, texture coordinates,
/// materials, textures and lights. Materials and lights enter through their `Debug` text, which
/// names every field and prints floats exactly, so that no field can be forgotten.
pub fn fingerprint(scene: &Scene) -> u64 {
    let mut h = Fingerprint::default();
    let floats = |h: &mut Fingerprint, v: Vec<f32>| {
        h.word(v.len() as u32);
        h.words(v.into_iter().map(f32::to_bits));
    };
    h.word(scene.meshes.len() as u32);
    for mesh in &scene.meshes {
        floats(
            &mut h,
            mesh.positions.iter().flat_map(|p| p.to_array()).collect(),
        );
        floats(
            &mut h,
            mesh.normals.iter().flat_map(|n| n.to_array()).collect(),
        );
        floats(
            &mut h,
            mesh.texcoords.iter().flat_map(|t| t.to_array()).collect(),
        );
        if !mesh.texcoords1.is_empty() {
            // Only where there is a second set: the keys of scenes without one stay as they were.
            floats(
                &mut h,
                mesh.texcoords1.iter().flat_map(|t| t.to_array()).collect(),
            );
        }
        h.word(mesh.triangles.len() as u32);
        h.words(mesh.triangles.iter().flatten().copied());
        h.words(mesh.material_ids.iter().copied());
    }
    h.bytes(format!("{:?}", scene.materials).as_bytes());
    h.word(scene.textures.len() as u32);
    for texture in &scene.textures {
        h.bytes(format!("{:?} {:?}", texture.encoding, texture.levels).as_bytes());
        h.word(texture.texels.len() as u32);
        h.words(texture.texels.iter().copied());
    }
    h.bytes(format!("{:?}", scene.lights).as_bytes());
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingerprint_sees_every_change_to_the_image() {
        let scene = lensray_core::scene::test_card::test_card();
        let base = fingerprint(&scene);
        assert_eq!(base, fingerprint(&scene.clone()));
        type Change = (&'static str, fn(&mut Scene));
        let changes: [Change; 6] = [
            ("a moved vertex", |s| s.meshes[0].positions[0].x += 1e-6),
            ("a new colour", |s| s.materials[0].diffuse.y += 1e-6),
            ("a texture coordinate", |s| {
                let mesh = s
                    .meshes
                    .iter_mut()
                    .find(|m| !m.texcoords.is_empty())
                    .unwrap();
                mesh.texcoords[0].x += 1e-6;
            }),
            ("a texel", |s| s.textures[0].texels[0] ^= 1),
            ("an alpha cut-off", |s| s.materials[0].alpha += 1e-6),
            ("a light", |s| {
                s.lights.push(lensray_core::scene::light::Light::point(
                    glam::Vec3::ONE,
                    glam::Vec3::ONE,
                ));
            }),
        ];
        for (what, change) in changes {
            let mut changed = scene.clone();
            change(&mut changed);
            assert_ne!(base, fingerprint(&changed), "the fingerprint misses {what}");
        }
    }
}
