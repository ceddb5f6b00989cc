//! Start-up: the window, the viewer drawing into it, the panel and the path that adds the
//! samples; and the GPU paths that follow the lens (a real lens needs a traversal path).

use std::sync::Arc;

use anyhow::{Context as _, Result};
use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::Window;

use super::{App, Gui};
use crate::paths;
use crate::paths::PathKind;
use crate::preview::cpu_feed::CpuFeed;
use lensray_vulkan::{Estimator, Viewer};

/// The GPU paths the window draws with: the one for thin lenses (asked for, or `auto`'s pick)
/// and the traversal path that traces real lenses where that one cannot (the hybrid, whose
/// shortcuts bound thin-lens rays only, and `auto`'s raster path, which would show a real
/// lens's first-order model). The panel may switch lenses at any frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct GpuPaths {
    thin: PathKind,
    /// The renderer's traversal, as a path.
    traced: PathKind,
    /// `--path raster` asked for: a real lens keeps it and shows its first-order model (with
    /// a notice, as `lensray render` does).
    raster_asked: bool,
    in_use: PathKind,
    /// The raster path's notice for a real lens was given.
    first_order_noticed: bool,
}

impl GpuPaths {
    /// The path for a camera with (`real`) or without a real lens.
    fn for_lens(&self, real: bool) -> PathKind {
        match self.thin {
            PathKind::Hybrid if real => self.traced,
            PathKind::Raster if real && !self.raster_asked => self.traced,
            thin => thin,
        }
    }
}

impl Gui {
    /// The panel's egui context and its winit state for `window`.
    fn new(window: &Window) -> Self {
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        Gui { ctx, state }
    }
}

impl App {
    /// Opens the window, the viewer that draws into it and the panel, and picks the path that
    /// adds the samples (the CPU path, or the GPU paths); says which on stderr.
    pub(super) fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let window = self.create_window(event_loop)?;
        let display = window.display_handle().context("window display handle")?;
        let handle = window.window_handle().context("window handle")?;
        let viewer = Viewer::new(
            &self.config.viewer,
            display.as_raw(),
            handle.as_raw(),
            &self.config.description.scene,
        )
        .context("preview")?;
        self.gui = Some(Gui::new(&window));
        let mut viewer = viewer;
        let path = if self.config.cpu_path {
            self.cpu_feed = Some(CpuFeed::new(&self.config.description.scene)?);
            "path cpu (samples traced on the CPU, shown by the GPU)".to_string()
        } else {
            self.pick_gpu_paths(&mut viewer)?
        };
        eprintln!("preview: {path} on {}", viewer.device_name());
        self.counters_at_start = viewer.renderer_mut().counters();
        self.viewer = Some(viewer);
        self.window = Some(window);
        Ok(())
    }

    /// Creates the window at the settings' image size, titled with the scene.
    fn create_window(&self, event_loop: &ActiveEventLoop) -> Result<Arc<Window>> {
        let settings = self.config.rig.settings();
        let (width, height) = (
            settings
                .image
                .width
                .unwrap_or(lensray_core::settings::DEFAULT_WIDTH),
            settings
                .image
                .height
                .unwrap_or(lensray_core::settings::DEFAULT_HEIGHT),
        );
        let attributes = Window::default_attributes()
            .with_title(format!(
                "lensray preview: {}",
                self.config.description.source
            ))
            .with_inner_size(PhysicalSize::new(width, height));
        Ok(Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot create the window")?,
        ))
    }

    /// Picks the GPU paths for the starting shot (as asked, or `auto`'s pick, which only a
    /// traversal path makes with a real lens) and sets the viewer's estimator; returns the
    /// path as the start-up line names it.
    fn pick_gpu_paths(&mut self, viewer: &mut Viewer) -> Result<String> {
        let shot = self
            .config
            .rig
            .shot(&self.config.description.scene)
            .context("camera")?;
        let real_lens = shot.camera.lens.real().cloned();
        let asked = self.config.viewer.estimator;
        if let (Some(real), Estimator::Hybrid) = (&real_lens, asked) {
            anyhow::bail!(
                "--path hybrid does not trace real lenses (--lens {}): use cpu, rayquery, rtpipeline, software or auto",
                real.name()
            );
        }
        let renderer = viewer.renderer_mut();
        let (kind, why) = if self.config.viewer.gpu.traversal.is_some() {
            let traversal = renderer.traversal();
            (traversal.to_string(), "asked for".to_string())
        } else if asked != Estimator::Traced
            || real_lens.is_some()
            || shot.render.noise_threshold.is_some()
        {
            // auto with a real lens or a noise threshold: only the traversal paths trace its
            // rays and sample adaptively (as `render`).
            let (kind, why) = paths::pick_traversal(renderer, &shot)?;
            (kind.to_string(), why)
        } else {
            // auto: any GPU path, the hybrid and raster paths included.
            let (kind, why) = paths::pick_path(renderer, &shot)?;
            viewer.use_estimator(kind.estimator());
            self.config.viewer.estimator = kind.estimator();
            (kind.to_string(), why)
        };
        let traced = PathKind::of_traversal(viewer.renderer_mut().traversal());
        let thin = match self.config.viewer.estimator {
            Estimator::Hybrid => PathKind::Hybrid,
            Estimator::Raster => PathKind::Raster,
            Estimator::Traced => traced,
        };
        let raster_asked = asked == Estimator::Raster;
        self.paths = Some(GpuPaths {
            thin,
            traced,
            raster_asked,
            in_use: thin,
            first_order_noticed: false,
        });
        Ok(match asked {
            Estimator::Hybrid => {
                format!("path hybrid (traces with {kind}: {why}; plan made on the device)")
            }
            Estimator::Raster => format!("path raster (shadow rays with {kind}: {why})"),
            Estimator::Traced => format!("path {kind} ({why})"),
        })
    }

    /// Draws the lens of `real` (a real lens or not) with the path for it from now on; says so
    /// when the path changes. Called before `prepare` (which makes the path's passes), and
    /// after the panel where only a traversal path is asked for (which needs no pass of its
    /// own).
    pub(super) fn follow_lens(&mut self, real: Option<&str>) {
        let (Some(paths), Some(viewer)) = (self.paths.as_mut(), self.viewer.as_mut()) else {
            return;
        };
        let want = paths.for_lens(real.is_some());
        if want == paths.in_use {
            return;
        }
        viewer.use_estimator(want.estimator());
        paths.in_use = want;
        self.converged = false;
        match real {
            Some(name) => eprintln!(
                "preview: path {want} (path {} does not trace real lenses: lens {name})",
                paths.thin
            ),
            None => eprintln!("preview: path {want} again (a thin lens)"),
        }
    }

    /// A real lens (`name`) in this frame's shot: switches to the path that traces it where
    /// the one in use cannot, and gives the raster path's first-order notice once.
    pub(super) fn follow_real_lens(&mut self, name: &str) {
        // A real lens picked in this frame: a traversal path traces it (no pass to make).
        if self.paths.is_some_and(|p| p.for_lens(true) != p.in_use) {
            self.follow_lens(Some(name));
        }
        if let Some(paths) = self
            .paths
            .as_mut()
            .filter(|p| p.in_use == PathKind::Raster && !p.first_order_noticed)
        {
            paths.first_order_noticed = true;
            eprintln!("{}", first_order_notice(name));
        }
    }
}

/// What `lensray render --path raster` says of a real lens (`paths::open`).
fn first_order_notice(lens: &str) -> String {
    format!(
        "notice: --path raster renders lens {lens} by its first-order model (a thin lens at its entrance pupil): no aberrations, distortion or vignetting"
    )
}
