//! The lens's own light in the preview (`--flare`, `--starburst`, the lens panel's toggles):
//! once the final view has converged, its image is read back and the flare drawn on it as
//! `render` draws it (the ghosts traced on the viewer's device; on the CPU with the CPU path),
//! and the light it added is handed to the final view, which adds it before exposure. A new
//! shot, other switches or another view take it away until the view converges again.

use anyhow::{Context, Result};

use super::App;
use crate::lens_flare;
use crate::preview::view::ViewMode;
use lensray_core::camera::flare::ghosts::FlareLens;
use lensray_core::camera::flare::FlareSwitches;
use lensray_core::film::Image;
use lensray_core::settings::Shot;
use lensray_vulkan::GhostRequest;

/// The flare the final view adds: what it was drawn for, and its light.
pub(super) struct ShownFlare {
    switches: FlareSwitches,
    shot: Shot,
    pub(super) light: Image,
}

impl ShownFlare {
    /// Whether it is the flare of `shot`.
    pub(super) fn is_of(&self, shot: &Shot) -> bool {
        &self.shot == shot
    }
}

impl App {
    /// Keeps the final view's flare that of `shot` under the rig's switches; returns whether
    /// it changed (a frame must show it).
    pub(super) fn follow_flare(&mut self, shot: &Shot) -> Result<bool> {
        let switches = lens_flare::switches(self.config.rig.settings());
        let wanted = (switches.ghosts || switches.starburst) && self.panel.view == ViewMode::Final;
        let current = self
            .flare
            .as_ref()
            .is_some_and(|f| f.switches == switches && f.is_of(shot));
        if current && wanted {
            return Ok(false);
        }
        let viewer = self.viewer.as_mut().context("no viewer")?;
        let dropped = self.flare.take().is_some();
        if dropped {
            viewer.set_flare(None)?;
        }
        if !(wanted && self.converged) {
            return Ok(dropped);
        }
        let flare = match lens_flare::flare_for(self.config.rig.settings(), shot) {
            Ok(Some(flare)) => flare,
            Ok(None) => return Ok(dropped),
            Err(e) => {
                if !self.said_flare {
                    eprintln!("flare: {e:#}");
                    self.said_flare = true;
                }
                return Ok(dropped);
            }
        };
        let Some(image) = viewer.read_accumulation()? else {
            return Ok(dropped);
        };
        let exposure = self.config.rig.exposure(&shot.camera)?.display.exposure;
        let scene = self
            .posed
            .as_ref()
            .unwrap_or(&self.config.description.scene);
        let points = lens_flare::point_sources(&scene.lights, &shot.camera);
        let mut flared = image.clone();
        if self.cpu_feed.is_some() {
            flare.apply(&mut flared, exposure, &points);
        } else {
            let renderer = viewer.renderer_mut();
            let mut trace = |lens: &FlareLens, degrees, wavelengths: &[f64], grid, bins| {
                let request = GhostRequest::new(degrees, wavelengths, grid, bins);
                renderer.ghost_light(&shot.camera, lens, &request)
            };
            flare.apply_traced(&mut flared, exposure, &points, &mut trace)?;
        }
        let light = Image {
            width: image.width,
            height: image.height,
            pixels: flared
                .pixels
                .iter()
                .zip(&image.pixels)
                .map(|(a, b)| *a - *b)
                .collect(),
        };
        viewer.set_flare(Some(&light))?;
        self.flare = Some(ShownFlare {
            switches,
            shot: shot.clone(),
            light,
        });
        Ok(true)
    }
}
