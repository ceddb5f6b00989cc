//! Shading modes and per-render settings, defined once for the CPU and GPU paths.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::sampler::SamplerKind;

/// What a pixel shows. `Unlit` and `Lit` are traced through the thin lens; the rest are AOVs:
/// the raster G-buffer's content, the surface seen by the aperture-centre ray at each pixel centre.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Shading {
    /// Base colour of the first surface hit, or the background on a miss: pure visibility, the
    /// mode that validates depth of field.
    Unlit,
    /// Emission + f * E cos(theta) summed over the scene's lights (point, spot, directional;
    /// `scene::light`), each with a hard shadow, plus the environment (a uniform sky or a map)
    /// by multiple importance sampling of the environment and the BRDF; f is glTF's
    /// metallic-roughness BRDF (`reference::brdf`; Lambert for materials without a specular
    /// lobe). With `bounces` > 1, a path goes on from each surface in the direction its BRDF
    /// drew, and the surfaces it meets add their emission and their own direct light.
    Lit,
    /// Distance of the first hit along the view axis (camera z); 0 on a miss.
    Depth,
    /// World-space shading normal of the first hit, facing the viewer; 0 on a miss.
    Normal,
    /// Base colour of the first hit (the G-buffer's material colour); the background on a miss.
    Albedo,
}

impl Shading {
    pub const ALL: [Shading; 5] = [
        Self::Unlit,
        Self::Lit,
        Self::Depth,
        Self::Normal,
        Self::Albedo,
    ];

    /// The name `--shading` and `shading` take.
    pub fn name(self) -> &'static str {
        match self {
            Self::Unlit => "unlit",
            Self::Lit => "lit",
            Self::Depth => "depth",
            Self::Normal => "normal",
            Self::Albedo => "albedo",
        }
    }

    /// AOVs describe the surface seen through each pixel centre: one ray, no lens blur.
    pub fn is_aov(self) -> bool {
        matches!(self, Shading::Depth | Shading::Normal | Shading::Albedo)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Samples per pixel, >= 1.
    pub spp: u32,
    pub seed: u32,
    /// How the camera's samples are drawn.
    pub sampler: SamplerKind,
    pub shading: Shading,
    /// Linear RGB seen on a miss.
    pub background: Vec3,
    /// Radiance of a uniform sky lighting every surface (`lit`), linear RGB; zero: none (or the
    /// scene's environment map instead, `Scene::environment`).
    pub environment: Vec3,
    /// A camera ray that leaves the scene sees the scene's environment map rather than
    /// `background` (a map and no background given).
    pub environment_seen: bool,
    /// The surfaces a `lit` path shades, 1 ..= `MAX_BOUNCES`: 1 is direct light.
    pub bounces: u32,
    /// Every pixel draws the same camera samples (those of pixel (0, 0), offset to its own
    /// position: `sampler::shared_pixel_sampler`) instead of its own. The `raster` path's
    /// estimator, which projects the whole image through one lens point per pass; the other
    /// paths take it to reproduce that path. Off by default: shared lens samples show blur as
    /// ghost copies instead of noise (docs/raster.md).
    pub shared_samples: bool,
    /// Adaptive sampling (`film::adaptive`): a pixel stops taking samples once its estimated
    /// error is below this (positive, finite); `spp` is then each pixel's cap. `None`: every
    /// pixel takes `spp`.
    pub noise_threshold: Option<f32>,
}
