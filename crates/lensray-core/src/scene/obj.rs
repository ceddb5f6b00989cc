//! Wavefront OBJ + MTL, read through `tobj` and written back for the generators.
//!
//! Reading is strict: a material library that fails to load, a `usemtl` naming no material, an
//! index out of range, a non-finite vertex or a malformed colour are errors naming the file and,
//! where known, the line. Before tobj parses the text, a quick scan checks what tobj would either
//! not locate or not survive (it panics on some malformed colours and indices).
//!
//! Mapping: n-gons are triangulated as fans; points and polylines are skipped; consecutive OBJ models of the same name (tobj splits
//! an object at each `usemtl`) become one [`Mesh`]; `Kd` is the diffuse colour (default 0.8 grey
//! when a material has none), `Ke` the emission (0 when absent); a colour given as one number is
//! grey. Triangles without a material get [`Material::default`], appended once. Normals are kept
//! as given; a mesh whose faces do not all have them, or that has a zero normal, gets none.

use std::cell::RefCell;
use std::fmt::Write as _;
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use glam::Vec3;

use super::{Material, Mesh, Scene, SceneError};

fn read(path: &Path) -> Result<Vec<u8>, SceneError> {
    let bytes = fs::read(path).map_err(|err| SceneError::Read {
        path: path.to_path_buf(),
        err,
    })?;
    Ok(bytes)
}

fn utf8<'a>(path: &Path, bytes: &'a [u8], what: &str) -> Result<&'a str, SceneError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        SceneError::ObjLine {
            path: path.to_path_buf(),
            line,
            reason: format!("{what} is not UTF-8 text"),
        }
    })
}

/// Loads an OBJ file and the material libraries it names. Positions are world positions.
pub fn load_obj(path: &Path) -> Result<Scene, SceneError> {
    let bytes = read(path)?;
    let text = utf8(path, &bytes, "the file")?;
    let scan = prescan(path, text)?;

    let mtl_error: RefCell<Option<SceneError>> = RefCell::new(None);
    let dir = path.parent().unwrap_or(Path::new(""));
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // tobj reads a polyline `l` of three or more points as a face: blank polylines out.
    let filtered;
    let text = if scan.polylines {
        filtered = text
            .lines()
            .map(|l| if is_polyline(l) { "#" } else { l })
            .collect::<Vec<_>>()
            .join("\n");
        filtered.as_str()
    } else {
        text
    };
    let loaded = tobj::load_obj_buf(&mut text.as_bytes(), &options, |mtl: &Path| {
        // tobj's callback must return a tobj error; the real one travels beside it.
        match load_mtl(&dir.join(mtl), path) {
            Ok(result) => result,
            Err(e) => {
                mtl_error.borrow_mut().get_or_insert(e);
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    });
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

    for (line, name) in &scan.usemtl {
        let before_library = scan.first_mtllib.is_none_or(|first| *line < first);
        if before_library || !materials.iter().any(|m| &m.name == name) {
            return Err(SceneError::UnknownMaterial {
                path: path.to_path_buf(),
                line: *line,
                name: name.clone(),
            });
        }
    }

    let mut scene = Scene {
        meshes: Vec::new(),
        materials: materials.iter().map(convert_material).collect(),
    };
    let mut default_material = None;
    // Whether every model merged into the last mesh had normals.
    let mut all_normals = true;
    let mut previous_name: Option<String> = None;
    for model in models {
        let m = model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let material = match m.material_id {
            Some(id) if id < scene.materials.len() => id as u32,
            Some(id) => {
                return Err(SceneError::Obj {
                    path: path.to_path_buf(),
                    reason: format!("material index {id} out of range"),
                })
            }
            None => *default_material.get_or_insert_with(|| {
                scene.materials.push(Material::default());
                (scene.materials.len() - 1) as u32
            }),
        };
        if previous_name.as_deref() != Some(model.name.as_str()) {
            finish_mesh(scene.meshes.last_mut(), all_normals);
            scene.meshes.push(Mesh {
                name: model.name.clone(),
                ..Mesh::default()
            });
            all_normals = true;
            previous_name = Some(model.name);
        }
        let mesh = scene.meshes.last_mut().expect("pushed above");
        let offset = mesh.positions.len() as u32;
        let vertex_count = m.positions.len() / 3;
        for p in m.positions.chunks_exact(3) {
            let p = Vec3::new(p[0], p[1], p[2]);
            if !p.is_finite() {
                // Only reachable through `v x y z w` with a tiny w.
                return Err(SceneError::Obj {
                    path: path.to_path_buf(),
                    reason: format!("vertex position {p} is not finite"),
                });
            }
            mesh.positions.push(p);
        }
        if m.normals.len() == m.positions.len() && all_normals {
            mesh.normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
        } else {
            all_normals = false;
        }
        for t in m.indices.chunks_exact(3) {
            if let Some(&bad) = t.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(SceneError::Obj {
                    path: path.to_path_buf(),
                    reason: format!("vertex index {bad} out of range ({vertex_count} vertices)"),
                });
            }
            mesh.triangles
                .push([t[0] + offset, t[1] + offset, t[2] + offset]);
            mesh.material_ids.push(material);
        }
    }
    finish_mesh(scene.meshes.last_mut(), all_normals);

    if scene.triangle_count() == 0 {
        return Err(SceneError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    debug_assert_eq!(scene.validate(), Ok(()));
    Ok(scene)
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

fn convert_material(m: &tobj::Material) -> Material {
    let default = Material::default();
    let emission = m
        .emissive
        .or_else(|| m.unknown_param.get("Ke").and_then(|s| parse_colour(s).ok()));
    Material {
        name: m.name.clone(),
        diffuse: m.diffuse.map(Vec3::from).unwrap_or(default.diffuse),
        emission: emission.map(Vec3::from).unwrap_or(Vec3::ZERO),
    }
}

/// Parses "r g b" or "v" (grey): finite, non-negative.
fn parse_colour(s: &str) -> Result<[f32; 3], ()> {
    let values: Vec<f32> = s
        .split_whitespace()
        .map(|w| w.parse::<f32>().map_err(|_| ()))
        .collect::<Result<_, _>>()?;
    let rgb = match values[..] {
        [v] => [v; 3],
        [r, g, b] => [r, g, b],
        _ => return Err(()),
    };
    if rgb.iter().all(|c| c.is_finite() && *c >= 0.0) {
        Ok(rgb)
    } else {
        Err(())
    }
}

/// Reads one material library for tobj, after checking its colours (tobj panics on a colour of
/// fewer than three numbers) and spelling a one-number colour out as three.
fn load_mtl(mtl: &Path, obj: &Path) -> Result<tobj::MTLLoadResult, SceneError> {
    let bytes = fs::read(mtl).map_err(|err| SceneError::MtlRead {
        mtl: mtl.to_path_buf(),
        obj: obj.to_path_buf(),
        err,
    })?;
    let text = std::str::from_utf8(&bytes).map_err(|_| SceneError::Mtl {
        path: mtl.to_path_buf(),
        reason: "not UTF-8 text".into(),
    })?;
    let mut normalized = String::with_capacity(text.len());
    for (index, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        let key = trimmed.split_whitespace().next().unwrap_or("");
        if matches!(key, "Kd" | "Ke" | "Ka" | "Ks") {
            let value = trimmed[key.len()..].trim();
            let rgb = parse_colour(value).map_err(|()| SceneError::Color {
                path: mtl.to_path_buf(),
                line: index + 1,
                key: key.into(),
                value: value.into(),
            })?;
            let _ = writeln!(normalized, "{key} {} {} {}", rgb[0], rgb[1], rgb[2]);
        } else {
            normalized.push_str(line);
            normalized.push('\n');
        }
    }
    tobj::load_mtl_buf(&mut normalized.as_bytes())
        .map_err(|e| SceneError::Mtl {
            path: mtl.to_path_buf(),
            reason: e.to_string(),
        })
        .map(Ok)
}

fn is_polyline(line: &str) -> bool {
    line.split_whitespace().next() == Some("l")
}

/// What the pre-scan learned.
struct Scan {
    /// Whether the file has `l` statements.
    polylines: bool,
    /// `usemtl` statements: line and material name.
    usemtl: Vec<(usize, String)>,
    first_mtllib: Option<usize>,
}

/// Checks vertex and normal values and face indices line by line, so that errors name the line.
fn prescan(path: &Path, text: &str) -> Result<Scan, SceneError> {
    let mut counts = [0usize; 3]; // v, vt, vn
    const KINDS: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    // Largest positive index of each kind and its line: checked against the final counts, since
    // tobj resolves positive indices when an object ends.
    let mut max_positive = [(0i64, 0usize); 3];
    let mut scan = Scan {
        polylines: false,
        usemtl: Vec::new(),
        first_mtllib: None,
    };
    let bad = |line: usize, reason: String| SceneError::ObjLine {
        path: path.to_path_buf(),
        line,
        reason,
    };
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let mut words = raw.split_whitespace();
        let Some(key) = words.next() else { continue };
        match key {
            "v" | "vn" => {
                let what = if key == "v" {
                    "vertex position"
                } else {
                    "vertex normal"
                };
                let mut xyz = [0.0f32; 3];
                for c in &mut xyz {
                    *c = words.next().and_then(|w| w.parse().ok()).ok_or_else(|| {
                        bad(
                            line,
                            format!("{what} needs three numbers: `{}`", raw.trim()),
                        )
                    })?;
                }
                if !xyz.iter().all(|c| c.is_finite()) {
                    return Err(SceneError::NonFinite {
                        path: path.to_path_buf(),
                        line,
                        what,
                        text: raw.trim().into(),
                    });
                }
                counts[if key == "v" { 0 } else { 2 }] += 1;
            }
            "vt" => counts[1] += 1,
            "f" | "l" => {
                let mut corners = 0;
                for word in words {
                    corners += 1;
                    for (kind, part) in word.split('/').enumerate() {
                        if part.is_empty() {
                            if kind == 0 {
                                return Err(bad(
                                    line,
                                    format!("face corner `{word}` has no vertex index"),
                                ));
                            }
                            continue;
                        }
                        if kind > 2 {
                            return Err(bad(
                                line,
                                format!("face corner `{word}` has too many indices"),
                            ));
                        }
                        let i: i64 = part.parse().map_err(|_| {
                            bad(line, format!("face index `{part}` is not an integer"))
                        })?;
                        let count = counts[kind];
                        let out_of_range = if i > 0 {
                            if i > max_positive[kind].0 {
                                max_positive[kind] = (i, line);
                            }
                            false
                        } else {
                            i == 0 || i.unsigned_abs() as usize > count
                        };
                        if out_of_range {
                            return Err(SceneError::IndexOutOfRange {
                                path: path.to_path_buf(),
                                line,
                                kind: KINDS[kind],
                                index: i,
                                count,
                            });
                        }
                    }
                }
                scan.polylines |= key == "l";
                if key == "f" && corners < 3 {
                    return Err(bad(
                        line,
                        format!("face with {corners} corners (needs at least 3)"),
                    ));
                }
            }
            "usemtl" => {
                // The name as tobj reads it: everything after the line's first space.
                let name = raw.split_once(' ').unwrap_or_default().1.trim();
                if name.is_empty() {
                    return Err(bad(
                        line,
                        "usemtl needs a material name after a space".into(),
                    ));
                }
                scan.usemtl.push((line, name.to_string()));
            }
            "mtllib" => {
                scan.first_mtllib.get_or_insert(line);
            }
            _ => {}
        }
    }
    for (kind, &(i, line)) in max_positive.iter().enumerate() {
        if i as u64 > counts[kind] as u64 {
            return Err(SceneError::IndexOutOfRange {
                path: path.to_path_buf(),
                line,
                kind: KINDS[kind],
                index: i,
                count: counts[kind],
            });
        }
    }
    Ok(scan)
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
