//! The deterministic samplers shared by every path: counter-based, so any dimension of any sample
//! of any pixel can be computed on its own, in any order, on any thread or GPU invocation.
//! `shaders/include/sampler.glsl` mirrors this module function by function with 32-bit integer arithmetic
//! only, so the GPU reproduces the CPU's samples bit for bit.
//!
//! Two kinds ([`SamplerKind`]): `sobol` (the default; Owen-scrambled Sobol' points stratified in
//! film, in lens and jointly, `scrambled_sobol.rs`) and `independent` (a hash per dimension: white
//! noise, kept for comparisons). Both are progressive: sample i does not depend on how many samples are taken,
//! so samples 0..8 then 8..16 add up to the image of 0..16.

pub mod hash;
pub mod independent;
pub mod owen;
pub mod quality;
pub mod scrambled_sobol;
pub mod sobol;

use glam::{UVec2, Vec2};
use serde::{Deserialize, Serialize};

pub use hash::{hash_u32, unit_float};
pub use independent::{independent_sample, sample_1d, sample_key};
pub use scrambled_sobol::{sobol_1d, sobol_pixel, sobol_sample, SobolPixel};

/// Sample dimensions used by the camera, the wavelength and a path's vertices (defined with
/// what the shaders share).
pub use crate::interface::{
    DIMS_PER_BOUNCE, DIM_BOUNCES, DIM_BRDF_X, DIM_BRDF_Y, DIM_DISPERSION_CHECK, DIM_EMITTERS,
    DIM_ENVIRONMENT_X, DIM_ENVIRONMENT_Y, DIM_FILM_X, DIM_FILM_Y, DIM_FRESNEL, DIM_LENS_X,
    DIM_LENS_Y, DIM_SKY_PICK, DIM_TIME, DIM_WAVELENGTH,
};

/// The dimensions vertex `vertex` (0: the camera ray's hit) of a path draws from: its
/// environment pair (x, y), then its BRDF pair. Each pair starts at an even dimension, so that
/// it is one of the sampler's stratified (0, 2) pairs.
#[inline]
pub fn vertex_dimensions(vertex: u32) -> [u32; 4] {
    if vertex == 0 {
        return [DIM_ENVIRONMENT_X, DIM_ENVIRONMENT_Y, DIM_BRDF_X, DIM_BRDF_Y];
    }
    let first = DIM_BOUNCES + DIMS_PER_BOUNCE * (vertex - 1);
    [first, first + 1, first + 2, first + 3]
}

/// The pair of dimensions vertex `vertex` (0: the camera ray's hit) of a path draws its point
/// on the emissive triangles from (`reference::emitters`). It starts at an even dimension, so
/// it is one of the sampler's stratified (0, 2) pairs.
#[inline]
pub fn emitter_dimensions(vertex: u32) -> [u32; 2] {
    let first = DIM_EMITTERS + 2 * vertex;
    [first, first + 1]
}

/// The dimension vertex `vertex` (0: the camera ray's hit) of a path picks with whether the
/// microfacet its glass draw found reflects or refracts (`MetallicRoughness::sample`).
#[inline]
pub fn fresnel_dimension(vertex: u32) -> u32 {
    DIM_FRESNEL + vertex
}

/// The dimension vertex `vertex` (0: the camera ray's hit) of a path picks with which of the
/// map's candidate directions its sky light goes along (`reference::sky::sky_draw`).
#[inline]
pub fn sky_pick_dimension(vertex: u32) -> u32 {
    DIM_SKY_PICK + vertex
}

/// How samples are drawn. The discriminants are the shaders' `SAMPLER_*` constants.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
#[repr(u32)]
pub enum SamplerKind {
    /// Owen-scrambled Sobol' points: film and lens each stratified, error falling about as
    /// N^-0.75 (at powers of two) instead of N^-0.5.
    #[default]
    Sobol = 0,
    /// Independent random numbers per dimension (white noise), for comparisons.
    Independent = 1,
}

impl SamplerKind {
    pub const ALL: [SamplerKind; 2] = [Self::Sobol, Self::Independent];

    /// The value of the shaders' `sampler` parameter (`SAMPLER_SOBOL`, `SAMPLER_INDEPENDENT`).
    pub fn id(self) -> u32 {
        match self {
            SamplerKind::Sobol => crate::interface::SAMPLER_SOBOL,
            SamplerKind::Independent => crate::interface::SAMPLER_INDEPENDENT,
        }
    }

    /// The name used on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Sobol => "sobol",
            SamplerKind::Independent => "independent",
        }
    }
}

impl std::fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The key of one (seed, pixel) pair, from which every sampler draws that pixel's samples.
#[inline]
pub fn pixel_key(seed: u32, pixel_index: u32) -> u32 {
    hash_u32(hash_u32(seed) ^ pixel_index)
}

/// Dimension `dim` of sample `sample_index` of pixel `pixel_index` (row * width + column),
/// uniform in [0, 1), computed on its own.
#[inline]
pub fn sample_dimension(
    kind: SamplerKind,
    seed: u32,
    pixel_index: u32,
    sample_index: u32,
    dim: u32,
) -> f32 {
    match kind {
        SamplerKind::Sobol => sobol_1d(pixel_key(seed, pixel_index), sample_index, dim),
        SamplerKind::Independent => sample_1d(sample_key(seed, pixel_index, sample_index), dim),
    }
}

/// What the camera needs of one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// Raster position (column + u, row + v): uniform over the pixel (box filter).
    pub film: Vec2,
    /// Uniform in [0, 1)^2, mapped to the aperture disk by the lens.
    pub lens: Vec2,
    /// Where in the shutter's time the sample is taken, in [0, 1): drawn (`Camera::sample_time`)
    /// only while the camera moves, [`CameraSample::MIDDLE`] otherwise.
    pub time: f32,
}

impl CameraSample {
    /// The shutter's middle: a still camera's samples' time.
    pub const MIDDLE: f32 = 0.5;

    /// The sample at film point `film` and lens sample `lens`, at the shutter's middle.
    pub fn new(film: Vec2, lens: Vec2) -> Self {
        Self {
            film,
            lens,
            time: Self::MIDDLE,
        }
    }
}

/// What drawing a pixel's camera samples needs, computed once per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelSampler {
    pub kind: SamplerKind,
    pub pixel: UVec2,
    /// [`pixel_key`] (used as is by the independent sampler).
    pub key: u32,
    /// The Sobol' sampler's seeds (zero for the independent sampler).
    pub sobol: SobolPixel,
}

/// The sampler of pixel (column, row) of an image `width` pixels wide.
#[inline]
pub fn pixel_sampler(kind: SamplerKind, seed: u32, pixel: UVec2, width: u32) -> PixelSampler {
    let key = pixel_key(seed, pixel.y * width + pixel.x);
    PixelSampler {
        kind,
        pixel,
        key,
        sobol: match kind {
            SamplerKind::Sobol => sobol_pixel(key),
            SamplerKind::Independent => SobolPixel::default(),
        },
    }
}

/// The sampler of pixel (column, row) when every pixel draws the same camera samples: those of
/// pixel (0, 0), offset to this pixel (`RenderSettings::shared_samples`). Each pixel's estimate
/// stays unbiased and stratified; only neighbours are no longer independent.
#[inline]
pub fn shared_pixel_sampler(kind: SamplerKind, seed: u32, pixel: UVec2) -> PixelSampler {
    PixelSampler {
        pixel,
        ..pixel_sampler(kind, seed, UVec2::ZERO, 1)
    }
}

/// Dimension `dim` of sample `sample_index` of the sampler's pixel, as [`sample_dimension`]
/// gives it for that pixel (with shared samples: pixel (0, 0)'s).
#[inline]
pub fn pixel_dimension(state: &PixelSampler, sample_index: u32, dim: u32) -> f32 {
    match state.kind {
        SamplerKind::Sobol => sobol_1d(state.key, sample_index, dim),
        SamplerKind::Independent => sample_1d(hash_u32(state.key ^ sample_index), dim),
    }
}

/// Sample `sample_index` of the sampler's pixel.
#[inline]
pub fn pixel_camera_sample(state: &PixelSampler, sample_index: u32) -> CameraSample {
    let [film_x, film_y, lens_x, lens_y] = match state.kind {
        SamplerKind::Sobol => sobol_sample(&state.sobol, sample_index),
        SamplerKind::Independent => independent_sample(state.key, sample_index),
    };
    CameraSample::new(
        Vec2::new(state.pixel.x as f32 + film_x, state.pixel.y as f32 + film_y),
        Vec2::new(lens_x, lens_y),
    )
}

/// Film x, film y, lens x and lens y of samples `first..first + N` of the sampler's pixel, as
/// [`pixel_camera_sample`] gives them, computed lane by lane so that the compiler vectorizes the
/// integer work (the CPU renderer's packets; the shaders need no such batch).
#[inline]
pub fn pixel_camera_samples<const N: usize>(state: &PixelSampler, first: u32) -> [[f32; N]; 4] {
    pixel_camera_samples_of(
        state,
        &std::array::from_fn(|lane| first.wrapping_add(lane as u32)),
    )
}

/// [`pixel_camera_samples`] of the samples `indices` names, lane by lane.
#[inline]
pub fn pixel_camera_samples_of<const N: usize>(
    state: &PixelSampler,
    indices: &[u32; N],
) -> [[f32; N]; 4] {
    let mut dims = [[0.0f32; N]; 4];
    match state.kind {
        SamplerKind::Sobol => {
            for (lane, &index) in indices.iter().enumerate() {
                let u = sobol_sample(&state.sobol, index);
                for (dim, value) in dims.iter_mut().zip(u) {
                    dim[lane] = value;
                }
            }
        }
        SamplerKind::Independent => {
            for (lane, &index) in indices.iter().enumerate() {
                let u = independent_sample(state.key, index);
                for (dim, value) in dims.iter_mut().zip(u) {
                    dim[lane] = value;
                }
            }
        }
    }
    let (x, y) = (state.pixel.x as f32, state.pixel.y as f32);
    dims[0].iter_mut().for_each(|v| *v += x);
    dims[1].iter_mut().for_each(|v| *v += y);
    dims
}

/// Sample `sample_index` of pixel (column, row) of an image `width` pixels wide.
#[inline]
pub fn camera_sample(
    kind: SamplerKind,
    seed: u32,
    pixel: UVec2,
    width: u32,
    sample_index: u32,
) -> CameraSample {
    pixel_camera_sample(&pixel_sampler(kind, seed, pixel, width), sample_index)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn emitter_pairs_follow_every_vertex_pair() {
        let last = vertex_dimensions(crate::interface::MAX_BOUNCES - 1);
        for vertex in 0..crate::interface::MAX_BOUNCES {
            let [x, y] = emitter_dimensions(vertex);
            assert!(x % 2 == 0 && y == x + 1, "vertex {vertex}: ({x}, {y})");
            assert!(
                x > last[3],
                "vertex {vertex}: {x} within the vertices' {last:?}"
            );
        }
    }

    #[test]
    fn fresnel_choices_follow_every_other_dimension() {
        let others = [
            DIM_TIME,
            emitter_dimensions(crate::interface::MAX_BOUNCES - 1)[1],
        ];
        for vertex in 0..crate::interface::MAX_BOUNCES {
            let d = fresnel_dimension(vertex);
            assert!(
                others.iter().all(|&o| d > o),
                "vertex {vertex}: {d} within {others:?}"
            );
        }
    }

    #[test]
    fn sky_picks_follow_every_fresnel_choice() {
        let last = fresnel_dimension(crate::interface::MAX_BOUNCES - 1);
        for vertex in 0..crate::interface::MAX_BOUNCES {
            let d = sky_pick_dimension(vertex);
            assert!(
                d > last,
                "vertex {vertex}: {d} within the Fresnel choices (last {last})"
            );
        }
    }

    #[test]
    fn film_sample_stays_in_its_pixel() {
        for kind in SamplerKind::ALL {
            for s in 0..256 {
                let c = camera_sample(kind, 1, UVec2::new(5, 9), 16, s);
                assert!(c.film.x >= 5.0 && c.film.x < 6.0 && c.film.y >= 9.0 && c.film.y < 10.0);
                assert!(c.lens.cmpge(Vec2::ZERO).all() && c.lens.cmplt(Vec2::ONE).all());
            }
        }
    }

    #[test]
    fn pixel_dimensions_are_the_dimensions_on_their_own() {
        for kind in SamplerKind::ALL {
            let state = pixel_sampler(kind, 11, UVec2::new(5, 3), 640);
            for s in 0..64 {
                for dim in 0..8 {
                    let alone = sample_dimension(kind, 11, 3 * 640 + 5, s, dim);
                    assert_eq!(pixel_dimension(&state, s, dim).to_bits(), alone.to_bits());
                }
            }
        }
    }

    #[test]
    fn camera_sample_is_the_four_dimensions() {
        for kind in SamplerKind::ALL {
            for (x, y) in [(0u32, 0u32), (639, 479), (17, 3)] {
                for s in [0u32, 1, 15, 16, 1000, u32::MAX] {
                    let c = camera_sample(kind, 11, UVec2::new(x, y), 640, s);
                    let dim = |d| sample_dimension(kind, 11, y * 640 + x, s, d);
                    assert_eq!(c.film, Vec2::new(x as f32 + dim(0), y as f32 + dim(1)));
                    assert_eq!(c.lens, Vec2::new(dim(2), dim(3)));
                }
            }
        }
    }

    #[test]
    fn batches_equal_single_samples() {
        for kind in SamplerKind::ALL {
            let state = pixel_sampler(kind, 5, UVec2::new(600, 400), 640);
            for first in [0u32, 16, 1 << 20, u32::MAX - 7] {
                let [fx, fy, lx, ly] = pixel_camera_samples::<16>(&state, first);
                for lane in 0..16 {
                    let c = pixel_camera_sample(&state, first.wrapping_add(lane as u32));
                    assert_eq!(
                        [fx[lane], fy[lane], lx[lane], ly[lane]].map(f32::to_bits),
                        [c.film.x, c.film.y, c.lens.x, c.lens.y].map(f32::to_bits),
                        "{kind} lane {lane} from {first}"
                    );
                }
            }
        }
    }

    #[test]
    fn kinds_parse_and_name_themselves() {
        for kind in SamplerKind::ALL {
            // A scene file's `sampler` reads the same name.
            let name: serde::de::value::StrDeserializer<serde::de::value::Error> =
                serde::de::IntoDeserializer::into_deserializer(kind.name());
            let parsed = SamplerKind::deserialize(name).expect("a known name");
            assert_eq!(parsed, kind);
        }
        assert_eq!(SamplerKind::default(), SamplerKind::Sobol);
        assert_eq!(SamplerKind::Sobol.id(), 0);
        assert_eq!(SamplerKind::Independent.id(), 1);
    }

    /// Whether samples `first..first + 2^k` of pixel (0, 0) put one film point and one lens point
    /// in each elementary interval of area 2^-k (film positions are exact at pixel 0).
    fn stratified(kind: SamplerKind, seed: u32, first: u32, k: u32) -> bool {
        let samples: Vec<CameraSample> = (first..first + (1 << k))
            .map(|s| camera_sample(kind, seed, UVec2::ZERO, 64, s))
            .collect();
        let one_per_cell = |point: &dyn Fn(&CameraSample) -> Vec2, a: u32| {
            let mut seen = vec![false; 1 << k];
            for c in &samples {
                let p = point(c);
                let column = (p.x * (1u32 << a) as f32) as usize;
                let row = (p.y * (1u32 << (k - a)) as f32) as usize;
                seen[(column << (k - a)) | row] = true;
            }
            seen.iter().all(|&s| s)
        };
        (0..=k).all(|a| one_per_cell(&|c| c.film, a) && one_per_cell(&|c| c.lens, a))
    }

    #[test]
    fn camera_samples_are_stratified_in_film_and_lens() {
        for seed in [0, 1, 77] {
            for k in 0..=8 {
                for first in [0, 1 << k, 5 << k] {
                    assert!(
                        stratified(SamplerKind::Sobol, seed, first, k),
                        "seed {seed}: samples {first}..{} are not stratified",
                        first + (1 << k)
                    );
                }
            }
        }
        // The control: independent samples leave intervals empty.
        assert!(!stratified(SamplerKind::Independent, 0, 0, 4));
    }

    #[test]
    fn sobol_camera_samples_are_uniform() {
        // Mean and variance of each dimension over 64 pixels x 1024 samples.
        let mut sums = [[0.0f64; 2]; 4];
        let n = 64 * 1024;
        for p in 0..64u32 {
            let sampler = pixel_sampler(SamplerKind::Sobol, 3, UVec2::new(p % 8, p / 8), 8);
            for s in 0..1024 {
                let c = pixel_camera_sample(&sampler, s);
                let u = [c.film.x.fract(), c.film.y.fract(), c.lens.x, c.lens.y];
                for (sum, v) in sums.iter_mut().zip(u) {
                    sum[0] += v as f64;
                    sum[1] += (v as f64) * (v as f64);
                }
            }
        }
        for (dim, [sum, sum_sq]) in sums.iter().enumerate() {
            let mean = sum / n as f64;
            let var = sum_sq / n as f64 - mean * mean;
            assert!((mean - 0.5).abs() < 1e-3, "dimension {dim}: mean {mean}");
            assert!(
                (var - 1.0 / 12.0).abs() < 1e-3,
                "dimension {dim}: variance {var}"
            );
        }
    }
}
