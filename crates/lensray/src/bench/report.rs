//! Everything a bench measured: what the table, the JSON file and the plot are made from.
//! The JSON file is this structure as it is (`schema` names its version).

use serde::Serialize;

use super::camera::CameraInfo;
use super::focus::FocusInfo;
use super::lens::LensPoint;
use super::movements::{BenchMovement, MovementsPoint};
use super::options::SweepKind;
use super::reference::ReferenceInfo;
use super::runs::Measurement;
use super::sweep::BenchAperture;
use crate::machine::Machine;
use crate::paths::PathKind;
use crate::paths::Startup;
use lensray_core::sampler::SamplerKind;
use lensray_core::scene::SceneDescription;
use lensray_core::settings::Shading;

pub const SCHEMA: &str = "lensray-bench/1";

#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub schema: &'static str,
    pub lensray_version: &'static str,
    pub machine: Machine,
    pub scene: SceneInfo,
    pub settings: SettingsInfo,
    /// The first point's camera (each point gives its own).
    pub camera: CameraInfo,
    /// What the points vary; `null` for a single point.
    pub sweep: Option<SweepKind>,
    /// The paths measured, each with the device it ran on.
    pub paths: Vec<PathInfo>,
    pub points: Vec<PointReport>,
}

#[derive(Clone, Debug, Serialize)]
pub struct SceneInfo {
    /// "default", "dense", "cornell", a file's path, or "generated dense" (triangle sweep).
    pub name: String,
    /// Triangles of the scene (of the first point's scene in a triangle sweep).
    pub triangles: usize,
    /// How long its file took to load, step by step (a scene file's; absent for the built-in
    /// and generated scenes). Each path's acceleration-structure build is its `build_seconds`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load: Option<SceneLoad>,
}

/// A scene file's load (`LoadTimes`) and the memory its textures take.
#[derive(Clone, Debug, Serialize)]
pub struct SceneLoad {
    /// The mesh file's whole load: `parse_seconds` + `texture_decode_seconds` +
    /// `texture_mips_seconds`.
    pub seconds: f64,
    /// Reading and parsing the file, its buffers and its geometry (texture files' reads
    /// included).
    pub parse_seconds: f64,
    /// Decoding the texture images to RGBA8.
    pub texture_decode_seconds: f64,
    /// Building their mip levels.
    pub texture_mips_seconds: f64,
    pub textures: usize,
    /// Every texture's texels, every level (4 bytes each).
    pub texture_bytes: u64,
}

impl SceneLoad {
    /// The load of `description`, `None` when it was not read from a file.
    pub fn of(description: &SceneDescription) -> Option<Self> {
        let t = &description.load_times;
        (!t.total.is_zero()).then(|| Self {
            seconds: t.total.as_secs_f64(),
            parse_seconds: t.parse().as_secs_f64(),
            texture_decode_seconds: t.texture_decode.as_secs_f64(),
            texture_mips_seconds: t.texture_mips.as_secs_f64(),
            textures: t.textures,
            texture_bytes: description.scene.textures.iter().map(|t| t.bytes()).sum(),
        })
    }
}

/// The shot as asked for; each point says what it varied.
#[derive(Clone, Debug, Serialize)]
pub struct SettingsInfo {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Adaptive sampling's threshold (`spp` its cap); `None`: uniform.
    pub noise_threshold: Option<f32>,
    pub shading: Shading,
    pub sampler: SamplerKind,
    pub seed: u32,
    /// The lens of the shot (world units; radius 0: pinhole).
    pub aperture_radius: f32,
    pub focus_distance: f32,
    /// Timed runs per path and point, after one warm-up.
    pub repeat: usize,
    pub reference_spp: u32,
}

#[derive(Clone, Debug, Serialize)]
pub struct PathInfo {
    pub path: PathKind,
    pub device: String,
    /// What opening the path took the first time (device and pipelines, scene upload and
    /// acceleration structures): its start-up.
    pub startup: Startup,
}

/// One configuration and every path's measurement of it.
#[derive(Clone, Debug, Serialize)]
pub struct PointReport {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub triangles: usize,
    /// The camera of this point's shot.
    pub camera: CameraInfo,
    /// The aperture sweep's shape at this point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aperture: Option<BenchAperture>,
    /// The lens sweep's lens at this point, and the share of camera samples it lets through.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lens: Option<LensPoint>,
    /// The movements sweep's shot at this point: its shift and tilt, and what they made of the
    /// camera.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub movements: Option<MovementsPoint>,
    pub reference: ReferenceInfo,
    /// How much of the shot is in focus (the hybrid's gain depends on it).
    pub focus: FocusInfo,
    pub results: Vec<Measurement>,
}

impl PointReport {
    /// The value the sweep varies at this point, as a number for tables and plots.
    pub fn swept(&self, sweep: Option<SweepKind>) -> f64 {
        match sweep {
            None | Some(SweepKind::Spp) => f64::from(self.spp),
            Some(SweepKind::Resolution) => f64::from(self.width) * f64::from(self.height),
            Some(SweepKind::Triangles) => self.triangles as f64,
            Some(SweepKind::Aperture) => match self.aperture {
                Some(a) => {
                    1.0 + BenchAperture::ALL.iter().position(|&b| b == a).unwrap_or(0) as f64
                }
                None => 1.0,
            },
            Some(SweepKind::Lens) => match &self.lens {
                // Lens by lens (1, 2, ...), its thin model half a step before it.
                Some(l) => {
                    let index = lensray_core::optics::builtin::names()
                        .iter()
                        .position(|n| *n == l.lens)
                        .unwrap_or(0) as f64;
                    1.0 + index
                        + if l.model == super::lens::LensModel::Real {
                            0.5
                        } else {
                            0.0
                        }
                }
                None => 1.0,
            },
            Some(SweepKind::Movements) => match &self.movements {
                Some(m) => {
                    1.0 + BenchMovement::ALL
                        .iter()
                        .position(|&b| b == m.point)
                        .unwrap_or(0) as f64
                }
                None => 1.0,
            },
        }
    }

    /// The same, in words: "16", "640x480", "1022560".
    pub fn swept_label(&self, sweep: Option<SweepKind>) -> String {
        match sweep {
            None | Some(SweepKind::Spp) => self.spp.to_string(),
            Some(SweepKind::Resolution) => format!("{}x{}", self.width, self.height),
            Some(SweepKind::Triangles) => self.triangles.to_string(),
            Some(SweepKind::Aperture) => self.aperture.map_or("round", |a| a.name()).to_string(),
            Some(SweepKind::Lens) => match &self.lens {
                Some(l) if l.model == super::lens::LensModel::Thin => format!("thin:{}", l.lens),
                Some(l) => l.lens.to_string(),
                None => "?".into(),
            },
            Some(SweepKind::Movements) => self
                .movements
                .as_ref()
                .map_or("plain", |m| m.point.name())
                .to_string(),
        }
    }
}

impl BenchReport {
    pub fn to_json(&self) -> String {
        // Plain data (numbers, strings, enums): serialising cannot fail.
        let mut text = serde_json::to_string_pretty(self).expect("a bench report serialises");
        text.push('\n');
        text
    }
}
