//! Vertex attributes read as floats from any component type glTF allows for them, with
//! `KHR_mesh_quantization`'s (gltfpack writes them): positions, normals, tangents, texture
//! coordinates and colours as BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT, normalized or not,
//! besides FLOAT. The
//! `gltf` crate's readers take positions and normals for floats whatever the accessor holds (and
//! stop on signed texture coordinates), so these are decoded here. Normalized integers become
//! floats as glTF says: c / 255 and c / 65535 unsigned, max(c / 127, -1) and max(c / 32767, -1)
//! signed; integers that are not normalized keep their values, which the node's transform (for
//! positions) or the texture transform (for texture coordinates) scales back.

use glam::{DMat4, DVec3, Vec3, Vec4};
use gltf::accessor::DataType;

/// The `N`-component elements of the vertex attribute `accessor` as floats, for `semantic` (its
/// name in errors). The accessor lies inside its buffer (`nodes::check_accessor`).
pub(super) fn read_floats<const N: usize>(
    accessor: &gltf::Accessor,
    buffers: &[Vec<u8>],
    semantic: &str,
) -> Result<Vec<[f32; N]>, String> {
    let index = accessor.index();
    let dimensions = accessor.dimensions();
    if dimensions.multiplicity() != N {
        return Err(format!(
            "{semantic} accessor {index} is {dimensions:?}, not a vector of {N} components"
        ));
    }
    let data_type = accessor.data_type();
    let normalized = accessor.normalized();
    let decode: fn(&[u8], bool) -> f32 = match data_type {
        DataType::F32 => |b, _| f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        DataType::I8 => |b, n| scaled(f32::from(b[0] as i8), n, 127.0),
        DataType::U8 => |b, n| scaled(f32::from(b[0]), n, 255.0),
        DataType::I16 => |b, n| scaled(f32::from(i16::from_le_bytes([b[0], b[1]])), n, 32767.0),
        DataType::U16 => |b, n| scaled(f32::from(u16::from_le_bytes([b[0], b[1]])), n, 65535.0),
        DataType::U32 => {
            return Err(format!(
                "{semantic} accessor {index} is UNSIGNED_INT, which glTF does not allow for it"
            ))
        }
    };
    let Some(view) = accessor.view() else {
        return Err(format!("accessor {index} has no buffer view"));
    };
    let buffer = buffers
        .get(view.buffer().index())
        .map_or(&[][..], Vec::as_slice);
    let component = data_type.size();
    let stride = view.stride().unwrap_or(accessor.size());
    let first = view.offset() + accessor.offset();
    let element = |i: usize| -> Option<[f32; N]> {
        let at = first + i * stride;
        let bytes = buffer.get(at..at + N * component)?;
        let mut out = [0.0; N];
        for (c, value) in out.iter_mut().enumerate() {
            *value = decode(&bytes[c * component..], normalized);
        }
        Some(out)
    };
    (0..accessor.count())
        .map(|i| element(i).ok_or_else(|| format!("accessor {index} ends past its buffer")))
        .collect()
}

/// An integer component as glTF reads it: divided by its type's largest value where the
/// accessor is normalized (signed ones clamped at -1), as it is otherwise.
fn scaled(value: f32, normalized: bool, largest: f32) -> f32 {
    if normalized {
        (value / largest).max(-1.0)
    } else {
        value
    }
}

/// The primitive's COLOR_0 as linear RGBA (alpha 1 where it is RGB), float or normalized
/// UNSIGNED_BYTE / UNSIGNED_SHORT; `None` where it has none.
pub(super) fn read_colours(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
) -> Result<Option<Vec<Vec4>>, String> {
    let Some(accessor) = primitive.get(&gltf::Semantic::Colors(0)) else {
        return Ok(None);
    };
    Ok(Some(if accessor.dimensions().multiplicity() == 3 {
        let rgb = read_floats::<3>(&accessor, buffers, "COLOR_0")?;
        rgb.into_iter().map(|c| Vec3::from(c).extend(1.0)).collect()
    } else {
        let rgba = read_floats::<4>(&accessor, buffers, "COLOR_0")?;
        rgba.into_iter().map(Vec4::from).collect()
    }))
}

/// The primitive's TANGENT in world space: xyz through `world_from_node`, normalized, w the
/// bitangent's sign, negated where the transform mirrors (the cross product of the normal and
/// the tangent turns with it); `None` where it has none.
pub(super) fn read_tangents(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world_from_node: &DMat4,
) -> Result<Option<Vec<Vec4>>, String> {
    let Some(accessor) = primitive.get(&gltf::Semantic::Tangents) else {
        return Ok(None);
    };
    let mirror = world_from_node.determinant().signum() as f32;
    let tangents = read_floats::<4>(&accessor, buffers, "TANGENT")?;
    Ok(Some(
        tangents
            .into_iter()
            .map(|[x, y, z, w]| {
                let t = world_from_node.transform_vector3(DVec3::new(x.into(), y.into(), z.into()));
                let sign = if w < 0.0 { -mirror } else { mirror };
                t.normalize_or_zero().as_vec3().extend(sign)
            })
            .collect(),
    ))
}

/// The primitive's NORMAL in world space, through the inverse transpose of `world_from_node`,
/// normalized; empty where it has none, where its count is not `count`, or where a normal is
/// zero (degenerate in the file: the mesh is left faceted, as for OBJ).
pub(super) fn read_normals(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world_from_node: &DMat4,
    count: usize,
) -> Result<Vec<Vec3>, String> {
    let Some(accessor) = primitive.get(&gltf::Semantic::Normals) else {
        return Ok(Vec::new());
    };
    let normal_from_node = world_from_node.inverse().transpose();
    let normals: Vec<Vec3> = read_floats::<3>(&accessor, buffers, "NORMAL")?
        .into_iter()
        .map(|n| {
            let n = normal_from_node.transform_vector3(DVec3::from(n.map(f64::from)));
            n.normalize_or_zero().as_vec3()
        })
        .collect();
    Ok(
        if normals.len() == count && !normals.contains(&Vec3::ZERO) {
            normals
        } else {
            Vec::new()
        },
    )
}
