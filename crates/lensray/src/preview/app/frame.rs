//! One frame: the lens's path, the window's size, the held keys' motion, the panel, the shot,
//! the draw (with the CPU path's samples), then what the frame reports.

use std::time::Instant;

use anyhow::{Context as _, Result};
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::App;
use crate::focus;
use crate::preview::cpu_feed::Snapshot;
use crate::preview::panel::PanelStats;
use lensray_core::camera::Camera;
use lensray_core::settings::Shot;
use lensray_vulkan::{FrameRequest, FrameResult, HostSamples, OverlayFrame};

impl App {
    /// Draws a frame of the current shot, after the input and the panel changed it.
    pub(super) fn frame(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        // A lens changed since the last frame: its path, before `prepare` makes its passes.
        let real_name = self.config.rig.readout().real.map(|r| r.name);
        self.follow_lens(real_name.as_deref());
        let (Some(window), Some(viewer)) = (self.window.clone(), self.viewer.as_mut()) else {
            return Ok(());
        };
        let size = window.inner_size();
        let Some([width, height]) = viewer.prepare([size.width, size.height])? else {
            self.minimised = true;
            return Ok(());
        };
        self.minimised = false;
        let now = Instant::now();
        self.fly_held(now);

        // The panel first: it may change the lens before this frame's camera is built.
        let overlay = self.run_panel(&window)?;
        for action in self.panel.take_actions() {
            self.act(event_loop, action)?;
        }
        // The frame of a keyframed shot after the panel's slider and keys: its camera.
        self.follow_frame(Instant::now());

        self.config.rig.set_image_size(width, height);
        let rig = &mut self.config.rig;
        let resolved = match rig.shot(&self.config.description.scene) {
            Ok(shot) => {
                rig.accept();
                shot
            }
            Err(e) => {
                eprintln!("camera: {e} (the change is undone)");
                rig.revert();
                rig.shot(&self.config.description.scene).context("camera")?
            }
        };
        let resolved = self.moving(resolved)?;
        if let Some(real) = resolved.camera.lens.real() {
            self.follow_real_lens(real.name());
        }
        // Exposure and tone map change what the final view shows, not its samples.
        let display = self
            .config
            .rig
            .exposure(&resolved.camera)
            .context("exposure")?
            .display;
        let restart = self.last.as_ref() != Some(&resolved);
        let changed = restart
            || Some(self.panel.view) != self.shown_view
            || Some(display) != self.shown_display;
        let pick = self.take_pick(width, height);
        let picked_camera = pick.map(|p| (p, resolved.camera.clone()));
        let snapshot = self.cpu_samples(&resolved, restart)?;
        let host = self.cpu_feed.as_ref().map(|_| HostSamples {
            sums: snapshot.as_ref().map(|s| s.sums.as_slice()),
            spp: self.cpu_spp,
            converged: self.cpu_converged,
            adaptive_active: self.cpu_active,
        });
        let viewer = self.viewer.as_mut().context("no viewer")?;
        let result = viewer.draw(FrameRequest {
            shot: &resolved,
            view: self.panel.view.code(),
            display,
            restart,
            target_spp: self.panel.target_spp,
            pick,
            overlay: Some(overlay),
            host,
        })?;
        if result.drawn {
            self.shown_display = Some(display);
            self.record_drawn(&result, changed, resolved, now, [width, height]);
        }
        if let Some(shot) = self.last.clone() {
            if self.follow_flare(&shot)? {
                window.request_redraw();
            }
        }
        if let Some(depth) = result.picked_depth {
            match picked_camera {
                Some((pixel, camera)) if self.plane_pick => {
                    self.plane_point(depth, pixel, &camera);
                }
                _ => self.focus_on_pick(depth),
            }
        }
        if self
            .config
            .frames
            .is_some_and(|limit| self.log.frames() >= limit)
        {
            self.exit(event_loop);
        }
        Ok(())
    }

    /// Moves the camera along the held fly keys for the time since the last frame (at most
    /// 0.1 s, so a stalled frame does not jump).
    fn fly_held(&mut self, now: Instant) {
        let fly = self.input.fly_direction();
        if fly != glam::Vec3::ZERO {
            let seconds = (now - self.last_fly).as_secs_f64().min(0.1);
            self.config.rig.fly(fly, seconds);
        }
        self.last_fly = now;
    }

    /// Runs the panel on this frame's input (it may change the rig and queue actions) and
    /// returns its shapes for the viewer to draw over the image.
    fn run_panel(&mut self, window: &Window) -> Result<OverlayFrame> {
        let gui = self.gui.as_mut().context("no GUI")?;
        let viewer = self.viewer.as_ref().context("no viewer")?;
        let raw_input = gui.state.take_egui_input(window);
        let stats = PanelStats {
            spp: self.spp,
            device: viewer.device_name(),
            times: self.log.last_times(),
            frame_ms: self.log.last_frame_ms(),
            lens_summary: self
                .last
                .as_ref()
                .and_then(|shot| shot.camera.lens.real())
                .map(|real| real.summary()),
            ev100: self
                .last
                .as_ref()
                .and_then(|shot| self.config.rig.exposure(&shot.camera).ok())
                .and_then(|e| e.physical)
                .map(|p| p.ev100),
        };
        let rig = &mut self.config.rig;
        let mut clock = self.config.playback.as_mut().map(|p| &mut p.clock);
        let panel = &mut self.panel;
        let output = gui.ctx.run_ui(raw_input, |ui| {
            panel.ui(ui.ctx(), rig, clock.as_deref_mut(), &stats);
        });
        gui.state
            .handle_platform_output(window, output.platform_output);
        Ok(OverlayFrame {
            primitives: gui.ctx.tessellate(output.shapes, output.pixels_per_point),
            textures: output.textures_delta,
            pixels_per_point: output.pixels_per_point,
        })
    }

    /// The pending pick as a pixel of the `width` x `height` image (`None` outside it).
    fn take_pick(&mut self, width: u32, height: u32) -> Option<[u32; 2]> {
        self.pending_pick.take().and_then(|at| {
            let (x, y) = (at.x.floor(), at.y.floor());
            (x >= 0.0 && y >= 0.0 && (x as u32) < width && (y as u32) < height)
                .then_some([x as u32, y as u32])
        })
    }

    /// With the CPU path: asks its worker for `shot` and takes its newest samples, counting
    /// the samples the shot has (none after a restart).
    fn cpu_samples(&mut self, shot: &Shot, restart: bool) -> Result<Option<Snapshot>> {
        let snapshot = match self.cpu_feed.as_mut() {
            Some(feed) => {
                feed.request(shot, self.panel.target_spp);
                feed.take_latest()?
            }
            None => None,
        };
        if restart {
            self.cpu_spp = 0;
            self.cpu_converged = false;
            self.cpu_active = None;
        }
        if let Some(snapshot) = &snapshot {
            self.cpu_spp = snapshot.spp;
            self.cpu_converged = snapshot.converged;
            self.cpu_active = snapshot.adaptive_active;
        }
        Ok(snapshot)
    }

    /// Records a drawn frame: when its image changed, a scripted size reached, the shot it
    /// drew, its times and the samples it reached.
    fn record_drawn(
        &mut self,
        result: &FrameResult,
        changed: bool,
        current: Shot,
        now: Instant,
        [width, height]: [u32; 2],
    ) {
        if changed {
            self.log.shown(Instant::now());
        }
        self.shown_view = Some(self.panel.view);
        if self
            .awaiting_size
            .is_some_and(|(size, _)| size == [width, height])
        {
            self.awaiting_size = None;
        }
        self.last = Some(current);
        self.log
            .record(now, result.times, u64::from(width) * u64::from(height));
        self.spp = result.spp;
        self.converged = result.converged;
        self.adaptive_active = result.adaptive_active;
    }

    /// A Shift+clicked surface at view depth `depth` under `pixel` of `camera`: the third lays
    /// the plane of focus through the three.
    fn plane_point(&mut self, depth: Option<f32>, pixel: [u32; 2], camera: &Camera) {
        self.converged = false;
        let Some(z) = depth else {
            eprintln!("focus plane: nothing under the cursor (points so far are kept)");
            return;
        };
        let point = camera
            .world_from_camera
            .transform_point3(focus::pixel_point(camera, pixel, z));
        self.plane_points.push(point.as_dvec3());
        let n = self.plane_points.len();
        if n < 3 {
            eprintln!("focus plane: point {n} of 3 at {point:.3}");
            return;
        }
        let points = [
            self.plane_points[0],
            self.plane_points[1],
            self.plane_points[2],
        ];
        self.plane_points.clear();
        match self.config.rig.lay_focus_plane(&points, camera) {
            Ok(plane) => eprintln!("focus plane: {}", focus::describe(&plane)),
            Err(e) => eprintln!("focus plane: {e}"),
        }
    }

    /// Focuses at the picked view depth (`None`: nothing under the cursor), no nearer than
    /// the lens reaches, and says where.
    fn focus_on_pick(&mut self, depth: Option<f32>) {
        // The new focus shows from the next frame on.
        self.converged = false;
        match depth {
            Some(d) => match self.config.rig.set_focus_distance(f64::from(d)) {
                Some(focus) if focus > f64::from(d) => eprintln!(
                    "focus: {focus:.4} (the nearest the lens focuses; the view depth under \
                     the cursor is {d:.4})"
                ),
                _ => eprintln!("focus: {d:.4} (view depth under the cursor)"),
            },
            None => eprintln!("focus: nothing under the cursor to focus on"),
        }
    }
}
