//! glTF 2.0 (`.gltf` with its buffers, data URIs included, and `.glb`), read with the `gltf`
//! crate into a [`Scene`] and the file's cameras. glTF is in metres, and so is the scene.
//!
//! Mapping: the default scene (else the first) is walked from its roots, each node's transform
//! (matrix or TRS) applied after its parent's. Every triangle primitive (`TRIANGLES`, strips and
//! fans; indexed or not) of a node's mesh becomes one [`Mesh`](super::Mesh) in world space: positions through
//! `world_from_node`, normals through its inverse transpose, the winding kept counter-clockwise
//! where the transform mirrors; TEXCOORD_0, TEXCOORD_1 and COLOR_0 come along, and TANGENT through
//! `world_from_node` (its sign turned where the transform mirrors); a normal-mapped mesh without
//! TANGENT gets MikkTSpace's (`scene::tangents`). Vertex attributes may be quantized
//! (`KHR_mesh_quantization`, `accessors.rs`). Points and lines are skipped with one
//! notice. Materials and their textures: `materials.rs`; a primitive without one gets a white
//! Lambert surface. What the shading does not use is named in one notice.
//!
//! Strict where the file is broken: a buffer that is missing or shorter than it says, an
//! accessor reaching past its buffer view, an index past the vertices, a position that is not
//! finite and a required extension lensray does not know are errors naming what and where.

use std::path::Path;
use std::time::Instant;

use base64::Engine;

use super::file_camera::FileCamera;
use super::motion::SceneMotion;
use super::{LoadTimes, Scene, SceneError};

mod accessors;
mod animation;
mod layers;
mod materials;
mod nodes;

/// Extensions this loader applies; a file requiring any other is refused.
const KNOWN_EXTENSIONS: [&str; 10] = [
    "KHR_lights_punctual",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_mesh_quantization",
    "KHR_texture_transform",
];

/// Known extensions that lensray reads without the `gltf` crate's help.
const READ_HERE_EXTENSIONS: [&str; 1] = ["KHR_mesh_quantization"];

/// A mesh file read: the scene, the cameras it holds (in the file's order), what the loader
/// has to say about it (one line each: what it ignored or repaired) and how long it took.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshFile {
    pub scene: Scene,
    pub cameras: Vec<FileCamera>,
    pub notices: Vec<String>,
    pub times: LoadTimes,
    /// The file's animations that move no camera, as lines name them ("animation I
    /// ('NAME')"); a camera's [`FileCamera::animation`] is the one that moves it.
    pub other_animations: Vec<String>,
    /// The meshes and lights the file's animations move, if any.
    pub motion: Option<SceneMotion>,
}

/// Reads a `.gltf` or `.glb` file with its buffers.
pub fn load_gltf(path: &Path) -> Result<MeshFile, SceneError> {
    let start = Instant::now();
    let bytes = std::fs::read(path).map_err(|err| SceneError::Read {
        path: path.to_path_buf(),
        err,
    })?;
    let bad = |reason: String| SceneError::Gltf {
        path: path.to_path_buf(),
        reason,
    };
    check_glb_header(&bytes).map_err(bad)?;
    // Extensions first, so that an unknown required one is named as such.
    let unchecked =
        gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| bad(e.to_string()))?;
    let mut notices = Vec::new();
    check_extensions(&unchecked.document, &mut notices).map_err(bad)?;
    let gltf::Gltf { document, blob } = unchecked;
    // The `gltf` crate's validation refuses a required extension it does not read itself,
    // though lensray reads it (`KHR_mesh_quantization`: `accessors.rs`); checked above.
    let mut json = document.into_json();
    json.extensions_required
        .retain(|name| !READ_HERE_EXTENSIONS.contains(&name.as_str()));
    check_trusted(&json).map_err(bad)?;
    let document = gltf::Document::from_json(json)
        .map_err(|e| bad(e.to_string().trim_end_matches(';').to_string()))?;
    let base = path.parent().unwrap_or(Path::new(""));
    let buffers = read_buffers(&document, base, blob, &mut notices).map_err(bad)?;
    let mut reader = nodes::Walk::new(&buffers, base, &document);
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| bad("the file has no scene".into()))?;
    for node in scene.nodes() {
        reader.tree(node).map_err(bad)?;
    }
    let mut out = reader.finish(&document);
    notices.append(&mut out.notices);
    notices.extend(crate::scene::tangents::unread_notice(&mut out.scene));
    if let Some(motion) = &mut out.motion {
        // A moving normal-mapped mesh without TANGENT gets MikkTSpace's in its node's space.
        let mut node_scene = super::Scene {
            meshes: motion
                .meshes
                .iter_mut()
                .map(|m| std::mem::take(&mut m.node_mesh))
                .collect(),
            materials: out.scene.materials.clone(),
            ..super::Scene::default()
        };
        super::tangents::generate_missing(&mut node_scene);
        for (moving, mesh) in motion.meshes.iter_mut().zip(node_scene.meshes) {
            moving.node_mesh = mesh;
        }
    }
    out.notices = notices
        .into_iter()
        .map(|n| format!("{}: {n}", path.display()))
        .collect();
    if out.scene.triangle_count() == 0 {
        return Err(SceneError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    out.times.total = start.elapsed();
    Ok(out)
}

/// A GLB header whose length is shorter than the header itself, refused here: the `gltf` crate
/// subtracts the header's size from it unchecked.
fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    let length = bytes
        .strip_prefix(b"glTF")
        .and_then(|rest| rest.get(4..8))
        .and_then(|field| field.try_into().ok())
        .map(u32::from_le_bytes);
    match length {
        Some(length) if length < 12 => Err(format!(
            "the GLB header gives the file's length as {length} bytes, less than the header's 12"
        )),
        _ => Ok(()),
    }
}

/// What the `gltf` crate's validation takes on trust and its readers unwrap, refused here in
/// one line: a primitive whose POSITION names no accessor (validation reads that accessor's
/// bounds before it checks the index), an animation channel aimed at no node or at no
/// property, an image without a URI or with a buffer view but no MIME type, and a camera
/// without the projection its type names (validation asks for either projection).
fn check_trusted(json: &gltf::json::Root) -> Result<(), String> {
    check_positions(json)?;
    check_channels(json)?;
    check_images(json)?;
    check_cameras(json)
}

fn check_cameras(json: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::camera::Type;
    use gltf::json::validation::Checked;
    for (i, camera) in json.cameras.iter().enumerate() {
        let missing = match camera.type_ {
            Checked::Valid(Type::Perspective) if camera.perspective.is_none() => "perspective",
            Checked::Valid(Type::Orthographic) if camera.orthographic.is_none() => "orthographic",
            _ => continue,
        };
        return Err(format!(
            "camera {i} is {missing} but has no {missing} object"
        ));
    }
    Ok(())
}

fn check_positions(json: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::mesh::Semantic;
    use gltf::json::validation::Checked;
    let accessors = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&Checked::Valid(Semantic::Positions));
            if let Some(index) = position.filter(|index| index.value() >= accessors) {
                return Err(format!(
                    "mesh {m} primitive {p}: POSITION names accessor {}, and the file has {accessors}",
                    index.value()
                ));
            }
        }
    }
    Ok(())
}

fn check_channels(json: &gltf::json::Root) -> Result<(), String> {
    let nodes = json.nodes.len();
    for (a, animation) in json.animations.iter().enumerate() {
        for (c, channel) in animation.channels.iter().enumerate() {
            let target = &channel.target;
            if target.node.value() >= nodes {
                return Err(format!(
                    "animation {a} channel {c} targets node {}, and the file has {nodes}",
                    target.node.value()
                ));
            }
            if matches!(target.path, gltf::json::validation::Checked::Invalid) {
                return Err(format!(
                    "animation {a} channel {c}: its target's path is not translation, rotation, \
                     scale or weights"
                ));
            }
        }
    }
    Ok(())
}

fn check_images(json: &gltf::json::Root) -> Result<(), String> {
    for (i, image) in json.images.iter().enumerate() {
        if image.buffer_view.is_some() && image.mime_type.is_none() {
            return Err(format!("image {i} is in a buffer view but has no mimeType"));
        }
        if image.buffer_view.is_none() && image.uri.is_none() {
            return Err(format!("image {i} has neither a uri nor a bufferView"));
        }
    }
    Ok(())
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
    notices: &mut Vec<String>,
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
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => {
                    gltf::buffer::Data::from_source_and_blob(buffer.source(), None, &mut blob)
                        .map_err(|e| format!("{name}: {e}"))?
                        .0
                }
                gltf::buffer::Source::Uri(uri) => match read_uri(uri, base) {
                    Ok((bytes, note)) => {
                        notices.extend(note);
                        bytes
                    }
                    Err(Missing::File(e) | Missing::Broken(e)) => {
                        return Err(format!("{name}: {e}"))
                    }
                },
            };
            if data.len() < buffer.length() {
                return Err(format!(
                    "{name} has {} bytes, fewer than its byteLength {}",
                    data.len(),
                    buffer.length()
                ));
            }
            Ok(data)
        })
        .collect()
}

/// Why an image's bytes are not there: a file that cannot be read (a warning), or a broken
/// reference (an error).
enum Missing {
    File(String),
    Broken(String),
}

/// The bytes a glTF URI names: a base64 data URI, a `file:` URI or a percent-encoded path
/// relative to `base` (`scene::reads`: refused outside the assets root, noted outside `base`),
/// and the note.
fn read_uri(uri: &str, base: &Path) -> Result<(Vec<u8>, Option<String>), Missing> {
    if let Some(data) = uri.strip_prefix("data:") {
        let (_, payload) = data
            .split_once(";base64,")
            .ok_or(Missing::Broken("a data URI without base64 content".into()))?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map(|bytes| (bytes, None))
            .map_err(|e| Missing::Broken(format!("bad base64: {e}")));
    }
    let path = urlencoding::decode(local_path(uri)?).map_err(|e| Missing::Broken(e.to_string()))?;
    let file = super::reads::named_file(base, Path::new(path.as_ref())).map_err(Missing::Broken)?;
    let bytes = std::fs::read(&file.path)
        .map_err(|e| Missing::File(format!("cannot read {}: {e}", file.path.display())))?;
    Ok((bytes, file.note))
}

/// The path part of a URI that is not a data URI: a relative reference as it is, a `file:` URI's
/// path (RFC 8089: `file:///a/b`, `file://localhost/a/b` or `file:/a/b`; exporters write them).
/// Another scheme (`http:`) or host is refused in one line: lensray reads no network.
fn local_path(uri: &str) -> Result<&str, Missing> {
    let scheme = uri.split_once(':').map(|(scheme, _)| scheme).filter(|s| {
        // RFC 3986's scheme, longer than a letter: `C:` starts a Windows path.
        s.len() > 1
            && s.starts_with(|c: char| c.is_ascii_alphabetic())
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
    });
    let Some(scheme) = scheme else {
        return Ok(uri);
    };
    if !scheme.eq_ignore_ascii_case("file") {
        return Err(Missing::Broken(format!(
            "a {scheme}: URI; lensray reads files beside the glTF, file: URIs and data URIs, \
             not the network"
        )));
    }
    let rest = &uri[scheme.len() + 1..];
    let Some(authority_and_path) = rest.strip_prefix("//") else {
        return Ok(rest);
    };
    let (host, path) = authority_and_path
        .find('/')
        .map_or((authority_and_path, ""), |at| {
            authority_and_path.split_at(at)
        });
    if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
        return Err(Missing::Broken(format!(
            "a file: URI on host {host}; lensray reads files on this machine"
        )));
    }
    Ok(path)
}

#[cfg(test)]
mod uri_tests {
    use super::*;

    fn path_of(uri: &str) -> Result<&str, String> {
        local_path(uri).map_err(|(Missing::File(e) | Missing::Broken(e))| e)
    }

    /// Relative references pass as they are; `file:` URIs give their path, with or without an
    /// authority; other schemes and hosts are one line naming them.
    #[test]
    fn file_uris_give_their_path_and_other_schemes_are_refused() {
        assert_eq!(path_of("meshes/a%20b.bin"), Ok("meshes/a%20b.bin"));
        assert_eq!(path_of("file:///srv/a%20b.bin"), Ok("/srv/a%20b.bin"));
        assert_eq!(path_of("FILE://localhost/srv/a.bin"), Ok("/srv/a.bin"));
        assert_eq!(path_of("file:/srv/a.bin"), Ok("/srv/a.bin"));
        assert_eq!(path_of("file:a.bin"), Ok("a.bin"));
        assert_eq!(path_of("C:/models/a.bin"), Ok("C:/models/a.bin"));
        let web = path_of("https://example.com/a.bin").unwrap_err();
        assert!(
            web.starts_with("a https: URI;") && web.contains("not the network"),
            "{web}"
        );
        let host = path_of("file://server/share/a.bin").unwrap_err();
        assert!(host.contains("on host server"), "{host}");
    }

    /// A buffer named by a `file://` URI with a percent-encoded absolute path loads as the same
    /// buffer beside the file does.
    #[test]
    fn a_buffer_named_by_a_file_uri_loads() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = materials::texcoord_tests::write_triangle(dir.path(), "{}", "");
        let json = std::fs::read_to_string(&path).unwrap();
        let (head, tail) = json
            .split_once("data:application/octet-stream;base64,")
            .unwrap();
        let (data, tail) = tail.split_once('"').unwrap();
        let bin = base64::engine::general_purpose::STANDARD
            .decode(data)
            .unwrap();
        let folder = dir.path().join("two words");
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(folder.join("tri.bin"), bin).unwrap();
        let uri = format!("file://{}/two%20words/tri.bin", dir.path().display());
        std::fs::write(&path, format!("{head}{uri}\"{tail}")).unwrap();
        let file = load_gltf(&path).unwrap_or_else(|e| panic!("{uri}: {e}"));
        assert_eq!(file.scene.meshes.len(), 1);
        let https = json.replace("data:", "https://example.com/tri.bin#");
        std::fs::write(&path, https).unwrap();
        let e = load_gltf(&path).map(|_| ()).unwrap_err().to_string();
        assert!(
            e.contains("buffer 0 (https://example.com/tri.bin#") && e.contains("https: URI"),
            "{e}"
        );
    }
}
