//! A real lens's ghosts on the device (shaders/passes/ghosts.comp): lensray-core's
//! `FlareLens::distant_source` traced and drawn by the GPU, every path and wavelength in two
//! dispatches. The first traces every grid ray; the host then sums each film plane's light
//! from the traced shares (a fixed-point plane is scaled to hold it, at most 2^31), and the
//! second draws every grid cell with integer atomics, which add up the same in any order.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::core::recorder::Access;
use crate::core::shader;
use crate::passes::aperture::ApertureTable;
use crate::passes::lens::LensBuffer;
use lensray_core::camera::flare::ghosts::{cell_corners, FilmBins, FilmLight, FlareLens};
use lensray_core::camera::Camera;
use lensray_core::interface::{
    ApertureGroup, DescriptorSet, GhostGroup, GhostPush, GhostSet, LensGroup,
    GHOST_FILM_FULL_SCALE, GHOST_GROUP_SIZE, GHOST_STEP_DRAW, GHOST_STEP_TRACE, GHOST_VERTEX_VEC4S,
};
use lensray_core::optics::coating::Coating;
use lensray_core::optics::glass::dispersion_offset;

/// Workgroups along x at most (each dimension's guaranteed minimum is 65535).
const GROUPS_X: u32 = 32768;

/// What one trace asks: a distant source `degrees` off the axis at `wavelengths_nm` on a
/// `grid` x `grid` grid, drawn into `bins`.
pub struct GhostRequest<'a> {
    pub degrees: f64,
    pub wavelengths_nm: &'a [f64],
    pub grid: usize,
    pub bins: FilmBins,
}

impl<'a> GhostRequest<'a> {
    /// The request of `FlareLens::distant_source`'s arguments (`flare::PatternTrace`'s).
    pub fn new(degrees: f64, wavelengths_nm: &'a [f64], grid: usize, bins: FilmBins) -> Self {
        Self {
            degrees,
            wavelengths_nm,
            grid,
            bins,
        }
    }
}

/// The light of `request` through `camera`'s real lens as `lens` (its flare: pairs and
/// coatings) traces it, on `ctx`'s device.
pub(crate) fn distant_source(
    ctx: &Arc<Context>,
    camera: &Camera,
    lens: &FlareLens,
    request: &GhostRequest,
) -> Result<FilmLight, GpuError> {
    let pipeline = Pipeline::compute(ctx, GhostSet::DECL, shader::GHOSTS_COMP)?;
    let paths = 1 + lens.pairs().len();
    let mut buffers = GhostBuffers::new(ctx, camera, lens, request)?;
    let aperture = ApertureTable::of(ctx, camera)?;
    let lens_buffer = LensBuffer::of(ctx, camera)?;
    pipeline.bind_group(&GhostGroup::<Gpu> {
        ghost_paths: &buffers.paths,
        ghost_wavelengths: &buffers.wavelengths,
        ghost_coatings: &buffers.coatings,
        ghost_vertices: &buffers.vertices,
        ghost_film: &buffers.film,
        camera: &buffers.camera,
    });
    pipeline.bind_group(&ApertureGroup::<Gpu> {
        aperture_table: &aperture,
    });
    pipeline.bind_group(&LensGroup::<Gpu> { lens: &lens_buffer });
    let (bins, grid, waves) = (request.bins, request.grid, request.wavelengths_nm.len());
    let (sin, cos) = request.degrees.to_radians().sin_cos();
    let front_radius = lens.front_radius();
    let cell = 2.0 * front_radius / grid as f64;
    let cell_share = cell * cell / (std::f64::consts::PI * front_radius * front_radius);
    let mut push = GhostPush {
        step: GHOST_STEP_TRACE,
        paths: paths as u32,
        wavelengths: waves as u32,
        grid: grid as u32,
        columns: bins.columns as u32,
        rows: bins.rows as u32,
        front_radius: front_radius as f32,
        bin_mm: bins.bin_mm as f32,
        sin_field: sin as f32,
        cos_field: cos as f32,
        cell_share: cell_share as f32,
        pad0: 0,
    };
    let mut wavelengths: Vec<[f32; 4]> = request
        .wavelengths_nm
        .iter()
        .map(|&l| [l as f32, dispersion_offset(l) as f32, 0.0, 0.0])
        .collect();
    buffers
        .wavelengths
        .write(bytemuck::cast_slice(&wavelengths))?;
    let rays = (grid + 1) * (grid + 1) * paths * waves;
    dispatch(ctx, &pipeline, &push, rays, &buffers, false)?;
    // Each plane's light, from the traced shares: its fixed-point scale.
    let traced: &[[f32; 4]] = bytemuck::cast_slice(buffers.vertices.read()?);
    for (w, entry) in wavelengths.iter_mut().enumerate() {
        let light = |path| plane_light(traced, grid, (w * paths + path, cell_share));
        let ghosts: f64 = (1..paths).map(light).sum();
        let scale = |light: f64| match light > 0.0 {
            true => (f64::from(GHOST_FILM_FULL_SCALE) / (light * 1.001)) as f32,
            false => 0.0,
        };
        entry[2] = scale(ghosts);
        entry[3] = scale(light(0));
    }
    buffers
        .wavelengths
        .write(bytemuck::cast_slice(&wavelengths))?;
    push.step = GHOST_STEP_DRAW;
    let cells = grid * grid * paths * waves;
    dispatch(ctx, &pipeline, &push, cells, &buffers, true)?;
    let film: &[u32] = bytemuck::cast_slice(buffers.film.read()?);
    let plane = bins.columns * bins.rows;
    let unscale = |plane_index: usize, scale: f32| -> Vec<f64> {
        let at = plane_index * plane;
        film[at..at + plane]
            .iter()
            .map(|&units| match scale > 0.0 {
                true => f64::from(units) / f64::from(scale),
                false => 0.0,
            })
            .collect()
    };
    Ok(FilmLight {
        bins,
        ghosts: (0..waves)
            .map(|w| unscale(2 * w, wavelengths[w][2]))
            .collect(),
        direct: (0..waves)
            .map(|w| unscale(2 * w + 1, wavelengths[w][3]))
            .collect(),
    })
}

/// The buffers of one trace.
struct GhostBuffers {
    paths: Buffer,
    coatings: Buffer,
    wavelengths: Buffer,
    vertices: Buffer,
    film: Buffer,
    camera: Buffer,
}

impl GhostBuffers {
    /// The paths (the direct one first, then `lens`'s ghosts), the coatings and the camera,
    /// uploaded; room for the wavelengths, the traced rays and the film planes of `request`.
    fn new(
        ctx: &Arc<Context>,
        camera: &Camera,
        lens: &FlareLens,
        request: &GhostRequest,
    ) -> Result<Self, GpuError> {
        let mut paths: Vec<[u32; 4]> = vec![[0, 0, 0, 0]];
        paths.extend(
            lens.pairs()
                .iter()
                .map(|&(i, j)| [i as u32, j as u32, 1, 0]),
        );
        let coatings: Vec<[f32; 4]> = lens
            .coatings()
            .iter()
            .map(|c| match *c {
                Coating::Uncoated => [0.0; 4],
                Coating::Layer {
                    index,
                    thickness_nm,
                } => [1.0, index as f32, thickness_nm as f32, 0.0],
            })
            .collect();
        let (grid, waves) = (request.grid, request.wavelengths_nm.len());
        let rays = (grid + 1) * (grid + 1) * paths.len() * waves;
        let plane = request.bins.columns * request.bins.rows;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let host = |name, bytes: usize, usage, location| {
            Buffer::new(ctx, name, bytes as u64, usage, location)
        };
        Ok(Self {
            paths: Buffer::with_data(ctx, "ghost paths", bytemuck::cast_slice(&paths), storage)?,
            coatings: Buffer::with_data(
                ctx,
                "ghost coatings",
                bytemuck::cast_slice(&coatings),
                storage,
            )?,
            wavelengths: host(
                "ghost wavelengths",
                waves * 16,
                storage,
                MemoryLocation::CpuToGpu,
            )?,
            vertices: host(
                "ghost rays",
                rays * GHOST_VERTEX_VEC4S as usize * 16,
                storage,
                MemoryLocation::GpuToCpu,
            )?,
            film: host(
                "ghost film",
                2 * waves * plane * 4,
                storage | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
            camera: Buffer::with_data(
                ctx,
                "ghost camera",
                bytemuck::bytes_of(&crate::upload::gpu_camera(camera)),
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            )?,
        })
    }
}

/// The light a plane of traced rays (`index`: wavelength x paths + path) can draw at most: its
/// cells with four traced corners, each `cell_share` times its corners' mean share.
fn plane_light(traced: &[[f32; 4]], grid: usize, (index, cell_share): (usize, f64)) -> f64 {
    let row = grid + 1;
    let base = index * row * row;
    let vec4s = GHOST_VERTEX_VEC4S as usize;
    let corner = |v: usize| -> Option<f64> {
        let at = (base + v) * vec4s;
        (traced[at + 2][3] != 0.0).then_some(f64::from(traced[at][2]))
    };
    let mut light = 0.0;
    for gy in 0..grid {
        for gx in 0..grid {
            if let [Some(a), Some(b), Some(c), Some(d)] = cell_corners(grid, gx, gy).map(corner) {
                light += 0.25 * cell_share * (a + b + c + d);
            }
        }
    }
    light
}

/// Runs one step over `count` invocations and waits; the draw step clears the film first and
/// reads it back, the trace step reads the rays back.
fn dispatch(
    ctx: &Context,
    pipeline: &Pipeline,
    push: &GhostPush,
    count: usize,
    buffers: &GhostBuffers,
    draw: bool,
) -> Result<(), GpuError> {
    let groups = (count as u32).div_ceil(GHOST_GROUP_SIZE);
    let (x, y) = (groups.min(GROUPS_X), groups.div_ceil(GROUPS_X));
    ctx.submit_and_wait(|rec| {
        let uses = [
            (buffers.paths.buffer, Access::ComputeRead),
            (buffers.coatings.buffer, Access::ComputeRead),
            (buffers.wavelengths.buffer, Access::ComputeRead),
            (buffers.camera.buffer, Access::Uniform),
            (buffers.vertices.buffer, Access::ComputeWrite),
            (buffers.film.buffer, Access::ComputeWrite),
        ];
        if draw {
            rec.fill_buffer(&buffers.film, 0, vk::WHOLE_SIZE, 0);
        }
        rec.dispatch(pipeline, bytemuck::bytes_of(push), [x, y, 1], &uses);
        rec.read_on_host(&[&buffers.vertices, &buffers.film]);
        Ok(())
    })
}
