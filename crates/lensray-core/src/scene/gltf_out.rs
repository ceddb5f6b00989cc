//! Scenes as glTF 2.0: `NAME.gltf` (the document, built from `gltf-json`'s types) and `NAME.bin`
//! (per mesh: positions, normals, TEXCOORD_0 as `f32`, indices as `u32`, an index list per
//! material). Each mesh is one node; its triangles of one material are one primitive.
//! Materials: `baseColorFactor` and `baseColorTexture`, `metallicFactor` and `roughnessFactor`,
//! `KHR_materials_specular`'s `specularFactor` where it is not 1 (0: a Lambert surface),
//! `emissiveFactor`, `doubleSided` as the material is, with the scene's alpha mode. `write_scene_gltf` writes the meshes alone (a scene file adds camera and lights);
//! `textured::gltf_out` adds textures, a camera and lights.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{bail, Context};
use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;

use crate::scene::{AlphaMode, Material, Mesh, Scene};

/// The document and the binary buffer it describes.
pub(crate) struct Builder {
    pub root: json::Root,
    bin: Vec<u8>,
}

impl Builder {
    /// An empty document that names `lensray generate NAME` as its generator.
    pub(crate) fn new(name: &str) -> Self {
        Self {
            root: json::Root {
                asset: json::Asset {
                    generator: Some(format!("lensray generate {name}")),
                    ..Default::default()
                },
                ..Default::default()
            },
            bin: Vec::new(),
        }
    }

    /// Writes `NAME.bin` and then `NAME.gltf` into `dir`; returns their names.
    pub(crate) fn finish(mut self, dir: &Path, name: &str) -> anyhow::Result<Vec<String>> {
        let bin_name = format!("{name}.bin");
        self.root.push(json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            extensions: None,
            extras: Default::default(),
            name: None,
            uri: Some(bin_name.clone()),
        });
        let gltf_name = format!("{name}.gltf");
        let text = self
            .root
            .to_string_pretty()
            .context("cannot serialize the glTF document")?;
        std::fs::write(dir.join(&bin_name), &self.bin)
            .with_context(|| format!("cannot write {bin_name}"))?;
        std::fs::write(dir.join(&gltf_name), text)
            .with_context(|| format!("cannot write {gltf_name}"))?;
        Ok(vec![bin_name, gltf_name])
    }

    /// Appends `bytes` to the buffer as a view of its own and returns the view.
    fn view(&mut self, bytes: &[u8]) -> json::Index<json::buffer::View> {
        // Every element is 4 bytes, so every view starts aligned as glTF asks.
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: None,
        })
    }

    /// An accessor of `count` elements of `type_` and `component` over a new view of `bytes`.
    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        (type_, component): (json::accessor::Type, json::accessor::ComponentType),
        bounds: Option<([f32; 3], [f32; 3])>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(bytes);
        let (min, max) = match bounds {
            Some((min, max)) => (Some(shortest(min)), Some(shortest(max))),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// The mesh `mesh` as a glTF mesh: its vertex attributes once, a primitive (an index list)
    /// per material, in the order of the materials' numbers.
    pub(crate) fn mesh(&mut self, mesh: &Mesh) -> json::Index<json::Mesh> {
        use json::accessor::{ComponentType::F32, ComponentType::U32, Type};
        let floats =
            |values: Vec<f32>| -> Vec<u8> { values.iter().flat_map(|v| v.to_le_bytes()).collect() };
        let count = mesh.positions.len();
        let (min, max) = mesh.positions.iter().fold(
            (
                glam::Vec3::splat(f32::INFINITY),
                glam::Vec3::splat(f32::NEG_INFINITY),
            ),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let mut attributes = BTreeMap::new();
        let positions = floats(mesh.positions.iter().flat_map(|p| p.to_array()).collect());
        let bounds = Some((min.to_array(), max.to_array()));
        let position = self.accessor(&positions, count, (Type::Vec3, F32), bounds);
        attributes.insert(Valid(json::mesh::Semantic::Positions), position);
        if !mesh.normals.is_empty() {
            let normals = floats(mesh.normals.iter().flat_map(|n| n.to_array()).collect());
            let normal = self.accessor(&normals, count, (Type::Vec3, F32), None);
            attributes.insert(Valid(json::mesh::Semantic::Normals), normal);
        }
        if !mesh.texcoords.is_empty() {
            let texcoords = floats(mesh.texcoords.iter().flat_map(|t| t.to_array()).collect());
            let texcoord = self.accessor(&texcoords, count, (Type::Vec2, F32), None);
            attributes.insert(Valid(json::mesh::Semantic::TexCoords(0)), texcoord);
        }
        let mut by_material: BTreeMap<u32, Vec<u8>> = BTreeMap::new();
        for (triangle, &material) in mesh.triangles.iter().zip(&mesh.material_ids) {
            let indices = by_material.entry(material).or_default();
            indices.extend(triangle.iter().flat_map(|i| i.to_le_bytes()));
        }
        let primitives = by_material
            .into_iter()
            .map(|(material, indices)| {
                let count = indices.len() / 4;
                let indices = self.accessor(&indices, count, (Type::Scalar, U32), None);
                json::mesh::Primitive {
                    attributes: attributes.clone(),
                    extensions: None,
                    extras: Default::default(),
                    indices: Some(indices),
                    material: Some(json::Index::new(material)),
                    mode: Valid(json::mesh::Mode::Triangles),
                    targets: None,
                }
            })
            .collect();
        self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(mesh.name.clone()),
            primitives,
            weights: None,
        })
    }

    /// Every mesh of `scene` as a node of the document's one scene; returns the nodes.
    pub(crate) fn meshes(&mut self, scene: &Scene) -> Vec<json::Index<json::Node>> {
        let mut nodes = Vec::new();
        for mesh in &scene.meshes {
            let index = self.mesh(mesh);
            nodes.push(self.root.push(json::Node {
                mesh: Some(index),
                name: Some(mesh.name.clone()),
                ..Default::default()
            }));
        }
        nodes
    }

    /// The document's scene, of `nodes`, as the default one.
    pub(crate) fn scene(&mut self, name: &str, nodes: Vec<json::Index<json::Node>>) {
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: Some(name.into()),
            nodes,
        });
        self.root.scene = Some(scene);
    }
}

/// Writes the meshes and materials of untextured `scene` as `NAME.gltf` and `NAME.bin` into
/// `dir` (no camera, no lights: a scene file gives those); returns the files' names.
pub fn write_scene_gltf(scene: &Scene, dir: &Path, name: &str) -> anyhow::Result<Vec<String>> {
    let mut b = Builder::new(name);
    for m in &scene.materials {
        if m.diffuse_texture.is_some() || m.emission_texture.is_some() || m.alpha_texture.is_some()
        {
            bail!(
                "material {}: write a textured scene with its own writer",
                m.name
            );
        }
        if m.emission.max_element() > 1.0 {
            bail!(
                "material {}: its emission {} exceeds glTF's emissiveFactor range [0, 1]",
                m.name,
                m.emission
            );
        }
        push_material(&mut b.root, m);
    }
    let nodes = b.meshes(scene);
    b.scene(name, nodes);
    b.finish(dir, name)
}

/// `values` as a JSON array of the shortest decimals that read back to them as `f32` (a plain
/// conversion writes the `f64` digits of each `f32`: -0.05 as -0.05000000074505806).
fn shortest(values: [f32; 3]) -> json::Value {
    let decimal = |v: f32| v.to_string().parse::<f64>().unwrap_or(f64::from(v));
    json::Value::from(values.map(decimal).to_vec())
}

/// Adds the glTF material of `m` to `root`, and the extension it uses to `extensionsUsed`.
pub(crate) fn push_material(root: &mut json::Root, m: &Material) {
    let specular = "KHR_materials_specular";
    if m.specular != 1.0 && !root.extensions_used.iter().any(|e| e == specular) {
        root.extensions_used.push(specular.into());
    }
    root.push(material(m));
}

/// The glTF material of `m`, whose textures are the document's textures of the same index.
fn material(m: &Material) -> json::Material {
    let (alpha_mode, alpha_cutoff) = match m.alpha_mode {
        AlphaMode::Opaque => (json::material::AlphaMode::Opaque, None),
        AlphaMode::Mask { cutoff } => (
            json::material::AlphaMode::Mask,
            Some(json::material::AlphaCutoff(cutoff)),
        ),
        AlphaMode::Blend => (json::material::AlphaMode::Blend, None),
    };
    json::Material {
        name: Some(m.name.clone()),
        alpha_mode: Valid(alpha_mode),
        alpha_cutoff,
        double_sided: m.double_sided,
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor([
                m.diffuse.x,
                m.diffuse.y,
                m.diffuse.z,
                m.alpha,
            ]),
            base_color_texture: m.diffuse_texture.map(|t| json::texture::Info {
                index: json::Index::new(t.texture),
                tex_coord: 0,
                extensions: None,
                extras: Default::default(),
            }),
            metallic_factor: json::material::StrengthFactor(m.metallic),
            roughness_factor: json::material::StrengthFactor(m.roughness),
            ..Default::default()
        },
        emissive_factor: json::material::EmissiveFactor(m.emission.to_array()),
        extensions: (m.specular != 1.0).then(|| json::extensions::material::Material {
            specular: Some(json::extensions::material::Specular {
                specular_factor: json::extensions::material::SpecularFactor(m.specular),
                specular_texture: None,
                specular_color_factor: Default::default(),
                specular_color_texture: None,
                extras: Default::default(),
            }),
            ..Default::default()
        }),
        ..Default::default()
    }
}
