//! The lens panel (egui): the lens and the view to edit, a keyframed shot's frame slider, the
//! frame's timings to read, and the controls' help.

use std::path::PathBuf;
use std::time::Instant;

use super::bindings::{controls_help, Action};
use super::playback::PlaybackClock;
use super::rig::{
    CameraRig, LensChoice, LensReadout, PANEL_MAX_TILT_DEGREES, SENSOR_HEIGHT_RANGE_MM,
};
use super::view::ViewMode;
use lensray_core::film::tonemap::ToneMap;
use lensray_core::settings::ProjectionKind;
use lensray_vulkan::FrameTimes;

/// What the panel shows of the renderer.
pub struct PanelStats {
    pub spp: u32,
    pub device: String,
    pub times: Option<FrameTimes>,
    pub frame_ms: Option<f64>,
    /// The real lens's summary line (`RealLens::summary`) of the last frame's camera.
    pub lens_summary: Option<String>,
    /// The physical exposure's EV100 of the last frame's camera, where one is set.
    pub ev100: Option<f64>,
}

pub struct Panel {
    pub view: ViewMode,
    pub target_spp: u32,
    pub show_help: bool,
    /// Buttons pressed this frame, for the app to carry out.
    actions: Vec<Action>,
    screenshots: u32,
}

impl Panel {
    pub fn new(view: ViewMode, target_spp: u32) -> Self {
        Self {
            view,
            target_spp,
            show_help: false,
            actions: Vec::new(),
            screenshots: 0,
        }
    }

    pub fn take_actions(&mut self) -> Vec<Action> {
        std::mem::take(&mut self.actions)
    }

    /// The next free name for a `P` screenshot in the working directory.
    pub fn screenshot_path(&mut self) -> PathBuf {
        loop {
            self.screenshots += 1;
            let path = PathBuf::from(format!("lensray-preview-{:03}.png", self.screenshots));
            if !path.exists() {
                return path;
            }
        }
    }

    pub fn ui(
        &mut self,
        ctx: &egui::Context,
        rig: &mut CameraRig,
        clock: Option<&mut PlaybackClock>,
        stats: &PanelStats,
    ) {
        egui::Window::new("Lens")
            .default_pos([8.0, 8.0])
            .resizable(false)
            .show(ctx, |ui| {
                if let Some(clock) = clock {
                    self.shot_frames(ui, clock, rig.motion_blur());
                    ui.separator();
                }
                self.lens(ui, rig, stats);
                ui.separator();
                Self::movements(ui, rig);
                ui.separator();
                self.view_controls(ui);
                Self::exposure(ui, rig, stats);
                ui.separator();
                Self::timings(ui, stats, self.target_spp);
                ui.horizontal(|ui| {
                    if ui.button("Screenshot (P)").clicked() {
                        self.actions.push(Action::Screenshot);
                    }
                    if ui.button("Print camera (C)").clicked() {
                        self.actions.push(Action::PrintCamera);
                    }
                    if ui.button("Reset (R)").clicked() {
                        self.actions.push(Action::ResetCamera);
                    }
                    if ui.button("Help (H)").clicked() {
                        self.show_help = !self.show_help;
                    }
                });
            });
        if self.show_help {
            egui::Window::new("Controls")
                .default_pos([8.0, 380.0])
                .open(&mut self.show_help)
                .show(ctx, |ui| ui.monospace(controls_help()));
        }
    }

    /// A keyframed shot: the frame slider over the keyframes' range, play / pause and motion
    /// blur (`motion_blur`: whether it is on).
    fn shot_frames(&mut self, ui: &mut egui::Ui, clock: &mut PlaybackClock, motion_blur: bool) {
        let (first, last) = clock.range();
        let mut frame = clock.frame();
        ui.horizontal(|ui| {
            let label = if clock.is_playing() {
                "Pause (Enter)"
            } else {
                "Play (Enter)"
            };
            if ui.button(label).clicked() {
                self.actions.push(Action::PlayPause);
            }
            let slider = egui::Slider::new(&mut frame, first..=last)
                .text("frame")
                .step_by(1.0);
            if ui.add(slider).changed() {
                clock.set_frame(frame, Instant::now());
            }
        });
        let mut blur = motion_blur;
        if ui.checkbox(&mut blur, "Motion blur (B)").changed() {
            self.actions.push(Action::ToggleMotionBlur);
        }
        ui.small(format!(
            "{} fps; the frame's keyed camera: a change by hand holds until the frame changes",
            clock.fps()
        ));
    }

    /// Shift and tilt (`camera::movements`), and how to lay the plane of focus by clicks.
    fn movements(ui: &mut egui::Ui, rig: &mut CameraRig) {
        let m = rig.movements();
        let r = rig.readout();
        let in_mm = r.focal_length_mm.is_some() || r.real.is_some();
        let (unit, speed) = if in_mm {
            ("mm", 0.1)
        } else {
            ("image heights", 0.005)
        };
        egui::Grid::new("movements").num_columns(2).show(ui, |ui| {
            ui.label(format!("Shift ({unit})"));
            let mut shift = m.shift;
            let changed = ui.horizontal(|ui| {
                let x = ui.add(egui::DragValue::new(&mut shift[0]).speed(speed).prefix("x "));
                let y = ui.add(egui::DragValue::new(&mut shift[1]).speed(speed).prefix("y "));
                x.changed() || y.changed()
            });
            if changed.inner {
                rig.set_shift(shift);
            }
            ui.end_row();
            let (mut tilt, mut direction) = (m.tilt_degrees, m.tilt_direction_degrees);
            ui.label("Tilt (deg)");
            let tilt_edit = ui.add(
                egui::DragValue::new(&mut tilt)
                    .speed(0.1)
                    .range(0.0..=PANEL_MAX_TILT_DEGREES),
            );
            ui.end_row();
            ui.label("Tilt direction (deg)");
            let direction_edit = ui
                .add(egui::DragValue::new(&mut direction).speed(1.0))
                .on_hover_text("where the plane of focus comes nearer: 0 the image's bottom (a ground plane), 90 its right");
            ui.end_row();
            if tilt_edit.changed() || direction_edit.changed() {
                rig.set_tilt(tilt, direction);
            }
        });
        ui.small("Shift+click three surfaces: the plane of focus through them");
    }

    /// The lens picker: the thin lens or a real one (each built-in, and the file the preview
    /// started with).
    fn lens_picker(ui: &mut egui::Ui, rig: &mut CameraRig) {
        let current = rig.lens_choice();
        let mut picked = current.clone();
        egui::ComboBox::from_label("Lens")
            .selected_text(current.label())
            .show_ui(ui, |ui| {
                for choice in rig.lens_choices() {
                    let label = choice.label();
                    let item = ui.selectable_value(&mut picked, choice.clone(), label);
                    if let LensChoice::Real(name) = &choice {
                        item.on_hover_text(name);
                    }
                }
            });
        if picked != current {
            rig.set_lens(&picked);
        }
    }

    fn lens(&mut self, ui: &mut egui::Ui, rig: &mut CameraRig, stats: &PanelStats) {
        Self::lens_picker(ui, rig);
        let r = rig.readout();
        if r.real.is_some() {
            self.real_lens(ui, rig, &r, stats);
            return;
        }
        let mut projection = r.projection;
        ui.horizontal(|ui| {
            ui.label("Projection");
            ui.selectable_value(&mut projection, ProjectionKind::Perspective, "perspective");
            ui.selectable_value(
                &mut projection,
                ProjectionKind::Orthographic,
                "orthographic",
            );
        });
        if projection != r.projection {
            rig.set_projection(projection);
        }
        egui::Grid::new("lens").num_columns(2).show(ui, |ui| {
            if let (Some(mut focal), Some(mut n)) = (r.focal_length_mm, r.f_number) {
                ui.label("Focal length (mm)");
                if ui
                    .add(
                        egui::DragValue::new(&mut focal)
                            .speed(0.5)
                            .range(1.0..=2000.0),
                    )
                    .changed()
                {
                    rig.set_focal_length_mm(focal);
                }
                ui.end_row();
                ui.label("f-number");
                if ui
                    .add(egui::DragValue::new(&mut n).speed(0.05).range(0.5..=64.0))
                    .changed()
                {
                    rig.set_f_number(n);
                }
                ui.end_row();
            }
            ui.label("Aperture radius");
            let mut radius = r.aperture_radius;
            let physical = r.focal_length_mm.is_some();
            let edited = ui
                .add_enabled(
                    !physical,
                    egui::DragValue::new(&mut radius)
                        .speed(0.001)
                        .range(0.0..=f64::MAX),
                )
                .changed();
            if edited {
                rig.set_aperture_radius(radius);
            }
            ui.end_row();
            self.aperture_shape(ui, rig);
            ui.label("Focus distance");
            let mut focus = r.focus_distance;
            if ui
                .add(
                    egui::DragValue::new(&mut focus)
                        .speed(0.01)
                        .range(1e-3..=f64::MAX),
                )
                .changed()
            {
                rig.set_focus_distance(focus);
            }
            ui.end_row();
        });
    }

    /// A real lens: its f-number (its widest to f/22), focus (no nearer than it reaches),
    /// sensor height, the stop's shape, and the summary of the lens as traced.
    fn real_lens(
        &mut self,
        ui: &mut egui::Ui,
        rig: &mut CameraRig,
        r: &LensReadout,
        stats: &PanelStats,
    ) {
        let Some(real) = &r.real else {
            return;
        };
        egui::Grid::new("real lens").num_columns(2).show(ui, |ui| {
            ui.label("Focal length (mm)");
            ui.label(format!("{:.2}", real.focal_length_mm));
            ui.end_row();
            ui.label("f-number");
            let mut n = r.f_number.unwrap_or(real.f_number_range.0);
            let (lo, hi) = real.f_number_range;
            let range = lo.min(n)..=hi.max(n);
            if ui
                .add(
                    egui::DragValue::new(&mut n)
                        .speed(0.05)
                        .range(range)
                        .max_decimals(2),
                )
                .on_hover_text(format!("f/{lo:.2} (wide open) to f/{hi}"))
                .changed()
            {
                rig.set_f_number(n);
            }
            ui.end_row();
            ui.label("Focus distance");
            let mut focus = r.focus_distance;
            if ui
                .add(
                    egui::DragValue::new(&mut focus)
                        .speed(0.01)
                        .range(real.nearest_focus..=f64::MAX),
                )
                .on_hover_text(format!(
                    "from the entrance pupil; the lens focuses no nearer than {:.4}",
                    real.nearest_focus
                ))
                .changed()
            {
                let _ = rig.set_focus_distance(focus);
            }
            ui.end_row();
            ui.label("Sensor height (mm)");
            let mut sensor = r.sensor_height_mm.unwrap_or(24.0);
            let (lo, hi) = SENSOR_HEIGHT_RANGE_MM;
            if ui
                .add(egui::DragValue::new(&mut sensor).speed(0.1).range(lo..=hi))
                .changed()
            {
                rig.set_sensor_height_mm(sensor);
            }
            ui.end_row();
            if let Some(vfov) = r.vfov_degrees {
                ui.label("Field of view");
                ui.label(format!("{vfov:.1} deg (first order)"));
                ui.end_row();
            }
            ui.label("Dispersion");
            let mut on = real.dispersion;
            let toggle = ui.add_enabled(real.dispersive_glass, egui::Checkbox::new(&mut on, ""));
            let hover = if real.dispersive_glass {
                "each camera ray carries a wavelength through the glass (colour fringes)"
            } else {
                "the lens gives no Abbe numbers: its glass has no dispersion"
            };
            if toggle.on_hover_text(hover).changed() {
                rig.set_dispersion(on);
            }
            ui.end_row();
            let mut flare = crate::lens_flare::switches(rig.settings());
            let before = flare;
            ui.label("Flare");
            ui.checkbox(&mut flare.ghosts, "ghosts")
                .on_hover_text("light reflected twice between the lens's coated surfaces, drawn once the view converges");
            ui.end_row();
            ui.label("Starburst");
            ui.checkbox(&mut flare.starburst, "")
                .on_hover_text("the aperture's diffraction around bright sources, drawn once the view converges");
            ui.end_row();
            if flare != before {
                rig.set_flare(flare);
            }
            self.aperture_shape(ui, rig);
        });
        if let Some(summary) = &stats.lens_summary {
            ui.small(summary);
        }
    }

    /// The iris: blades (or round), rotation, roundness and the anamorphic aspect, live.
    fn aperture_shape(&mut self, ui: &mut egui::Ui, rig: &mut CameraRig) {
        let mut a = rig.aperture();
        let before = a.clone();
        if let Some(image) = &a.image {
            ui.label("Aperture image");
            let name = image.file_name().unwrap_or(image.as_os_str());
            ui.label(name.to_string_lossy())
                .on_hover_text(image.display().to_string());
            ui.end_row();
        }
        let has_image = a.image.is_some();
        ui.label("Aperture blades");
        ui.add_enabled_ui(!has_image, |ui| {
            ui.horizontal(|ui| {
                let mut round = a.blades.is_none();
                if ui.checkbox(&mut round, "round").changed() {
                    a.blades = if round { None } else { Some(6) };
                }
                if let Some(blades) = a.blades.as_mut() {
                    ui.add(egui::DragValue::new(blades).speed(0.05).range(3..=32));
                }
            })
        });
        ui.end_row();
        let mut rotation = a.rotation.unwrap_or(0.0);
        let mut roundness = a.roundness.unwrap_or(0.0);
        let mut aspect = a.aspect.unwrap_or(1.0);
        ui.label("Rotation");
        ui.add_enabled(
            a.blades.is_some() || has_image,
            egui::DragValue::new(&mut rotation)
                .speed(0.5)
                .range(-180.0..=180.0)
                .suffix(" deg"),
        );
        ui.end_row();
        ui.label("Roundness");
        ui.add_enabled(
            a.blades.is_some(),
            egui::Slider::new(&mut roundness, 0.0..=1.0),
        );
        ui.end_row();
        ui.label("Aspect (h / w)");
        ui.add(egui::Slider::new(&mut aspect, 0.25..=4.0).logarithmic(true));
        ui.end_row();
        // Only what differs from the default is written (the C snippet stays short).
        a.rotation = (rotation != 0.0).then_some(rotation);
        a.roundness = (roundness != 0.0).then_some(roundness);
        a.aspect = (aspect != 1.0).then_some(aspect);
        if a != before {
            rig.set_aperture(a);
        }
    }

    fn view_controls(&mut self, ui: &mut egui::Ui) {
        egui::ComboBox::from_label("View")
            .selected_text(self.view.label())
            .show_ui(ui, |ui| {
                for view in ViewMode::ALL {
                    ui.selectable_value(&mut self.view, view, view.label());
                }
            });
        ui.horizontal(|ui| {
            ui.label("Target spp");
            ui.add(egui::DragValue::new(&mut self.target_spp).range(1..=1 << 20));
        });
    }

    /// Exposure in stops (on top of a physical exposure, whose EV100 is shown) and the tone
    /// map: they change what the final view shows, not its samples.
    fn exposure(ui: &mut egui::Ui, rig: &mut CameraRig, stats: &PanelStats) {
        let set = rig.exposure_settings();
        let mut ev = set.ev.unwrap_or(0.0);
        let mut tonemap = set.tonemap.unwrap_or_default();
        ui.horizontal(|ui| {
            ui.label("Exposure (EV)");
            let edit = ui.add(
                egui::DragValue::new(&mut ev)
                    .speed(0.05)
                    .range(-20.0..=20.0)
                    .fixed_decimals(2),
            );
            if edit.changed() {
                rig.set_exposure_ev(ev);
            }
            if let Some(ev100) = stats.ev100 {
                ui.label(format!("on EV100 {ev100:.2}"));
            }
        });
        ui.horizontal(|ui| {
            ui.label("Tone map");
            let before = tonemap;
            for t in ToneMap::ALL {
                ui.selectable_value(&mut tonemap, t, t.name());
            }
            if tonemap != before {
                rig.set_tonemap(tonemap);
            }
        });
    }

    fn timings(ui: &mut egui::Ui, stats: &PanelStats, target: u32) {
        ui.label(format!("{} spp of {target}", stats.spp));
        if let Some(ms) = stats.frame_ms {
            ui.label(format!("frame {ms:.1} ms ({:.0} fps)", 1e3 / ms.max(1e-3)));
        }
        if let Some(t) = stats.times {
            // The final view skips the G-buffer once every pixel has a sample.
            let gbuffer = if t.gbuffer_drawn {
                format!("{:.2} ms", t.gbuffer_ms)
            } else {
                "skipped".to_owned()
            };
            ui.label(format!(
                "G-buffer {gbuffer}, trace {:.1} ms, resolve {:.2} ms, present {:.2} ms",
                t.trace_ms, t.resolve_ms, t.present_ms
            ));
        }
        ui.small(&stats.device);
    }
}
