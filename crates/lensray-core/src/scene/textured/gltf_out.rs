//! The textured scene as glTF 2.0: `NAME.gltf` (the document, built from `gltf-json`'s types)
//! and `NAME.bin` (per mesh: positions, normals, TEXCOORD_0 as `f32`, indices as `u32`). Each
//! mesh is one node of one primitive; the camera is a node of its own, a perspective camera
//! without `zfar`. Materials: `baseColorFactor` and `baseColorTexture`, not metallic and fully
//! rough (the matte surface lensray's Lambert shading draws), double-sided, with the scene's
//! alpha mode. Every texture samples with REPEAT, as MTL's maps do.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{bail, Context};
use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;

use super::TexturedScene;
use crate::scene::{AlphaMode, Material, Mesh};

/// The document and the binary buffer it describes.
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
}

impl Builder {
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

    /// The mesh `mesh` (all of one material) as a glTF mesh of one primitive.
    fn mesh(&mut self, mesh: &Mesh) -> anyhow::Result<json::Index<json::Mesh>> {
        use json::accessor::{ComponentType::F32, ComponentType::U32, Type};
        let material = mesh.material_ids.first().copied().unwrap_or(0);
        if mesh.material_ids.iter().any(|&m| m != material) {
            bail!("mesh {} has more than one material", mesh.name);
        }
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
        let positions = floats(mesh.positions.iter().flat_map(|p| p.to_array()).collect());
        let normals = floats(mesh.normals.iter().flat_map(|n| n.to_array()).collect());
        let texcoords = floats(mesh.texcoords.iter().flat_map(|t| t.to_array()).collect());
        let indices: Vec<u8> = mesh
            .triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let mut attributes = BTreeMap::new();
        let position = self.accessor(
            &positions,
            count,
            (Type::Vec3, F32),
            Some((min.to_array(), max.to_array())),
        );
        attributes.insert(Valid(json::mesh::Semantic::Positions), position);
        let normal = self.accessor(&normals, count, (Type::Vec3, F32), None);
        attributes.insert(Valid(json::mesh::Semantic::Normals), normal);
        let texcoord = self.accessor(&texcoords, count, (Type::Vec2, F32), None);
        attributes.insert(Valid(json::mesh::Semantic::TexCoords(0)), texcoord);
        let indices = self.accessor(
            &indices,
            3 * mesh.triangles.len(),
            (Type::Scalar, U32),
            None,
        );
        Ok(self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(mesh.name.clone()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(indices),
                material: Some(json::Index::new(material)),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        }))
    }
}

/// `values` as a JSON array of the shortest decimals that read back to them as `f32` (a plain
/// conversion writes the `f64` digits of each `f32`: -0.05 as -0.05000000074505806).
fn shortest(values: [f32; 3]) -> json::Value {
    let decimal = |v: f32| v.to_string().parse::<f64>().unwrap_or(f64::from(v));
    json::Value::from(values.map(decimal).to_vec())
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
        double_sided: true,
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
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(1.0),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Writes `NAME.gltf` and `NAME.bin` into `dir`; returns their names.
pub(super) fn write_gltf(
    textured: &TexturedScene,
    dir: &Path,
    name: &str,
) -> anyhow::Result<Vec<String>> {
    let scene = &textured.scene;
    let mut b = Builder {
        root: json::Root {
            asset: json::Asset {
                generator: Some(format!("lensray generate {name}")),
                ..Default::default()
            },
            ..Default::default()
        },
        bin: Vec::new(),
    };
    // The glTF materials before any mesh, so that the loader (which numbers them as primitives
    // first use them) and the MTL list them alike when meshes use them in order.
    for m in &scene.materials {
        if m.alpha_texture.is_some() && m.alpha_texture != m.diffuse_texture {
            bail!(
                "material {}: glTF's coverage is the base colour texture's alpha",
                m.name
            );
        }
        b.root.push(material(m));
    }
    let sampler = b.root.push(json::texture::Sampler {
        mag_filter: Some(Valid(json::texture::MagFilter::Linear)),
        min_filter: Some(Valid(json::texture::MinFilter::LinearMipmapLinear)),
        wrap_s: Valid(json::texture::WrappingMode::Repeat),
        wrap_t: Valid(json::texture::WrappingMode::Repeat),
        ..Default::default()
    });
    for image in &textured.images {
        let source = b.root.push(json::Image {
            buffer_view: None,
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: Some(image.file.trim_end_matches(".png").into()),
            uri: Some(image.file.clone()),
            extensions: None,
            extras: Default::default(),
        });
        b.root.push(json::Texture {
            name: None,
            sampler: Some(sampler),
            source,
            extensions: None,
            extras: Default::default(),
        });
    }
    let mut nodes = Vec::new();
    for mesh in &scene.meshes {
        let index = b.mesh(mesh)?;
        nodes.push(b.root.push(json::Node {
            mesh: Some(index),
            name: Some(mesh.name.clone()),
            ..Default::default()
        }));
    }
    nodes.push(camera_node(&mut b.root, textured));
    nodes.extend(light_nodes(&mut b.root, &scene.lights)?);
    let scene_index = b.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some(name.into()),
        nodes,
    });
    b.root.scene = Some(scene_index);
    let bin_name = format!("{name}.bin");
    b.root.push(json::Buffer {
        byte_length: USize64::from(b.bin.len()),
        extensions: None,
        extras: Default::default(),
        name: None,
        uri: Some(bin_name.clone()),
    });
    let gltf_name = format!("{name}.gltf");
    let text = b
        .root
        .to_string_pretty()
        .context("cannot serialize the glTF document")?;
    std::fs::write(dir.join(&bin_name), &b.bin)
        .with_context(|| format!("cannot write {bin_name}"))?;
    std::fs::write(dir.join(&gltf_name), text)
        .with_context(|| format!("cannot write {gltf_name}"))?;
    Ok(vec![bin_name, gltf_name])
}

/// The camera's node: at the eye, turned down by the pitch, with a perspective camera.
fn camera_node(root: &mut json::Root, textured: &TexturedScene) -> json::Index<json::Node> {
    let c = &textured.camera;
    let camera = root.push(json::Camera {
        name: Some("view".into()),
        orthographic: None,
        perspective: Some(json::camera::Perspective {
            aspect_ratio: Some(c.aspect_ratio),
            yfov: c.yfov_degrees.to_radians(),
            zfar: None,
            znear: c.znear,
            extensions: None,
            extras: Default::default(),
        }),
        type_: Valid(json::camera::Type::Perspective),
        extensions: None,
        extras: Default::default(),
    });
    root.push(json::Node {
        camera: Some(camera),
        name: Some("camera".into()),
        translation: Some(c.eye.to_array()),
        rotation: Some(json::scene::UnitQuaternion(c.rotation().to_array())),
        ..Default::default()
    })
}

/// A node per light (point lights only: at their positions), and the lights in the root's
/// `KHR_lights_punctual`.
fn light_nodes(
    root: &mut json::Root,
    lights: &[crate::scene::Light],
) -> anyhow::Result<Vec<json::Index<json::Node>>> {
    use json::extensions::scene::khr_lights_punctual as punctual;
    let mut out = Vec::new();
    let mut list = Vec::new();
    for (i, light) in lights.iter().enumerate() {
        if light.kind != crate::scene::LightKind::Point || light.range != 0.0 {
            bail!("light {i}: the textured scene writes point lights without a range only");
        }
        // glTF's colour times intensity: the brightest channel is the intensity.
        let intensity = light.intensity.max_element();
        list.push(punctual::Light {
            color: (light.intensity / intensity.max(f32::MIN_POSITIVE)).to_array(),
            extensions: None,
            extras: Default::default(),
            intensity,
            name: Some(format!("light {i}")),
            range: None,
            spot: None,
            type_: Valid(punctual::Type::Point),
        });
        out.push(root.push(json::Node {
            name: Some(format!("light {i}")),
            translation: Some(light.position.to_array()),
            extensions: Some(json::extensions::scene::Node {
                khr_lights_punctual: Some(punctual::KhrLightsPunctual {
                    light: json::Index::new(i as u32),
                }),
                ..Default::default()
            }),
            ..Default::default()
        }));
    }
    if !list.is_empty() {
        root.extensions_used.push("KHR_lights_punctual".into());
        root.extensions = Some(json::extensions::Root {
            khr_lights_punctual: Some(json::extensions::root::KhrLightsPunctual { lights: list }),
            ..Default::default()
        });
    }
    Ok(out)
}
