//! The emissive triangles as the shaders draw them (shaders/include/emitters.glsl): lensray-core's
//! `scene::emitters::EmitterDistribution` over the flattened triangles, the order the CPU
//! reference numbers them in, so both draw the same triangle and point from the same sample.

use glam::Vec3;
use lensray_core::interface::TRI_MATERIAL_MASK;
use lensray_core::scene::emitters::EmitterDistribution;
use lensray_core::scene::Scene;

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
    /// `tri_info`) of `scene`.
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
        let d = EmitterDistribution::new(&triangles, |t| material(t).emission);
        if d.is_empty() {
            // Shaders index non-empty arrays; a cdf of 0 says nothing emits.
            return Self {
                triangles: vec![0],
                cdf: vec![0.0],
                area_pdf: vec![0.0],
            };
        }
        Self {
            triangles: d.triangles,
            cdf: d.cdf,
            area_pdf: d.area_pdf,
        }
    }
}
