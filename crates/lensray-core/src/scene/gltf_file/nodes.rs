//! The walk over the default scene's nodes: meshes in world space, cameras, lights, and the
//! checks of the accessors they read.

use std::path::Path;

use glam::{DMat4, DVec3, Vec2, Vec3};
use gltf::mesh::Mode;

use super::accessors::{read_colours, read_floats, read_normals, read_tangents};
use super::animation::{animation_name, camera_animation, node_tracks, NodeTracks};
use super::materials::{ignored_features, ImageSlot};
use super::MeshFile;
use crate::scene::camera_animation::{AnimatedNode, CameraPose};
use crate::scene::file_camera::{FileCamera, FileProjection};
use crate::scene::motion::{MovingLight, MovingMesh, SceneMotion};
use crate::scene::{Light, LightKind, Mesh};

/// The node walk's state: the buffers and what is gathered.
pub(super) struct Walk<'a> {
    pub buffers: &'a [Vec<u8>],
    pub document: &'a gltf::Document,
    /// The nodes from the scene root down to the node being read (an animated camera's chain).
    pub chain: Vec<usize>,
    /// The nodes already read, so that a node reached twice is refused rather than walked again.
    visited: Vec<bool>,
    /// Whether each node is on `chain`, so that a cycle is found without searching it.
    on_chain: Vec<bool>,
    /// The animations that move a camera, by index.
    pub camera_animations: Vec<usize>,
    /// Every node's tracks, from all the animations.
    tracks: NodeTracks,
    /// The meshes and lights the animations move, and the animations that move them.
    moving_meshes: Vec<MovingMesh>,
    moving_lights: Vec<MovingLight>,
    motion_animations: Vec<usize>,
    /// Where image files named by URI are.
    pub base: &'a Path,
    pub out: MeshFile,
    /// The scene material of each glTF material, once a primitive uses it.
    pub materials: Vec<Option<u32>>,
    /// glTF's default material in the scene, once a primitive needs it.
    pub default_material: Option<u32>,
    /// The scene texture of each glTF image, as colour (sRGB) and as data (linear), once a
    /// material uses it so; both missing once its file is found missing.
    pub images: Vec<[Option<ImageSlot>; 2]>,
    /// Primitives of point and line modes.
    pub skipped_modes: usize,
    /// The first texture coordinate set past TEXCOORD_1 that a texture reads (read from
    /// TEXCOORD_0).
    pub other_texcoords: Option<u32>,
}

impl<'a> Walk<'a> {
    pub(super) fn new(
        buffers: &'a [Vec<u8>],
        base: &'a Path,
        document: &'a gltf::Document,
    ) -> Self {
        Self {
            buffers,
            document,
            chain: Vec::new(),
            visited: vec![false; document.nodes().len()],
            on_chain: vec![false; document.nodes().len()],
            camera_animations: Vec::new(),
            tracks: node_tracks(document, buffers),
            moving_meshes: Vec::new(),
            moving_lights: Vec::new(),
            motion_animations: Vec::new(),
            base,
            out: MeshFile::default(),
            materials: vec![None; document.materials().len()],
            default_material: None,
            images: vec![[None; 2]; document.images().len()],
            skipped_modes: 0,
            other_texcoords: None,
        }
    }

    /// Adds the tree under the scene root `root`. The walk keeps its own stack: a file's
    /// hierarchy may be deep, and a cycle or a node with two parents is refused in one line.
    pub(super) fn tree(&mut self, root: gltf::Node) -> Result<(), String> {
        let mut stack = vec![(root, DMat4::IDENTITY, 0)];
        while let Some((node, world_from_parent, depth)) = stack.pop() {
            while self.chain.len() > depth {
                let left = self.chain.pop().expect("the chain is longer than depth");
                self.on_chain[left] = false;
            }
            let index = node.index();
            if self.on_chain[index] {
                let at = self.chain.iter().position(|&n| n == index).unwrap_or(0);
                let cycle: Vec<String> = self.chain[at..]
                    .iter()
                    .chain([&index])
                    .map(|n| n.to_string())
                    .collect();
                return Err(format!(
                    "the node hierarchy has a cycle: nodes {}",
                    cycle.join(" -> ")
                ));
            }
            if std::mem::replace(&mut self.visited[index], true) {
                return Err(format!(
                    "node {index} is reached twice (a child of two nodes, or a scene root and a \
                     child); glTF's node hierarchy is a set of trees"
                ));
            }
            let world_from_node = self.node(&node, world_from_parent)?;
            self.on_chain[index] = true;
            // Pushed last to first, so that the children are read in the file's order.
            let children: Vec<gltf::Node> = node.children().collect();
            for child in children.into_iter().rev() {
                stack.push((child, world_from_node, depth + 1));
            }
        }
        for left in self.chain.drain(..) {
            self.on_chain[left] = false;
        }
        Ok(())
    }

    /// Adds `node` itself under `world_from_parent`, leaves it last on the chain, and returns
    /// its world transform.
    fn node(&mut self, node: &gltf::Node, world_from_parent: DMat4) -> Result<DMat4, String> {
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world_from_node = world_from_parent * local;
        if !world_from_node.is_finite() {
            return Err(format!(
                "node {}: its transform is not finite",
                node.index()
            ));
        }
        self.chain.push(node.index());
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                self.primitive(node, &mesh, &primitive, &world_from_node)?;
            }
        }
        if let Some(camera) = node.camera() {
            let index = self.out.cameras.len();
            let mut camera = file_camera(node, &camera, &world_from_node, index);
            let animations =
                camera_animation(self.document, self.buffers, &self.chain, &camera.name);
            camera.animation = animations.played;
            self.out.notices.extend(animations.notices);
            self.camera_animations.extend(animations.moving);
            self.out.cameras.push(camera);
        }
        if let Some(light) = node.light() {
            let node_light = punctual_light(&light, &DMat4::IDENTITY);
            let light = punctual_light(&light, &world_from_node);
            light
                .check()
                .map_err(|e| format!("node {}: {e}", node.index()))?;
            if let Some(chain) = self.moving_chain() {
                self.moving_lights.push(MovingLight {
                    index: self.out.scene.lights.len(),
                    chain,
                    node_light,
                });
            }
            self.out.scene.lights.push(light);
        }
        Ok(world_from_node)
    }

    /// The nodes of `chain` with their tracks, where an animation moves one of them, and the
    /// animations that do noted as played.
    fn moving_chain(&mut self) -> Option<Vec<AnimatedNode>> {
        let nodes = &self.tracks.nodes;
        if !self.chain.iter().any(|&i| nodes[i].is_animated()) {
            return None;
        }
        for &i in &self.chain {
            self.motion_animations.extend(&self.tracks.movers[i]);
        }
        Some(self.chain.iter().map(|&i| nodes[i].clone()).collect())
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
            check_index_type(&indices).map_err(|e| format!("{what}: indices: {e}"))?;
        }
        let reader = primitive.reader(get);
        let attribute = |semantic: gltf::Semantic| primitive.get(&semantic);
        let positions: Vec<[f32; 3]> = attribute(gltf::Semantic::Positions)
            .map(|a| read_floats(&a, buffers, "POSITION"))
            .transpose()
            .map_err(|e| format!("{what}: {e}"))?
            .ok_or_else(|| format!("{what} has no POSITION"))?;
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
        let normals = read_normals(primitive, buffers, world_from_node, count)
            .map_err(|e| format!("{what}: {e}"))?;
        let texcoord_set = |set: u32| -> Result<Vec<Vec2>, String> {
            let name = format!("TEXCOORD_{set}");
            let texcoords: Vec<Vec2> = attribute(gltf::Semantic::TexCoords(set))
                .map(|a| read_floats(&a, buffers, &name))
                .transpose()
                .map_err(|e| format!("{what}: {e}"))?
                .map_or_else(Vec::new, |t| t.into_iter().map(Vec2::from).collect());
            Ok(if texcoords.len() == count {
                texcoords
            } else {
                Vec::new()
            })
        };
        let texcoords = texcoord_set(0)?;
        let texcoords1 = texcoord_set(1)?;
        let colours = read_colours(primitive, buffers)
            .map_err(|e| format!("{what}: {e}"))?
            .filter(|c| c.len() == count)
            .unwrap_or_default();
        let tangents = read_tangents(primitive, buffers, world_from_node)
            .map_err(|e| format!("{what}: {e}"))?
            .filter(|t| t.len() == count)
            .unwrap_or_default();
        let material = self
            .material(primitive.material())
            .map_err(|e| format!("{what}: {e}"))?;
        let mesh = Mesh {
            colours,
            tangents,
            name: mesh_name(node, mesh),
            positions: world_positions(&positions, world_from_node),
            normals,
            texcoords,
            texcoords1,
            material_ids: vec![material; triangles.len()],
            triangles,
        };
        if let Some(chain) = self.moving_chain() {
            let triangles = assemble(mode, &corners, false);
            let node_mesh = node_space_mesh(primitive, buffers, &mesh, &positions, triangles)
                .map_err(|e| format!("{what}: {e}"))?;
            self.moving_meshes.push(MovingMesh {
                index: self.out.scene.meshes.len(),
                chain,
                node_mesh,
            });
        }
        self.out.scene.meshes.push(mesh);
        Ok(())
    }

    /// What was gathered, with the notices about what the shading ignores.
    pub(super) fn finish(mut self, document: &gltf::Document) -> MeshFile {
        let played = |i: &usize| self.motion_animations.contains(i);
        self.out.other_animations = document
            .animations()
            .filter(|a| !self.camera_animations.contains(&a.index()) && !played(&a.index()))
            .map(|a| animation_name(&a))
            .collect();
        let names = document
            .animations()
            .filter(|a| played(&a.index()))
            .map(|a| animation_name(&a))
            .collect();
        self.out.motion = SceneMotion::new(names, self.moving_meshes, self.moving_lights);
        if self.out.motion.is_some() {
            self.out.notices.append(&mut self.tracks.notices);
        }
        if let Some(set) = self.other_texcoords {
            self.out.notices.push(format!(
                "reads textures of TEXCOORD_{set} with TEXCOORD_0 (lensray reads TEXCOORD_0 and \
                 TEXCOORD_1)"
            ));
        }
        if self.skipped_modes > 0 {
            self.out.notices.push(format!(
                "skipped {} point or line primitives (lensray renders triangles)",
                self.skipped_modes
            ));
        }
        let ignored = ignored_features(document);
        if !ignored.is_empty() {
            self.out.notices.push(format!(
                "not rendered yet by lensray's shading: {}",
                ignored.join(", ")
            ));
        }
        self.out
    }
}

/// A mesh's name in lines: its node's, else its own, else "node I".
fn mesh_name(node: &gltf::Node, mesh: &gltf::Mesh) -> String {
    node.name()
        .or(mesh.name())
        .map_or_else(|| format!("node {}", node.index()), str::to_string)
}

/// `positions` (in a node's space) in the world.
fn world_positions(positions: &[[f32; 3]], world_from_node: &DMat4) -> Vec<Vec3> {
    positions
        .iter()
        .map(|p| {
            let p = world_from_node.transform_point3(DVec3::from(p.map(f64::from)));
            p.as_vec3()
        })
        .collect()
}

/// `mesh` (read from `primitive` and placed in the world) in its node's space: `positions` as
/// the file holds them, the normals and tangents read again without the node's transform, and
/// `triangles` wound as in the file.
fn node_space_mesh(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    mesh: &Mesh,
    positions: &[[f32; 3]],
    triangles: Vec<[u32; 3]>,
) -> Result<Mesh, String> {
    let count = positions.len();
    Ok(Mesh {
        positions: positions.iter().map(|&p| Vec3::from(p)).collect(),
        normals: read_normals(primitive, buffers, &DMat4::IDENTITY, count)?,
        tangents: read_tangents(primitive, buffers, &DMat4::IDENTITY)?
            .filter(|t| t.len() == count)
            .unwrap_or_default(),
        triangles,
        ..mesh.clone()
    })
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

/// An error when an indices accessor holds anything but unsigned integers, one a vertex (the
/// `gltf` crate's reader treats any other component type as unreachable).
fn check_index_type(indices: &gltf::Accessor) -> Result<(), String> {
    use gltf::accessor::{DataType, Dimensions};
    let unsigned = matches!(
        indices.data_type(),
        DataType::U8 | DataType::U16 | DataType::U32
    );
    if unsigned && indices.dimensions() == Dimensions::Scalar {
        Ok(())
    } else {
        Err(format!(
            "accessor {} holds {:?} {:?}: indices are SCALAR unsigned integers (componentType \
             5121, 5123 or 5125)",
            indices.index(),
            indices.dimensions(),
            indices.data_type()
        ))
    }
}

/// An error when `accessor` has no elements, or its elements do not lie inside its buffer view
/// and the view inside its buffer (the reader would otherwise stop short or panic).
pub(super) fn check_accessor(accessor: &gltf::Accessor, buffers: &[Vec<u8>]) -> Result<(), String> {
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
    // glTF requires at least one element; the gltf crate's reader takes one off the count.
    if count == 0 {
        return Err(format!("accessor {index} has no elements"));
    }
    let end = accessor.offset() + stride * (count - 1) + size;
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
    let CameraPose { eye, forward, up } = CameraPose::of(world_from_node);
    FileCamera {
        name,
        eye,
        forward,
        up,
        projection,
        animation: None,
    }
}

/// The `KHR_lights_punctual` light at `node`: at the node's origin, shining down its -Z axis;
/// colour times intensity, in the extension's units (candela for point and spot lights, lux for
/// directional ones) taken as lensray's W/sr and W/m^2.
fn punctual_light(light: &gltf::khr_lights_punctual::Light, world_from_node: &DMat4) -> Light {
    use gltf::khr_lights_punctual::Kind;
    let kind = match light.kind() {
        Kind::Point => LightKind::Point,
        Kind::Directional => LightKind::Directional,
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => LightKind::Spot {
            cos_inner: inner_cone_angle.cos(),
            cos_outer: outer_cone_angle.cos(),
        },
    };
    Light {
        kind,
        position: world_from_node.transform_point3(DVec3::ZERO).as_vec3(),
        direction: world_from_node
            .transform_vector3(DVec3::NEG_Z)
            .normalize_or_zero()
            .as_vec3(),
        intensity: Vec3::from(light.color()) * light.intensity(),
        range: light.range().unwrap_or(0.0),
    }
}
