//! The hybrid plan's host reference (a probe: tests/hybrid.rs): per pixel, take the G-buffer's
//! shortcut or trace, and how many samples (the rules: `estimators`' module documentation).
//! `Plan::new` makes the plan on the host from a G-buffer read back; shaders/passes/hybrid_plan.comp
//! makes the same plan on the device, and tests compare the two: [`host_plan`] reads the G-buffer
//! (and, lit, the lit pre-pass) back and plans on the host, [`device_plan`] plans on the device
//! and reads its entries back, [`read_plan`] reads back the plan the device holds now (that of
//! the last hybrid `add_samples`). A render reads none of the plan back.

use glam::Vec3;

use crate::{GBuffer, GpuError, GpuRenderer};
use lensray_core::camera::Camera;
use lensray_core::interface::{
    HYBRID_CHECK_INVERSE, HYBRID_MAX_REACH_TILES, HYBRID_SEGMENT, HYBRID_SHORTCUT,
    HYBRID_SHORTCUT_COC, HYBRID_TILE,
};
use lensray_core::settings::{Shading, Shot};

/// Side of the tiles over which the circle of confusion is maximised, pixels.
const TILE: u32 = HYBRID_TILE;
/// Dilated CoC radius (pixels) under which a pixel may take the shortcut.
const SHORTCUT_COC: f32 = HYBRID_SHORTCUT_COC;
/// Pixels of a row that a device runs in lockstep (lavapipe: 8 invocations, one row of an 8x8
/// workgroup): they share one decision (shortcut, or the most samples of any of them).
const SEGMENT: u32 = HYBRID_SEGMENT;
/// How far (in tiles) a tile's CoC is spread at most: a bound on the dilation's cost.
const MAX_REACH_TILES: i64 = HYBRID_MAX_REACH_TILES as i64;
/// The half-width (pixels, Chebyshev) of the window of G-buffer pixels that must hold no edge
/// for a pixel with dilated circle of confusion `coc` to take the shortcut. Its lens rays reach
/// image points within `0.5 + coc` of its centre (film samples stay in the pixel); an edge
/// crossing there lies between two pixel centres, one of them within `floor(0.5 + coc)` and the
/// other one further, and marks the first of the pair (left or upper): so `1 + floor(0.5 +
/// coc)`. Below half a pixel (`SHORTCUT_COC`) that is 1: the pixel and its neighbours, the
/// in-focus rule. hybrid_plan.comp computes it alike.
fn window_radius(coc: f32) -> u32 {
    // Beyond any image the radius crosses the frame: clamped before converting.
    1 + (coc.min(1e7) + SHORTCUT_COC).floor() as u32
}

/// Per pixel: what the trace pass does (see `interface::HybridTraceGroup`).
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub width: u32,
    pub height: u32,
    /// xyz: the shortcut value (unlit: the albedo; lit: the pre-pass's), w: samples to trace,
    /// or HYBRID_SHORTCUT.
    pub entries: Vec<[f32; 4]>,
    /// Pixels that take the shortcut.
    pub shortcut_pixels: u64,
    /// Camera samples the trace pass is expected to trace for samples 0..spp (the planned ones,
    /// plus the shortcut pixels' checks), and that a path tracing all of them traces.
    pub expected_samples: f64,
    pub all_samples: u64,
}

impl Plan {
    /// The plan of `spp` samples seen by `camera`, from its G-buffer (of the camera's size):
    /// unlit for `lit == None`; lit with the lit pre-pass's output (`GpuRenderer::lit_prepass`:
    /// per pixel the shortcut value and 1 where its shadow ray was blocked, else 0).
    pub fn new(camera: &Camera, gbuffer: &GBuffer, lit: Option<&[[f32; 4]]>, spp: u32) -> Plan {
        let (w, h) = (gbuffer.width, gbuffer.height);
        let tiles = Tiles {
            x: w.div_ceil(TILE),
            y: h.div_ceil(TILE),
        };
        let dilated = tiles.dilate(&tiles.max_coc(camera, gbuffer));
        let edges = EdgeTable::new(gbuffer, lit);
        let spp = spp.max(1);
        let mut samples = pixel_samples(&tiles, &dilated, &edges, spp);
        share_within_segments(&mut samples, w);
        let (entries, shortcut_pixels, planned) = plan_entries(samples, gbuffer, lit);
        Plan {
            width: w,
            height: h,
            entries,
            shortcut_pixels,
            expected_samples: planned as f64
                + shortcut_pixels as f64 * f64::from(spp) / f64::from(HYBRID_CHECK_INVERSE),
            all_samples: u64::from(w) * u64::from(h) * u64::from(spp),
        }
    }

    /// A plan from its entries (as the device plan pass writes them), with its counts.
    fn from_entries(width: u32, height: u32, entries: Vec<[f32; 4]>, spp: u32) -> Plan {
        let spp = spp.max(1);
        let shortcut_pixels = entries.iter().filter(|e| e[3] == HYBRID_SHORTCUT).count() as u64;
        let planned: u64 = entries
            .iter()
            .filter(|e| e[3] != HYBRID_SHORTCUT)
            .map(|e| e[3] as u64)
            .sum();
        Plan {
            width,
            height,
            entries,
            shortcut_pixels,
            expected_samples: planned as f64
                + shortcut_pixels as f64 * f64::from(spp) / f64::from(HYBRID_CHECK_INVERSE),
            all_samples: u64::from(width) * u64::from(height) * u64::from(spp),
        }
    }

    /// The fraction of pixels that take the shortcut.
    pub fn shortcut_fraction(&self) -> f64 {
        self.shortcut_pixels as f64 / (self.entries.len().max(1)) as f64
    }
}

/// The image's tiles of `TILE` x `TILE` pixels, over which the circle of confusion is maximised.
struct Tiles {
    /// Tiles across.
    x: u32,
    /// Tiles down.
    y: u32,
}

impl Tiles {
    /// Circle of confusion per pixel (0 where nothing is covered: the background is at
    /// infinity, but a background pixel is only blurred by what covers it, which dilation
    /// brings in), maximum per tile.
    fn max_coc(&self, camera: &Camera, gbuffer: &GBuffer) -> Vec<f32> {
        let (w, h, tw) = (gbuffer.width, gbuffer.height, self.x);
        let mut tile_max = vec![0f32; (self.x * self.y) as usize];
        let coc_lens = lensray_core::camera::CocLens::of(camera);
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                if gbuffer.coverage[i] {
                    let centre = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    let coc = coc_lens.radius_pixels(centre, gbuffer.view_depth[i]);
                    let t = ((y / TILE) * tw + x / TILE) as usize;
                    tile_max[t] = tile_max[t].max(coc);
                }
            }
        }
        tile_max
    }

    /// Each tile spreads its maximum to the tiles within its reach: those whose nearest pixel
    /// lies within that many pixels (Chebyshev distance).
    fn dilate(&self, tile_max: &[f32]) -> Vec<f32> {
        let (tw, th) = (self.x, self.y);
        let mut dilated = tile_max.to_vec();
        for ty in 0..i64::from(th) {
            for tx in 0..i64::from(tw) {
                let m = tile_max[(ty * i64::from(tw) + tx) as usize];
                if m <= 0.0 {
                    continue;
                }
                let reach = ((m / TILE as f32) as i64 + 1).min(MAX_REACH_TILES);
                for dy in -reach..=reach {
                    for dx in -reach..=reach {
                        let (x, y) = (tx + dx, ty + dy);
                        if x < 0 || y < 0 || x >= i64::from(tw) || y >= i64::from(th) {
                            continue;
                        }
                        let gap = (dx.abs().max(dy.abs()) - 1).max(0) * i64::from(TILE);
                        if gap as f32 <= m {
                            let t = (y * i64::from(tw) + x) as usize;
                            dilated[t] = dilated[t].max(m);
                        }
                    }
                }
            }
        }
        dilated
    }
}

/// Summed-area table of the G-buffer's edge marks: "no edge within r pixels" in O(1).
struct EdgeTable {
    table: Vec<u32>,
    /// Entries per row of `table`: the image's width + 1.
    stride: usize,
    width: u32,
    height: u32,
}

impl EdgeTable {
    /// Marks the edges of the G-buffer: a pixel differs from its right or lower neighbour in
    /// what the shading depends on (unlit: coverage and albedo; lit: also the normal, the depth
    /// and whether the light is blocked: a shadow boundary, which no G-buffer shows).
    fn new(gbuffer: &GBuffer, lit: Option<&[[f32; 4]]>) -> Self {
        let (w, h) = (gbuffer.width, gbuffer.height);
        let differs = |a: usize, b: usize| {
            if gbuffer.coverage[a] != gbuffer.coverage[b] || gbuffer.albedo[a] != gbuffer.albedo[b]
            {
                return true;
            }
            let Some(prepass) = lit.filter(|_| gbuffer.coverage[a]) else {
                return false;
            };
            let (da, db) = (gbuffer.view_depth[a], gbuffer.view_depth[b]);
            gbuffer.normal[a].dot(gbuffer.normal[b]) < 0.995
                || (da - db).abs() > 0.02 * da.abs().max(db.abs())
                || prepass[a][3] != prepass[b][3]
        };
        let stride = (w + 1) as usize;
        let mut table = vec![0u32; stride * (h + 1) as usize];
        for y in 0..h {
            let mut row = 0u32;
            for x in 0..w {
                let i = (y * w + x) as usize;
                let edge =
                    (x + 1 < w && differs(i, i + 1)) || (y + 1 < h && differs(i, i + w as usize));
                row += u32::from(edge);
                let at = (y as usize + 1) * stride + x as usize + 1;
                table[at] = table[at - stride] + row;
            }
        }
        EdgeTable {
            table,
            stride,
            width: w,
            height: h,
        }
    }

    /// No edge mark within `r` pixels (Chebyshev) of pixel (x, y).
    fn no_edge_within(&self, x: u32, y: u32, r: u32) -> bool {
        let (w, h, stride, table) = (self.width, self.height, self.stride, &self.table);
        // Beyond the frame the G-buffer knows nothing, and a blurred pixel's lens rays
        // reach there: a window that crosses the border is not uniform (r = 1, the pixel
        // and its neighbours, stays inside: film samples do not leave the pixel).
        if r > 1 && (x < r || y < r || x + r >= w || y + r >= h) {
            return false;
        }
        let (x0, y0) = (x.saturating_sub(r) as usize, y.saturating_sub(r) as usize);
        let (x1, y1) = ((x + r + 1).min(w) as usize, (y + r + 1).min(h) as usize);
        table[y1 * stride + x1] + table[y0 * stride + x0]
            == table[y0 * stride + x1] + table[y1 * stride + x0]
    }
}

/// Per pixel: None for the shortcut, else the samples to trace: all `spp` of them. (Fewer
/// where the circle of confusion is small, ceil(spp * coc / 2 px) below 2 px, lost more in
/// error than it saved in time at every aperture measured: docs/hybrid.md.)
fn pixel_samples(tiles: &Tiles, dilated: &[f32], edges: &EdgeTable, spp: u32) -> Vec<Option<u32>> {
    let (w, h, tw) = (edges.width, edges.height, tiles.x);
    let mut samples: Vec<Option<u32>> = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let coc = dilated[((y / TILE) * tw + x / TILE) as usize];
            // The G-buffer is uniform over the pixel and its circle of confusion: every lens
            // ray is expected to see what the G-buffer sees (checked, unbiased).
            let radius = window_radius(coc);
            samples.push((!edges.no_edge_within(x, y, radius)).then_some(spp));
        }
    }
    samples
}

/// SIMD coherence: a device runs neighbouring invocations in lockstep (lavapipe: the 8 of one
/// tile row), so a segment of a row traces as long as its busiest pixel. Where one pixel of a
/// segment traces, all of it traces that many samples (for free).
fn share_within_segments(samples: &mut [Option<u32>], width: u32) {
    for row in samples.chunks_mut(width as usize) {
        for segment in row.chunks_mut(SEGMENT as usize) {
            if segment.iter().any(Option::is_some) {
                let n = segment.iter().flatten().copied().max();
                segment.fill(n);
            }
        }
    }
}

/// The plan's entries from the pixels' samples, with the count of shortcut pixels and of
/// planned samples.
fn plan_entries(
    samples: Vec<Option<u32>>,
    gbuffer: &GBuffer,
    lit: Option<&[[f32; 4]]>,
) -> (Vec<[f32; 4]>, u64, u64) {
    let mut entries = Vec::with_capacity(samples.len());
    let mut shortcut_pixels = 0u64;
    let mut planned = 0u64;
    for (i, n) in samples.into_iter().enumerate() {
        // Lit, every pixel keeps the pre-pass's value: the shortcut samples of its
        // neighbours reproject onto it (trace.comp).
        let value = match lit {
            Some(prepass) => Vec3::from_slice(&prepass[i][..3]),
            None if n.is_none() => gbuffer.albedo[i],
            None => Vec3::ZERO,
        };
        entries.push(match n {
            None => {
                shortcut_pixels += 1;
                [value.x, value.y, value.z, HYBRID_SHORTCUT]
            }
            Some(n) => {
                planned += u64::from(n);
                [value.x, value.y, value.z, n as f32]
            }
        });
    }
    (entries, shortcut_pixels, planned)
}

/// The plan of `shot`, made on the device (shaders/passes/hybrid_plan.comp: the G-buffer and the
/// plan in one submission, no G-buffer readback) and left in the renderer for its later
/// `accumulate` calls. Its entries are read back (a mapped buffer) for the counts.
pub fn device_plan(renderer: &mut GpuRenderer, shot: &Shot) -> Result<Plan, GpuError> {
    renderer.plan_on_device(shot)?;
    read_plan(renderer, shot)
}

/// The plan the device holds now for `shot` (its size and spp): that of the last
/// `plan_on_device`, the hybrid `add_samples` included, read back once it is made.
pub fn read_plan(renderer: &GpuRenderer, shot: &Shot) -> Result<Plan, GpuError> {
    let (camera, settings) = (&shot.camera, &shot.render);
    let entries = renderer.read_plan_entries(u64::from(camera.width) * u64::from(camera.height))?;
    Ok(Plan::from_entries(
        camera.width,
        camera.height,
        entries,
        settings.spp,
    ))
}

/// The reference plan of `shot`: the G-buffer (and, lit, the lit pre-pass) read back,
/// `Plan::new` on the host.
pub fn host_plan(renderer: &mut GpuRenderer, shot: &Shot) -> Result<Plan, GpuError> {
    let (camera, settings) = (&shot.camera, &shot.render);
    let gbuffer = renderer.render_gbuffer(&camera.for_rasterizing_rays(), settings.background)?;
    let prepass = match settings.shading {
        Shading::Lit => Some(renderer.lit_prepass(shot)?),
        _ => None,
    };
    Ok(Plan::new(
        camera,
        &gbuffer,
        prepass.as_deref(),
        settings.spp,
    ))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use lensray_core::camera::{CameraParams, LensParams, ProjectionParams};

    /// The window is the smallest that sees every edge a pixel's lens rays can reach: along a
    /// row, an edge at `e` (between the centres of pixels k and k + 1, k <= e <= k + 1: at a
    /// centre either pair may differ, marked on k) is reached from pixel j when
    /// |e - j| <= 0.5 + coc; then |k - j| <= window_radius(coc), and one less would miss some
    /// such edge.
    #[test]
    fn the_window_sees_every_edge_within_reach() {
        for step in 0..=400 {
            let coc = step as f32 * 0.0125;
            let r = window_radius(coc) as i64;
            let mut farthest = 0;
            // Edges over [-8, 8] in 1/64 px steps, pixel j = 0.
            for e64 in -512..=512 {
                let e = e64 as f32 / 64.0;
                if e.abs() <= 0.5 + coc {
                    let k = e.floor() as i64;
                    let lower = if e == e.floor() { k - 1 } else { k };
                    farthest = farthest.max(k.abs()).max(lower.abs());
                }
            }
            assert_eq!(
                r, farthest,
                "coc {coc}: radius {r}, farthest mark {farthest}"
            );
        }
        assert_eq!(window_radius(0.0), 1);
        assert_eq!(window_radius(0.49), 1);
        assert_eq!(window_radius(0.5), 2);
        assert_eq!(window_radius(f32::INFINITY), 1 + 1e7 as u32);
    }

    /// A 64x32 G-buffer: a wall at the focus distance, with a near square (blurred) over tile
    /// (0, 0). The tiles the square's CoC reaches are traced, the far ones take the shortcut.
    #[test]
    fn dilation_spreads_a_blurred_foreground_over_sharp_neighbours() {
        let camera = CameraParams {
            eye: Vec3::ZERO,
            target: Vec3::new(0.0, 0.0, -1.0),
            up: Vec3::Y,
            projection: ProjectionParams::Perspective { vfov_degrees: 45.0 },
            lens: LensParams::ThinLens {
                aperture_radius: 0.4,
                focus_distance: 5.0,
            },
            near: 0.1,
            far: 100.0,
            width: 64,
            height: 32,
            movements: lensray_core::camera::Movements::NONE,
        }
        .build()
        .expect("camera");
        let (w, h) = (64u32, 32u32);
        let n = (w * h) as usize;
        let mut gbuffer = GBuffer {
            width: w,
            height: h,
            view_depth: vec![5.0; n],
            normal: vec![Vec3::Z; n],
            albedo: vec![Vec3::splat(0.5); n],
            coverage: vec![true; n],
        };
        for y in 0..4 {
            for x in 0..4 {
                gbuffer.view_depth[(y * w + x) as usize] = 1.0;
                gbuffer.albedo[(y * w + x) as usize] = Vec3::splat(0.9);
            }
        }
        let near_coc = camera.coc_radius_pixels(glam::Vec2::splat(0.5), 1.0);
        assert!(near_coc > 9.0 && near_coc < 16.0, "{near_coc}");
        let plan = Plan::new(&camera, &gbuffer, None, 16);
        let traced = |x: u32, y: u32| plan.entries[(y * w + x) as usize][3] != HYBRID_SHORTCUT;
        // The square's tile, its neighbours and the tiles within its CoC are traced...
        assert!(traced(0, 0) && traced(8, 0) && traced(0, 8) && traced(16, 16));
        // ...the tiles beyond take the shortcut, with the G-buffer's albedo.
        assert!(!traced(40, 20) && !traced(63, 31));
        assert_eq!(plan.entries[(20 * w + 40) as usize][..3], [0.5; 3]);
        assert_eq!(plan.entries[0][3], 16.0, "traced: every sample");
        assert!(plan.shortcut_pixels > 0 && plan.expected_samples < plan.all_samples as f64);
    }
}
