//! Scenes: triangle meshes with per-triangle materials, in world space.
//!
//! Meshes come from OBJ files (`obj`), which carry no transforms, so a mesh's positions are the
//! file's, or from glTF files (`gltf_file`), whose node transforms are applied on loading. Each
//! OBJ model or glTF primitive becomes one [`Mesh`] (one bottom-level acceleration structure on
//! the GPU). A glTF file's cameras come with it (`file_camera`).

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

pub mod builtin;
pub mod camera_animation;
pub mod emitters;
pub mod environment;
mod error;
pub mod file;
pub mod file_camera;
pub mod generate;
pub mod gltf_file;
pub mod gltf_out;
pub mod light;
pub mod load_times;
mod material;
pub mod motion;
pub mod normals;
pub mod obj;
pub mod order;
pub mod reads;
pub mod tangents;
pub mod terrain;
pub mod test_card;
pub mod texture;
pub mod textured;
pub mod units;

pub use builtin::default_scene;
pub use camera_animation::{CameraAnimation, CameraPose};
pub use environment::EnvironmentLight;
pub use error::SceneError;
pub use file::{load, load_scene_file, SceneDescription};
pub use file_camera::{pick_camera, FileCamera, FileProjection};
pub use gltf_file::{load_gltf, MeshFile};
pub use light::{Light, LightKind};
pub use load_times::LoadTimes;
pub use material::{blend_threshold, ray_key, AlphaMode, Material};
pub use material::{AOV_BLEND_THRESHOLD, BLEND_CAMERA_SALT, BLEND_SHADOW_SALT};
pub use obj::{load_obj, write_obj};
pub use texture::{Texture, TextureRef, TEXCOORD_SETS};

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Per-vertex normals, same length as `positions`, or empty when the OBJ has none.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates (glTF's TEXCOORD_0, OBJ's `vt`), same length as
    /// `positions`, or empty when the file has none (textures then read coordinate (0, 0)).
    pub texcoords: Vec<Vec2>,
    /// Per-vertex second texture coordinates (glTF's TEXCOORD_1), same length as `positions`,
    /// or empty when the file has none (textures that read this set then read (0, 0)); OBJ
    /// files carry one set.
    pub texcoords1: Vec<Vec2>,
    /// Per-vertex linear RGBA colours (glTF's COLOR_0), which multiply the base colour, same
    /// length as `positions`, or empty.
    pub colours: Vec<Vec4>,
    /// Per-vertex tangents (xyz, unit; w = +-1, the sign of the bitangent cross(normal,
    /// tangent) w), same length as `positions`, or empty: the frame of a normal map
    /// (glTF's TANGENT, or `tangents::generate`).
    pub tangents: Vec<Vec4>,
    pub triangles: Vec<[u32; 3]>,
    /// Index into `Scene::materials`, one per triangle.
    pub material_ids: Vec<u32>,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    /// What materials' [`TextureRef`]s index.
    pub textures: Vec<Texture>,
    /// The lights the `lit` shading sums: the file's (glTF `KHR_lights_punctual`) and, once a
    /// shot is lit (`settings::light_scene`), the settings' or the default one.
    pub lights: Vec<Light>,
    /// The environment map that lights the scene and is seen where rays leave it (the
    /// settings', once a shot is lit: `settings::light_scene`); none: the settings' uniform sky.
    pub environment: Option<Arc<EnvironmentLight>>,
}

/// Axis-aligned bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
    pub fn diagonal(&self) -> Vec3 {
        self.max - self.min
    }
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}

impl Scene {
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.triangles.len()).sum()
    }

    /// Bounds of all vertices that triangles use; `None` for an empty scene.
    pub fn bounds(&self) -> Option<Bounds> {
        let mut points = self.meshes.iter().flat_map(|m| {
            m.triangles
                .iter()
                .flatten()
                .map(|&i| m.positions[i as usize])
        });
        let first = points.next()?;
        let (min, max) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        Some(Bounds { min, max })
    }

    /// A sphere around every vertex that triangles use (centre, radius): centred on the bounds'
    /// centre, reaching the farthest vertex (a round model's is its own sphere, not its box's,
    /// which is up to 1.7 times larger); `None` for an empty scene.
    pub fn bounding_sphere(&self) -> Option<(Vec3, f32)> {
        let centre = self.bounds()?.center();
        let farthest = self
            .meshes
            .iter()
            .flat_map(|m| {
                m.triangles
                    .iter()
                    .flatten()
                    .map(|&i| m.positions[i as usize].distance_squared(centre))
            })
            .fold(0.0f32, f32::max);
        Some((centre, farthest.sqrt().max(1e-6)))
    }
}

impl Scene {
    /// Checks the invariants the renderers rely on: every index in range, one material id per
    /// triangle and each in range, normals, both texture coordinate sets, colours and tangents
    /// absent or one per position, positions finite.
    /// The error says which mesh and what.
    pub fn validate(&self) -> Result<(), String> {
        for (i, light) in self.lights.iter().enumerate() {
            light.check().map_err(|e| format!("light {i}: {e}"))?;
        }
        for mesh in &self.meshes {
            let name = &mesh.name;
            let n = mesh.positions.len();
            if mesh.material_ids.len() != mesh.triangles.len() {
                return Err(format!(
                    "mesh {name}: {} material ids for {} triangles",
                    mesh.material_ids.len(),
                    mesh.triangles.len()
                ));
            }
            if !mesh.normals.is_empty() && mesh.normals.len() != n {
                return Err(format!(
                    "mesh {name}: {} normals for {n} positions",
                    mesh.normals.len()
                ));
            }
            for (what, len) in [
                ("texture coordinates", mesh.texcoords.len()),
                ("second texture coordinates", mesh.texcoords1.len()),
                ("colours", mesh.colours.len()),
                ("tangents", mesh.tangents.len()),
            ] {
                if len != 0 && len != n {
                    return Err(format!("mesh {name}: {len} {what} for {n} positions"));
                }
            }
            if let Some((t, tri)) = mesh
                .triangles
                .iter()
                .enumerate()
                .find(|(_, tri)| tri.iter().any(|&i| i as usize >= n))
            {
                return Err(format!(
                    "mesh {name}: triangle {t} {tri:?} indexes past {n} positions"
                ));
            }
            if let Some((t, m)) = mesh
                .material_ids
                .iter()
                .enumerate()
                .find(|(_, &m)| m as usize >= self.materials.len())
            {
                return Err(format!(
                    "mesh {name}: triangle {t} has material {m} of {}",
                    self.materials.len()
                ));
            }
            if let Some(p) = mesh.positions.iter().find(|p| !p.is_finite()) {
                return Err(format!("mesh {name}: position {p} is not finite"));
            }
        }
        self.validate_textures()
    }

    /// Every material's textures exist, each reading a set a mesh may have.
    fn validate_textures(&self) -> Result<(), String> {
        for m in &self.materials {
            let refs = [
                &m.diffuse_texture,
                &m.emission_texture,
                &m.alpha_texture,
                &m.metallic_roughness_texture,
                &m.occlusion_texture,
                &m.normal_texture,
            ];
            if let Some(t) = refs.into_iter().flatten().find(|t| {
                t.texcoord_set as usize >= TEXCOORD_SETS
                    || self
                        .textures
                        .get(t.texture as usize)
                        .is_none_or(|texture| texture.levels.is_empty())
            }) {
                return Err(format!(
                    "material {}: texture {} of {} (texture coordinate set {})",
                    m.name,
                    t.texture,
                    self.textures.len(),
                    t.texcoord_set
                ));
            }
        }
        Ok(())
    }
}
