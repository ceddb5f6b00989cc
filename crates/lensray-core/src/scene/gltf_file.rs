//! glTF 2.0 (`.gltf` with its buffers, data URIs included, and `.glb`), read with the `gltf`
//! crate into a [`Scene`] and the file's cameras. glTF is in metres, and so is the scene.
//!
//! Mapping: the default scene (else the first) is walked from its roots, each node's transform
//! (matrix or TRS) applied after its parent's. Every triangle primitive (`TRIANGLES`, strips and
//! fans; indexed or not) of a node's mesh becomes one [`Mesh`] in world space: positions through
//! `world_from_node`, normals through its inverse transpose, the winding kept counter-clockwise
//! where the transform mirrors. Points and lines are skipped with one notice. A material is its
//! `baseColorFactor` (the diffuse colour) and `emissiveFactor` times
//! `KHR_materials_emissive_strength`; a primitive without one gets glTF's default material
//! (white). What the Lambert shading does not use is named in one notice.
//!
//! Strict where the file is broken: a buffer that is missing or shorter than it says, an
//! accessor reaching past its buffer view, an index past the vertices, a position that is not
//! finite and a required extension lensray does not know are errors naming what and where.

use std::path::Path;

use glam::{DMat4, DVec3, Vec3};
use gltf::mesh::Mode;

use super::file_camera::{FileCamera, FileProjection};
use super::{Material, Mesh, Scene, SceneError};

/// Extensions this loader applies; a file requiring any other is refused.
const KNOWN_EXTENSIONS: [&str; 1] = ["KHR_materials_emissive_strength"];

/// A mesh file read: the scene, the cameras it holds (in the file's order) and what the loader
/// has to say about it (one line each: what it ignored or repaired).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshFile {
    pub scene: Scene,
    pub cameras: Vec<FileCamera>,
    pub notices: Vec<String>,
}

/// Reads a `.gltf` or `.glb` file with its buffers.
pub fn load_gltf(path: &Path) -> Result<MeshFile, SceneError> {
    let bytes = std::fs::read(path).map_err(|err| SceneError::Read {
        path: path.to_path_buf(),
        err,
    })?;
    let bad = |reason: String| SceneError::Gltf {
        path: path.to_path_buf(),
        reason,
    };
    // Extensions first, so that an unknown required one is named as such.
    let unchecked =
        gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| bad(e.to_string()))?;
    let mut notices = Vec::new();
    check_extensions(&unchecked.document, &mut notices).map_err(bad)?;
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(&bytes)
        .map_err(|e| bad(e.to_string().trim_end_matches(';').to_string()))?;
    let base = path.parent().unwrap_or(Path::new(""));
    let buffers = read_buffers(&document, base, blob).map_err(bad)?;
    let mut reader = Walk {
        buffers: &buffers,
        out: MeshFile::default(),
        materials: vec![None; document.materials().len()],
        default_material: None,
        skipped_modes: 0,
    };
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| bad("the file has no scene".into()))?;
    for node in scene.nodes() {
        reader.node(&node, DMat4::IDENTITY).map_err(bad)?;
    }
    let mut out = reader.finish(&document);
    notices.append(&mut out.notices);
    out.notices = notices
        .into_iter()
        .map(|n| format!("{}: {n}", path.display()))
        .collect();
    if out.scene.triangle_count() == 0 {
        return Err(SceneError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    Ok(out)
}

/// An error for a required extension lensray does not apply; a notice for used ones.
fn check_extensions(document: &gltf::Document, notices: &mut Vec<String>) -> Result<(), String> {
    let unknown = |name: &&str| !KNOWN_EXTENSIONS.contains(name);
    if let Some(name) = document.extensions_required().find(unknown) {
        return Err(format!(
            "requires the extension {name}, which lensray does not support"
        ));
    }
    let ignored: Vec<&str> = document.extensions_used().filter(unknown).collect();
    if !ignored.is_empty() {
        notices.push(format!("ignores the extensions {}", ignored.join(", ")));
    }
    Ok(())
}

/// Every buffer's bytes: a file beside the glTF, a data URI, or the GLB's binary chunk; an
/// error names a buffer that cannot be read or is shorter than its `byteLength`.
fn read_buffers(
    document: &gltf::Document,
    base: &Path,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, String> {
    document
        .buffers()
        .map(|buffer| {
            let name = match buffer.source() {
                gltf::buffer::Source::Bin => {
                    format!("buffer {} (the GLB's BIN chunk)", buffer.index())
                }
                gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                    format!("buffer {} (a data URI)", buffer.index())
                }
                gltf::buffer::Source::Uri(uri) => format!("buffer {} ({uri})", buffer.index()),
            };
            let data =
                gltf::buffer::Data::from_source_and_blob(buffer.source(), Some(base), &mut blob)
                    .map_err(|e| format!("{name}: {e}"))?;
            if data.len() < buffer.length() {
                return Err(format!(
                    "{name} has {} bytes, fewer than its byteLength {}",
                    data.len(),
                    buffer.length()
                ));
            }
            Ok(data.0)
        })
        .collect()
}

/// The node walk's state: the buffers and what is gathered.
struct Walk<'a> {
    buffers: &'a [Vec<u8>],
    out: MeshFile,
    /// The scene material of each glTF material, once a primitive uses it.
    materials: Vec<Option<u32>>,
    /// glTF's default material in the scene, once a primitive needs it.
    default_material: Option<u32>,
    /// Primitives of point and line modes.
    skipped_modes: usize,
}

impl Walk<'_> {
    /// Adds `node` and its subtree under `world_from_parent`.
    fn node(&mut self, node: &gltf::Node, world_from_parent: DMat4) -> Result<(), String> {
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world_from_node = world_from_parent * local;
        if !world_from_node.is_finite() {
            return Err(format!(
                "node {}: its transform is not finite",
                node.index()
            ));
        }
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                self.primitive(node, &mesh, &primitive, &world_from_node)?;
            }
        }
        if let Some(camera) = node.camera() {
            let index = self.out.cameras.len();
            self.out
                .cameras
                .push(file_camera(node, &camera, &world_from_node, index));
        }
        for child in node.children() {
            self.node(&child, world_from_node)?;
        }
        Ok(())
    }

    /// Adds one primitive of `mesh` at `node` as a mesh in world space.
    fn primitive(
        &mut self,
        node: &gltf::Node,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        world_from_node: &DMat4,
    ) -> Result<(), String> {
        let mode = primitive.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.skipped_modes += 1;
            return Ok(());
        }
        let what = format!(
            "mesh {} ({}) primitive {}",
            mesh.index(),
            mesh.name().unwrap_or("unnamed"),
            primitive.index()
        );
        let buffers = self.buffers;
        let get = |buffer: gltf::Buffer| buffers.get(buffer.index()).map(Vec::as_slice);
        for (semantic, accessor) in primitive.attributes() {
            check_accessor(&accessor, buffers)
                .map_err(|e| format!("{what}: attribute {semantic:?}: {e}"))?;
        }
        if let Some(indices) = primitive.indices() {
            check_accessor(&indices, buffers).map_err(|e| format!("{what}: indices: {e}"))?;
        }
        let reader = primitive.reader(get);
        let positions: Vec<[f32; 3]> = reader
            .read_positions()
            .ok_or_else(|| format!("{what} has no POSITION"))?
            .collect();
        if let Some(p) = positions.iter().find(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(format!("{what}: position {p:?} is not finite"));
        }
        let count = positions.len();
        let corners: Vec<u32> = match reader.read_indices() {
            Some(indices) => indices.into_u32().collect(),
            None => (0..count as u32).collect(),
        };
        if let Some(&bad) = corners.iter().find(|&&i| i as usize >= count) {
            return Err(format!(
                "{what}: index {bad} is out of range ({count} vertices)"
            ));
        }
        let mirrored = world_from_node.determinant() < 0.0;
        let triangles = assemble(mode, &corners, mirrored);
        let normals: Vec<Vec3> = match reader.read_normals() {
            Some(normals) => {
                let normal_from_node = world_from_node.inverse().transpose();
                normals
                    .map(|n| {
                        let n = normal_from_node.transform_vector3(DVec3::from(n.map(f64::from)));
                        n.normalize_or_zero().as_vec3()
                    })
                    .collect()
            }
            None => Vec::new(),
        };
        // A zero normal (degenerate in the file) leaves the mesh faceted, as for OBJ.
        let normals = if normals.len() == count && !normals.contains(&Vec3::ZERO) {
            normals
        } else {
            Vec::new()
        };
        let material = self.material(primitive.material());
        let name = node
            .name()
            .or(mesh.name())
            .map_or_else(|| format!("node {}", node.index()), str::to_string);
        self.out.scene.meshes.push(Mesh {
            name,
            positions: positions
                .iter()
                .map(|p| {
                    let p = world_from_node.transform_point3(DVec3::from(p.map(f64::from)));
                    p.as_vec3()
                })
                .collect(),
            normals,
            material_ids: vec![material; triangles.len()],
            triangles,
        });
        Ok(())
    }

    /// The scene material of a glTF material (made on its first use).
    fn material(&mut self, material: gltf::Material) -> u32 {
        let slot = match material.index() {
            Some(i) => &mut self.materials[i],
            None => &mut self.default_material,
        };
        if let Some(id) = *slot {
            return id;
        }
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let strength = material.emissive_strength().unwrap_or(1.0);
        let name = material
            .name()
            .map(str::to_string)
            .unwrap_or_else(|| match material.index() {
                Some(i) => format!("material {i}"),
                None => "glTF default".into(),
            });
        let scene = &mut self.out.scene;
        scene.materials.push(Material {
            name,
            diffuse: Vec3::new(r, g, b),
            emission: Vec3::from(material.emissive_factor()) * strength,
        });
        let id = (scene.materials.len() - 1) as u32;
        *slot = Some(id);
        id
    }

    /// What was gathered, with the notices about what the shading ignores.
    fn finish(mut self, document: &gltf::Document) -> MeshFile {
        if self.skipped_modes > 0 {
            self.out.notices.push(format!(
                "skipped {} point or line primitives (lensray renders triangles)",
                self.skipped_modes
            ));
        }
        let ignored = ignored_features(document);
        if !ignored.is_empty() {
            self.out.notices.push(format!(
                "not rendered yet by lensray's Lambert shading: {}",
                ignored.join(", ")
            ));
        }
        let lights = document.lights().map_or(0, |l| l.len());
        if lights > 0 {
            self.out.notices.push(format!(
                "its {lights} KHR_lights_punctual lights are not used yet: the shot's own light is"
            ));
        }
        self.out
    }
}

/// The features of the file's materials that the scene does not carry, by name.
fn ignored_features(document: &gltf::Document) -> Vec<&'static str> {
    let mut ignored = Vec::new();
    let mut note = |used: bool, name| {
        if used && !ignored.contains(&name) {
            ignored.push(name);
        }
    };
    for m in document.materials() {
        let pbr = m.pbr_metallic_roughness();
        note(pbr.base_color_texture().is_some(), "base colour textures");
        note(m.emissive_texture().is_some(), "emissive textures");
        note(
            m.alpha_mode() != gltf::material::AlphaMode::Opaque,
            "alpha (MASK and BLEND draw opaque)",
        );
        note(!m.double_sided(), "single-sided culling");
        note(
            pbr.metallic_roughness_texture().is_some()
                || pbr.metallic_factor() != 1.0
                || pbr.roughness_factor() != 1.0,
            "metallic-roughness",
        );
        note(m.normal_texture().is_some(), "normal maps");
        note(m.occlusion_texture().is_some(), "occlusion maps");
    }
    ignored
}

/// The triangles of `corners` in `mode`, counter-clockwise as glTF winds them (reversed where
/// the node's transform mirrors, so that they stay counter-clockwise in the world).
fn assemble(mode: Mode, corners: &[u32], mirrored: bool) -> Vec<[u32; 3]> {
    let triangles: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => corners
            .windows(3)
            .enumerate()
            .map(|(i, w)| {
                if i % 2 == 0 {
                    [w[0], w[1], w[2]]
                } else {
                    [w[1], w[0], w[2]]
                }
            })
            .collect(),
        Mode::TriangleFan => corners
            .windows(2)
            .skip(1)
            .map(|w| [corners[0], w[0], w[1]])
            .collect(),
        _ => corners
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
    };
    if mirrored {
        triangles.into_iter().map(|[a, b, c]| [a, c, b]).collect()
    } else {
        triangles
    }
}

/// An error when `accessor`'s elements do not lie inside its buffer view and the view inside
/// its buffer (the reader would otherwise stop short or panic).
fn check_accessor(accessor: &gltf::Accessor, buffers: &[Vec<u8>]) -> Result<(), String> {
    let index = accessor.index();
    if accessor.sparse().is_some() {
        return Err(format!(
            "accessor {index} is sparse, which lensray does not read"
        ));
    }
    let view = accessor
        .view()
        .ok_or_else(|| format!("accessor {index} has no buffer view"))?;
    let buffer_len = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    let view_end = view.offset() + view.length();
    if view_end > buffer_len {
        return Err(format!(
            "buffer view {} ends at byte {view_end}, past its buffer's {buffer_len}",
            view.index()
        ));
    }
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    let count = accessor.count();
    let end = match count {
        0 => 0,
        n => accessor.offset() + stride * (n - 1) + size,
    };
    if end > view.length() {
        return Err(format!(
            "accessor {index} ({count} elements) ends at byte {end} of buffer view {}, which has {}",
            view.index(),
            view.length()
        ));
    }
    Ok(())
}

/// The camera of `node` as lensray reads it: the node's position, its -Z axis the view
/// direction and its +Y axis up (glTF's camera axes).
fn file_camera(
    node: &gltf::Node,
    camera: &gltf::Camera,
    world_from_node: &DMat4,
    index: usize,
) -> FileCamera {
    let projection = match camera.projection() {
        gltf::camera::Projection::Perspective(p) => FileProjection::Perspective {
            yfov: f64::from(p.yfov()),
            aspect_ratio: p.aspect_ratio().map(f64::from),
            znear: f64::from(p.znear()),
            zfar: p.zfar().map(f64::from),
        },
        gltf::camera::Projection::Orthographic(o) => FileProjection::Orthographic {
            xmag: f64::from(o.xmag()),
            ymag: f64::from(o.ymag()),
            znear: f64::from(o.znear()),
            zfar: f64::from(o.zfar()),
        },
    };
    let name = camera
        .name()
        .or(node.name())
        .map_or_else(|| format!("camera {index}"), str::to_string);
    FileCamera {
        name,
        eye: world_from_node.transform_point3(DVec3::ZERO),
        forward: world_from_node
            .transform_vector3(DVec3::NEG_Z)
            .normalize_or_zero(),
        up: world_from_node
            .transform_vector3(DVec3::Y)
            .normalize_or_zero(),
        projection,
    }
}
