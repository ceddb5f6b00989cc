//! The textured scene as Wavefront OBJ + MTL: per mesh an `o`, its `v`, `vt` and `vn` (one of
//! each per vertex, so that every corner is `i/i/i`) and its faces; per material `Kd`, `map_Kd`
//! and, where the material has a coverage texture, `d` and `map_d`.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Context;

use super::TexturedScene;
use crate::scene::AlphaMode;

/// The MTL text: `Kd` (linear RGB), `map_Kd` (sRGB) and `map_d` (the image's alpha).
fn mtl_text(textured: &TexturedScene) -> String {
    let mut out =
        String::from("# lensray materials: diffuse Kd times map_Kd, coverage d times map_d\n");
    for m in &textured.scene.materials {
        let _ = writeln!(out, "\nnewmtl {}", m.name);
        let _ = writeln!(out, "Kd {} {} {}", m.diffuse.x, m.diffuse.y, m.diffuse.z);
        if let Some(t) = m.diffuse_texture {
            let _ = writeln!(out, "map_Kd {}", textured.images[t.texture as usize].file);
        }
        if m.alpha_mode != AlphaMode::Opaque {
            if matches!(m.alpha_mode, AlphaMode::Mask { .. }) {
                // MTL says nothing of masks: lensray cuts a map_d surface stochastically.
                let _ = writeln!(out, "# the glTF masks this surface; map_d blends it");
            }
            let _ = writeln!(out, "d {}", m.alpha);
            if let Some(t) = m.alpha_texture {
                let _ = writeln!(out, "map_d {}", textured.images[t.texture as usize].file);
            }
        }
    }
    out
}

/// The OBJ text, its materials in `mtl`.
fn obj_text(textured: &TexturedScene, mtl: &str) -> String {
    let scene = &textured.scene;
    let mut out = format!(
        "# lensray generate textured: {} meshes, {} triangles\n# vt is (u, 1 - v) of glTF's top-left texture coordinates (OBJ's v runs up)\nmtllib {mtl}\n",
        scene.meshes.len(),
        scene.triangle_count()
    );
    let mut base = 1;
    for mesh in &scene.meshes {
        let _ = writeln!(out, "o {}", mesh.name);
        for p in &mesh.positions {
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
        }
        for t in &mesh.texcoords {
            let _ = writeln!(out, "vt {} {}", t.x, 1.0 - t.y);
        }
        for n in &mesh.normals {
            let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
        }
        let mut current = None;
        for (t, &m) in mesh.triangles.iter().zip(&mesh.material_ids) {
            if current != Some(m) {
                let _ = writeln!(out, "usemtl {}", scene.materials[m as usize].name);
                current = Some(m);
            }
            let [a, b, c] = t.map(|i| i as usize + base);
            let _ = writeln!(out, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}");
        }
        base += mesh.positions.len();
    }
    out
}

/// Writes `NAME.obj` and `NAME.mtl` into `dir`; returns their names.
pub(super) fn write_obj_with_maps(
    textured: &TexturedScene,
    dir: &Path,
    name: &str,
) -> anyhow::Result<Vec<String>> {
    let (obj, mtl) = (format!("{name}.obj"), format!("{name}.mtl"));
    std::fs::write(dir.join(&mtl), mtl_text(textured))
        .with_context(|| format!("cannot write {mtl}"))?;
    std::fs::write(dir.join(&obj), obj_text(textured, &mtl))
        .with_context(|| format!("cannot write {obj}"))?;
    Ok(vec![mtl, obj])
}
