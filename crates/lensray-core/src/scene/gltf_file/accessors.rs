//! Vertex attributes read as floats from any component type glTF allows for them, with
//! `KHR_mesh_quantization`'s (gltfpack writes them): positions, normals and texture coordinates
//! as BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT, normalized or not, besides FLOAT. The
//! `gltf` crate's readers take positions and normals for floats whatever the accessor holds (and
//! stop on signed texture coordinates), so these are decoded here. Normalized integers become
//! floats as glTF says: c / 255 and c / 65535 unsigned, max(c / 127, -1) and max(c / 32767, -1)
//! signed; integers that are not normalized keep their values, which the node's transform (for
//! positions) or the texture transform (for texture coordinates) scales back.

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
