//! How much of a shot is in focus: what the hybrid path's gain depends on besides the aperture.
//! From the CPU's depth AOV (one ray per pixel centre through the lens centre) and the camera's
//! circle of confusion at each depth.

use serde::Serialize;

use lensray_core::reference::Renderer as CpuRenderer;
use lensray_core::settings::{RenderSettings, Shading, Shot};

/// Circles of confusion under this radius (pixels) are in focus: the hybrid's shortcut rule.
const IN_FOCUS_COC: f32 = lensray_core::interface::HYBRID_SHORTCUT_COC;

#[derive(Clone, Copy, Debug, Serialize)]
pub struct FocusInfo {
    /// Share of the image's pixels that see a surface with a circle of confusion under half a
    /// pixel.
    pub in_focus_fraction: f64,
    /// Share of the pixels that see no surface (the background).
    pub background_fraction: f64,
    /// The mean and the largest circle of confusion (radius, pixels) of the surfaces seen.
    pub mean_coc_pixels: f64,
    pub largest_coc_pixels: f32,
}

impl FocusInfo {
    /// How much of `shot` is in focus, from its depth AOV rendered by `cpu`.
    pub fn of(cpu: &CpuRenderer, shot: &Shot) -> Self {
        let camera = &shot.camera;
        let depth_shot = Shot {
            camera: camera.clone(),
            render: RenderSettings {
                shading: Shading::Depth,
                spp: 1,
                ..shot.render
            },
        };
        let (depth, _) = cpu.render(&depth_shot, &mut |_, _| {});
        let pixels = depth.pixels.len().max(1) as f64;
        let (mut in_focus, mut background, mut largest, mut sum) = (0usize, 0usize, 0f32, 0f64);
        let coc_lens = lensray_core::camera::CocLens::of(camera);
        for (i, z) in depth.pixels.iter().map(|p| p.x).enumerate() {
            // The AOV is 0 where nothing is seen.
            if z <= 0.0 {
                background += 1;
                continue;
            }
            let (x, y) = (i as u32 % camera.width, i as u32 / camera.width);
            let coc = coc_lens.radius_pixels(glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5), z);
            largest = largest.max(coc);
            sum += f64::from(coc);
            in_focus += usize::from(coc < IN_FOCUS_COC);
        }
        Self {
            in_focus_fraction: in_focus as f64 / pixels,
            background_fraction: background as f64 / pixels,
            mean_coc_pixels: sum / (depth.pixels.len() - background).max(1) as f64,
            largest_coc_pixels: largest,
        }
    }
}
