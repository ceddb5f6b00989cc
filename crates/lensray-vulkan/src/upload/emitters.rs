//! The emissive triangles as the shaders draw them (shaders/include/emitters.glsl): lensray-core's
//! `scene::emitters::EmitterDistribution` over the flattened triangles, the order the CPU
//! reference numbers them in, so both draw the same triangle and point from the same sample.

use glam::Vec3;
use lensray_core::interface::TRI_MATERIAL_MASK;
use lensray_core::scene::emitters::EmitterDistribution;
use lensray_core::scene::Scene;

use super::motion::vertex_moves;
use crate::core::buffer::MIN_BUFFER_SIZE;

/// The least length of each array: a shorter one's buffer is padded to `MIN_BUFFER_SIZE` bytes,
/// and the shaders' `emitter_cdf.length()` (the last entry says whether anything emits, the
/// bisection's bound) would count the padding.
const MIN_LEN: usize = (MIN_BUFFER_SIZE as usize).div_ceil(size_of::<f32>());

/// The arrays of the scene group's `emitter_*` bindings, each at least one element long.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct FlatEmitters {
    pub triangles: Vec<u32>,
    /// A scene without emitters holds one 0 (a drawn cdf ends at 1).
    pub cdf: Vec<f32>,
    pub area_pdf: Vec<f32>,
}

impl FlatEmitters {
    /// The emitters among the flattened triangles (`indices` into `positions`, materials in
    /// `tri_info`) of `scene`: those that stand still while the shutter is open (a moving one
    /// lights what a BRDF's draw meets it from, as on the CPU).
    pub(crate) fn new(
        positions: &[[f32; 4]],
        indices: &[u32],
        tri_info: &[u32],
        scene: &Scene,
    ) -> Self {
        let triangles: Vec<[Vec3; 3]> = indices
            .chunks_exact(3)
            .map(|t| [0, 1, 2].map(|k| Vec3::from_slice(&positions[t[k] as usize][..3])))
            .collect();
        let material = |t: usize| &scene.materials[(tri_info[t] & TRI_MATERIAL_MASK) as usize];
        let moves =
            |t: usize| (0..3).any(|k| vertex_moves(&positions[indices[3 * t + k] as usize]));
        let d = EmitterDistribution::new(&triangles, |t| match moves(t) {
            true => Vec3::ZERO,
            false => material(t).emission,
        });
        if d.is_empty() {
            // Shaders index non-empty arrays; a cdf of 0 says nothing emits.
            return Self {
                triangles: vec![0; MIN_LEN],
                cdf: vec![0.0; MIN_LEN],
                area_pdf: vec![0.0; MIN_LEN],
            };
        }
        Self {
            triangles: padded(d.triangles, 0),
            // Entries of 1 past the last draw nothing: no u.x < 1 lies at or above them.
            cdf: padded(d.cdf, 1.0),
            // Triangles past the last one are never looked up.
            area_pdf: padded(d.area_pdf, 0.0),
        }
    }
}

/// `array` extended with `fill` to at least `MIN_LEN` elements.
fn padded<T: Copy>(mut array: Vec<T>, fill: T) -> Vec<T> {
    if array.len() < MIN_LEN {
        array.resize(MIN_LEN, fill);
    }
    array
}
