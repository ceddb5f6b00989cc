//! Wavefront OBJ + MTL, read through `tobj` and written back for the generators.
//!
//! Reading is forgiving where real files are messy and strict where the geometry is wrong. A
//! material library that cannot be read and a `usemtl` naming no material are notices (the
//! triangles get the default material); a UTF-8 byte-order mark and bytes that are not UTF-8
//! inside comments are accepted. An index out of range, a non-finite vertex, a malformed colour
//! and any other text that is not UTF-8 are errors naming the file and, where known, the line.
//! Before tobj parses the text, a quick scan (`prescan`) checks what tobj would either not
//! locate or not survive (it panics on some malformed colours and indices).
//!
//! Mapping: n-gons are triangulated as fans; points and polylines are skipped; consecutive OBJ
//! models of the same name (tobj splits an object at each `usemtl`) become one [`Mesh`]; `Kd` is
//! the diffuse colour (default 0.8 grey when a material has none), `Ke` the emission (0 when
//! absent); a colour given as one number is grey (`mtl`). Triangles without a material get
//! [`Material::default`], appended once. Normals are kept as given; a mesh whose faces do not
//! all have them, or that has a zero normal, gets none.

mod mtl;
mod prescan;
mod textures;

use std::borrow::Cow;
use std::cell::RefCell;
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{Vec2, Vec3};

use self::mtl::{convert_material, load_mtl};
use self::prescan::{is_polyline, prescan, Scan};
use self::textures::TextureFiles;
use super::gltf_file::MeshFile;
use super::{LoadTimes, Material, Mesh, Scene, SceneError};

fn read(path: &Path) -> Result<Vec<u8>, SceneError> {
    let bytes = fs::read(path).map_err(|err| SceneError::Read {
        path: path.to_path_buf(),
        err,
    })?;
    Ok(bytes)
}

/// The text of `bytes` (an OBJ or MTL file at `path`): without a UTF-8 byte-order mark, and
/// with comments that are not UTF-8 (a Latin-1 `©`) cut at their `#`, which a notice says.
/// Other bytes that are not UTF-8 are an error naming the line.
pub(super) fn decode_text<'a>(
    path: &Path,
    bytes: &'a [u8],
    what: &str,
    notices: &mut Vec<String>,
) -> Result<Cow<'a, str>, SceneError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    if let Ok(text) = std::str::from_utf8(bytes) {
        return Ok(Cow::Borrowed(text));
    }
    let mut text = String::with_capacity(bytes.len());
    let mut repaired = 0;
    for (index, line) in bytes.split(|&b| b == b'\n').enumerate() {
        if index > 0 {
            text.push('\n');
        }
        match std::str::from_utf8(line) {
            Ok(line) => text.push_str(line),
            Err(e) => {
                // Only a comment may hold such bytes: they must come after a `#`.
                let valid = &line[..e.valid_up_to()];
                let Some(hash) = valid.iter().position(|&b| b == b'#') else {
                    return Err(SceneError::ObjLine {
                        path: path.to_path_buf(),
                        line: index + 1,
                        reason: format!("{what} is not UTF-8 text outside a comment"),
                    });
                };
                text.push_str(std::str::from_utf8(&valid[..=hash]).expect("valid prefix"));
                repaired += 1;
            }
        }
    }
    notices.push(format!(
        "{}: {repaired} comment lines are not UTF-8 text: read without them",
        path.display()
    ));
    Ok(Cow::Owned(text))
}

/// Loads an OBJ file and the material libraries it names. Positions are world positions.
pub fn load_obj(path: &Path) -> Result<MeshFile, SceneError> {
    let start = Instant::now();
    let bytes = read(path)?;
    let mut notices = Vec::new();
    let text = decode_text(path, &bytes, "the file", &mut notices)?;
    let scan = prescan(path, &text)?;
    let (models, materials, dirs) = parse(path, &text, &scan, &mut notices)?;
    check_usemtl(path, &scan, &materials, &mut notices);

    let mut times = LoadTimes::default();
    let mut builder = ObjSceneBuilder::new(path, &materials, &dirs, &mut notices, &mut times)?;
    for model in models {
        builder.add_model(model)?;
    }
    let mut scene = builder.finish();
    notices.extend(super::tangents::unread_notice(&mut scene));
    if scene.triangle_count() == 0 {
        return Err(SceneError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    debug_assert_eq!(scene.validate(), Ok(()));
    times.total = start.elapsed();
    Ok(MeshFile {
        scene,
        cameras: Vec::new(),
        notices,
        times,
        other_animations: Vec::new(),
        motion: None,
    })
}

/// tobj's models and materials, and the folder of each material's library.
type Parsed = (Vec<tobj::Model>, Vec<tobj::Material>, Vec<PathBuf>);

/// tobj's models and materials of `text`, the material libraries read from beside `path`, and
/// the folder of each material's library (where its textures are).
fn parse(
    path: &Path,
    text: &str,
    scan: &Scan,
    notices: &mut Vec<String>,
) -> Result<Parsed, SceneError> {
    let mtl_error: RefCell<Option<SceneError>> = RefCell::new(None);
    let mtl_notices: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let material_dirs: RefCell<Vec<PathBuf>> = RefCell::new(Vec::new());
    let dir = path.parent().unwrap_or(Path::new(""));
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // tobj reads a polyline `l` of three or more points as a face: blank polylines out.
    let text = if scan.polylines {
        Cow::Owned(
            text.lines()
                .map(|l| if is_polyline(l) { "#" } else { l })
                .collect::<Vec<_>>()
                .join("\n"),
        )
    } else {
        Cow::Borrowed(text)
    };
    let loaded = tobj::load_obj_buf(&mut text.as_bytes(), &options, |mtl: &Path| {
        // tobj's callback must return a tobj error; the real one travels beside it.
        let library = match super::reads::named_file(dir, mtl) {
            Ok(file) => {
                mtl_notices.borrow_mut().extend(file.note);
                file.path
            }
            Err(message) => {
                let by = path.to_path_buf();
                mtl_error
                    .borrow_mut()
                    .get_or_insert(SceneError::Confined { by, message });
                return Err(tobj::LoadError::OpenFileFailed);
            }
        };
        // Bound first: the notices' borrow ends here, before the arms borrow them again.
        let loaded = load_mtl(&library, path, &mut mtl_notices.borrow_mut());
        match loaded {
            Ok(result) => {
                if let Ok((materials, _)) = &result {
                    let folder = library.parent().unwrap_or(Path::new("")).to_path_buf();
                    material_dirs
                        .borrow_mut()
                        .extend(std::iter::repeat_n(folder, materials.len()));
                }
                result
            }
            // A library that cannot be read leaves its materials undefined (the default).
            Err(e @ SceneError::MtlRead { .. }) => {
                mtl_notices
                    .borrow_mut()
                    .push(format!("{e}: its materials are the default"));
                tobj::load_mtl_buf(&mut &b""[..])
            }
            Err(e) => {
                mtl_error.borrow_mut().get_or_insert(e);
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    });
    notices.append(&mut mtl_notices.into_inner());
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    let (models, materials) = loaded.map_err(|e| SceneError::Obj {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    // Every library loaded (an error would have been recorded above), so this is Ok.
    let materials = materials.map_err(|e| SceneError::Obj {
        path: path.to_path_buf(),
        reason: format!("material library: {e}"),
    })?;
    Ok((models, materials, material_dirs.into_inner()))
}

/// A notice for each `usemtl` that names no material of a library loaded before it (its
/// triangles get the default material), one line for all of them.
fn check_usemtl(path: &Path, scan: &Scan, materials: &[tobj::Material], notices: &mut Vec<String>) {
    let unknown: Vec<String> = scan
        .usemtl
        .iter()
        .filter(|(line, name)| {
            let before_library = scan.first_mtllib.is_none_or(|first| *line < first);
            before_library || !materials.iter().any(|m| &m.name == name)
        })
        .map(|(line, name)| format!("`{name}` (line {line})"))
        .collect();
    if let Some(first) = unknown.first() {
        let more = match unknown.len() {
            1 => String::new(),
            n => format!(" and {} more", n - 1),
        };
        notices.push(format!(
            "{}: usemtl {first}{more} names no material of the file's libraries: the default material",
            path.display()
        ));
    }
}

/// Gathers tobj's models into a scene: consecutive models of the same name become one mesh.
struct ObjSceneBuilder<'a> {
    path: &'a Path,
    scene: Scene,
    /// Where `Material::default()` is in `scene.materials`, once a triangle needs it.
    default_material: Option<u32>,
    /// Whether every model merged into the last mesh had normals.
    all_normals: bool,
    /// Whether any model merged into the last mesh had texture coordinates.
    any_texcoords: bool,
    previous_name: Option<String>,
}

impl<'a> ObjSceneBuilder<'a> {
    /// A scene with no meshes yet and the materials of the file's libraries (read from
    /// `dirs`, one per material) with their textures (timed into `times`).
    fn new(
        path: &'a Path,
        materials: &[tobj::Material],
        dirs: &[PathBuf],
        notices: &mut Vec<String>,
        times: &mut LoadTimes,
    ) -> Result<Self, SceneError> {
        let mut files = TextureFiles::new(path);
        let obj_dir = path.parent().unwrap_or(Path::new(""));
        let converted = materials
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let dir = dirs.get(i).map_or(obj_dir, PathBuf::as_path);
                convert_material(m, dir, &mut files)
            })
            .collect::<Result<_, _>>()?;
        notices.append(&mut files.notices);
        *times = files.times;
        Ok(Self {
            path,
            scene: Scene {
                meshes: Vec::new(),
                materials: converted,
                textures: files.textures,
                lights: Vec::new(),
                environment: None,
            },
            default_material: None,
            all_normals: true,
            any_texcoords: false,
            previous_name: None,
        })
    }

    /// Adds a model's triangles to the last mesh, or to a new one when its name differs.
    fn add_model(&mut self, model: tobj::Model) -> Result<(), SceneError> {
        let m = model.mesh;
        if m.indices.is_empty() {
            return Ok(());
        }
        let material = self.material(m.material_id)?;
        if self.previous_name.as_deref() != Some(model.name.as_str()) {
            self.finish_mesh();
            self.scene.meshes.push(Mesh {
                colours: Vec::new(),
                tangents: Vec::new(),
                name: model.name.clone(),
                ..Mesh::default()
            });
            self.all_normals = true;
            self.any_texcoords = false;
            self.previous_name = Some(model.name);
        }
        self.append(&m, material)
    }

    /// The scene material of a model's material id (none: the default material).
    fn material(&mut self, id: Option<usize>) -> Result<u32, SceneError> {
        Ok(match id {
            Some(id) if id < self.scene.materials.len() => id as u32,
            Some(id) => {
                return Err(SceneError::Obj {
                    path: self.path.to_path_buf(),
                    reason: format!("material index {id} out of range"),
                })
            }
            None => *self.default_material.get_or_insert_with(|| {
                self.scene.materials.push(Material::default());
                (self.scene.materials.len() - 1) as u32
            }),
        })
    }

    /// Appends a model's vertices, normals and triangles (all of `material`) to the last mesh.
    fn append(&mut self, m: &tobj::Mesh, material: u32) -> Result<(), SceneError> {
        let mesh = self.scene.meshes.last_mut().expect("pushed by add_model");
        let offset = mesh.positions.len() as u32;
        let vertex_count = m.positions.len() / 3;
        for p in m.positions.chunks_exact(3) {
            let p = Vec3::new(p[0], p[1], p[2]);
            if !p.is_finite() {
                // Only reachable through `v x y z w` with a tiny w.
                return Err(SceneError::Obj {
                    path: self.path.to_path_buf(),
                    reason: format!("vertex position {p} is not finite"),
                });
            }
            mesh.positions.push(p);
        }
        if m.normals.len() == m.positions.len() && self.all_normals {
            mesh.normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
        } else {
            self.all_normals = false;
        }
        // OBJ's v runs up the image, the textures' (glTF's) down from its first row.
        if m.texcoords.len() / 2 == vertex_count {
            self.any_texcoords = true;
            let flipped = m
                .texcoords
                .chunks_exact(2)
                .map(|t| Vec2::new(t[0], 1.0 - t[1]));
            mesh.texcoords.extend(flipped);
        } else {
            mesh.texcoords
                .extend(std::iter::repeat_n(Vec2::ZERO, vertex_count));
        }
        for t in m.indices.chunks_exact(3) {
            if let Some(&bad) = t.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(SceneError::Obj {
                    path: self.path.to_path_buf(),
                    reason: format!("vertex index {bad} out of range ({vertex_count} vertices)"),
                });
            }
            mesh.triangles
                .push([t[0] + offset, t[1] + offset, t[2] + offset]);
            mesh.material_ids.push(material);
        }
        Ok(())
    }

    /// The scene, its last mesh finished.
    fn finish(mut self) -> Scene {
        self.finish_mesh();
        self.scene
    }

    /// The last mesh's normals and texture coordinates dropped unless it has them.
    fn finish_mesh(&mut self) {
        finish_mesh(self.scene.meshes.last_mut(), self.all_normals);
        if let Some(mesh) = self.scene.meshes.last_mut() {
            if !self.any_texcoords {
                mesh.texcoords.clear();
            }
        }
    }
}

/// Drops a mesh's normals unless every part of it had them and none is zero.
fn finish_mesh(mesh: Option<&mut Mesh>, all_normals: bool) {
    if let Some(mesh) = mesh {
        if !all_normals
            || mesh.normals.len() != mesh.positions.len()
            || mesh.normals.contains(&Vec3::ZERO)
        {
            mesh.normals.clear();
        }
    }
}

/// Names made unique (and non-empty, without line breaks) by appending `_2`, `_3`, ...
fn unique_names<'a>(names: impl Iterator<Item = &'a str>, fallback: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for name in names {
        let base: String = name.trim().replace(['\n', '\r'], " ");
        let base = if base.is_empty() {
            fallback.to_string()
        } else {
            base
        };
        let mut candidate = base.clone();
        let mut n = 2;
        while out.contains(&candidate) {
            candidate = format!("{base}_{n}");
            n += 1;
        }
        out.push(candidate);
    }
    out
}

/// Writes `scene` as `obj_path` and a sibling material library (same stem, `.mtl`) with `Kd`
/// and `Ke`. Numbers are written in the shortest form that reads back exactly; meshes become
/// `o` objects; duplicate mesh or material names get a `_2`, `_3`, ... suffix. A mesh with
/// normals writes `f v//vn` corners.
pub fn write_obj(scene: &Scene, obj_path: &Path) -> io::Result<()> {
    let stem = obj_path
        .file_stem()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "OBJ path has no file name"))?;
    let mtl_name = format!("{}.mtl", stem.to_string_lossy());
    let mtl_path = obj_path.with_file_name(&mtl_name);
    let material_names = unique_names(scene.materials.iter().map(|m| m.name.as_str()), "material");
    let mesh_names = unique_names(scene.meshes.iter().map(|m| m.name.as_str()), "mesh");

    let mut mtl = BufWriter::new(fs::File::create(&mtl_path)?);
    writeln!(
        mtl,
        "# lensray materials: diffuse Kd and emission Ke, linear RGB"
    )?;
    for (m, name) in scene.materials.iter().zip(&material_names) {
        writeln!(mtl, "\nnewmtl {name}")?;
        writeln!(mtl, "Kd {} {} {}", m.diffuse.x, m.diffuse.y, m.diffuse.z)?;
        writeln!(mtl, "Ke {} {} {}", m.emission.x, m.emission.y, m.emission.z)?;
    }
    mtl.into_inner().map_err(|e| e.into_error())?.sync_all()?;

    let mut obj = BufWriter::with_capacity(1 << 20, fs::File::create(obj_path)?);
    writeln!(
        obj,
        "# lensray scene: {} meshes, {} triangles, {} materials",
        scene.meshes.len(),
        scene.triangle_count(),
        scene.materials.len()
    )?;
    writeln!(obj, "mtllib {mtl_name}")?;
    let mut base = 1usize;
    for (mesh, name) in scene.meshes.iter().zip(&mesh_names) {
        writeln!(obj, "o {name}")?;
        for p in &mesh.positions {
            writeln!(obj, "v {} {} {}", p.x, p.y, p.z)?;
        }
        let with_normals = !mesh.normals.is_empty() && mesh.normals.len() == mesh.positions.len();
        if with_normals {
            for n in &mesh.normals {
                writeln!(obj, "vn {} {} {}", n.x, n.y, n.z)?;
            }
        }
        let mut current = None;
        for (t, &m) in mesh.triangles.iter().zip(&mesh.material_ids) {
            if current != Some(m) {
                let name = material_names.get(m as usize).ok_or_else(|| {
                    io::Error::new(
                        io::ErrorKind::InvalidInput,
                        format!("mesh {name}: material id {m} out of range"),
                    )
                })?;
                writeln!(obj, "usemtl {name}")?;
                current = Some(m);
            }
            let [a, b, c] = t.map(|i| i as usize + base);
            if with_normals {
                writeln!(obj, "f {a}//{a} {b}//{b} {c}//{c}")?;
            } else {
                writeln!(obj, "f {a} {b} {c}")?;
            }
        }
        base += mesh.positions.len();
    }
    obj.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}
