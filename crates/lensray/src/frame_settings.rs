//! A sequence's settings at each frame: the scene file's, the keyframes at that frame over them,
//! the command line's over those, and the frame's seed. `render --frames` renders each frame
//! from them and the preview's frame slider shows each frame from them, so a frame the preview
//! shows is the frame the sequence renders.

use anyhow::{Context, Result};

use lensray_core::camera::Camera;
use lensray_core::scene::Scene;
use lensray_core::settings::{
    frame_seed, shot, shutter, FocusKey, Keyframes, Settings, Shot, Shutter,
};

/// The command line's settings (`command_line`, in metres) over a scene file's (`file`): a
/// lens the command line describes replaces the file's description of one (a focal length
/// replaces an aperture radius, an aperture radius a physical lens).
pub fn command_line_over(file: &Settings, command_line: &Settings) -> Settings {
    let mut base = file.clone();
    if command_line.camera.focal_length_mm.is_some() {
        base.camera.aperture_radius = None;
    }
    if command_line.camera.aperture_radius.is_some() {
        base.camera.focal_length_mm = None;
        base.camera.f_number = None;
        base.camera.sensor_height_mm = None;
    }
    base.overridden_by(command_line)
}

/// The view depth of the surface seen at a pixel through a camera (the app's render path
/// answers it), or an error naming the key (the third argument) and the pixel.
pub type PixelDepth<'a> = dyn FnMut(&Camera, [u32; 2], &str) -> Result<f32> + 'a;

/// Each frame's settings of a sequence.
#[derive(Clone, Debug)]
pub struct FrameSettings {
    /// The scene file's settings.
    file: Settings,
    /// The command line's, in metres.
    command_line: Settings,
    keyframes: Keyframes,
    /// The sequence's seed, each frame's from it (`settings::frame_seed`).
    seed: u32,
    /// Whether the file's meshes move while the shutter is open: the camera's samples then
    /// take their moments even where it stands still (`Shutter::camera_motion`).
    objects_move: bool,
}

impl FrameSettings {
    pub fn new(file: Settings, command_line: Settings, keyframes: Keyframes) -> Self {
        let seed = command_line_over(&file, &command_line)
            .image
            .seed
            .unwrap_or(0);
        Self {
            file,
            command_line,
            keyframes,
            seed,
            objects_move: false,
        }
    }

    /// These settings for a scene whose meshes move while the shutter is open (`moving`).
    pub fn with_moving_objects(mut self, moving: bool) -> Self {
        self.objects_move = moving;
        self
    }

    pub fn keyframes(&self) -> &Keyframes {
        &self.keyframes
    }

    /// The settings without the keyframes: a single image's (`render` without `--frames`).
    pub fn unkeyed(&self) -> Settings {
        command_line_over(&self.file, &self.command_line)
    }

    /// The settings of frame `frame`.
    pub fn at(&self, frame: u32) -> Settings {
        let keyed = self.keyframes.settings_at(&self.file, frame);
        let mut settings = command_line_over(&keyed, &self.command_line);
        settings.image.seed = Some(frame_seed(self.seed, frame));
        settings
    }

    /// The settings at the fractional frame `frame`: a time within a frame's shutter (the
    /// seed is the frame's own, [`Self::at`]'s).
    pub fn at_time(&self, frame: f64) -> Settings {
        let keyed = self.keyframes.settings_at_time(&self.file, frame);
        command_line_over(&keyed, &self.command_line)
    }

    /// The shot of frame `frame` on `scene` (whose file `source` names in an error), its
    /// camera moving over the frame's shutter where motion blur or a rolling shutter is on.
    pub fn shot(&self, frame: u32, scene: &Scene, source: &str) -> Result<Shot> {
        let settings = self.at(frame);
        let shot =
            shot(&settings, scene).with_context(|| format!("scene {source}: frame {frame}"))?;
        self.moving(frame, shot, scene, source)
    }

    /// `shot` of frame `frame` with its camera moving as the keyframes or the camera
    /// animation move it over the frame's shutter (`settings::shutter`), if it is open for a
    /// time or rolls.
    pub fn moving(&self, frame: u32, shot: Shot, scene: &Scene, source: &str) -> Result<Shot> {
        let context = || format!("scene {source}: frame {frame}");
        let shutter = shutter(&self.at(frame)).with_context(context)?;
        self.moving_through(shutter, frame, shot, scene, source)
    }

    /// [`Self::moving`] through `shutter` (the preview's, which its key toggles), if any.
    pub fn moving_through(
        &self,
        shutter: Option<Shutter>,
        frame: u32,
        shot: Shot,
        scene: &Scene,
        source: &str,
    ) -> Result<Shot> {
        let context = || format!("scene {source}: frame {frame}");
        let Some(shutter) = shutter else {
            return Ok(shot);
        };
        let motion = shutter
            .camera_motion(
                f64::from(frame),
                &|t| self.at_time(t),
                scene,
                self.objects_move,
            )
            .with_context(context)?;
        Ok(Shot {
            camera: shot.camera.with_motion(motion),
            ..shot
        })
    }

    /// Turns the keyframes' focus points and pixels into distances, each at its frame's camera;
    /// `depth` gives a pixel's (only asked for where a key names a pixel).
    pub fn resolve_focus(
        &mut self,
        scene: &Scene,
        source: &str,
        depth: &mut PixelDepth,
    ) -> Result<()> {
        for (frame, key) in self.keyframes.unresolved_focus() {
            let camera = self.shot(frame, scene, source)?.camera;
            let distance = match key {
                FocusKey::Point(p) => {
                    let depth = camera.view_depth(glam::DVec3::from(p).as_vec3());
                    if depth <= 0.0 {
                        anyhow::bail!(
                            "scene {source}: keyframe at frame {frame}: `focus_point` is behind the camera"
                        );
                    }
                    depth
                }
                FocusKey::Pixel(pixel) => depth(
                    &camera,
                    pixel,
                    &format!("keyframe at frame {frame}: `focus_at`"),
                )?,
                FocusKey::Distance(d) => d as f32,
            };
            self.keyframes.resolve_focus(frame, f64::from(distance));
        }
        Ok(())
    }
}
