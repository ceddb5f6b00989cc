//! What GLSL mirrors of Rust must agree on: the shared structs' layouts, and the sampler and
//! camera functions evaluated on the device against their Rust originals.

use glam::{UVec2, Vec2, Vec3};
use lensray_core::camera::{Aperture, ApertureShape, Camera, LensParams};
use lensray_core::sampler::owen::{owen_scramble_reversed, shuffle_index};
use lensray_core::sampler::sobol::{lens_index, sobol_reversed};
use lensray_core::sampler::{
    camera_sample, hash_u32, sample_1d, sample_dimension, sample_key, CameraSample, SamplerKind,
};
use lensray_vulkan::{ProbeQuery, ProbeResult};

use crate::support::*;

/// The sampler kinds the mirror probe alternates between, indexed by their ids.
const KINDS: [SamplerKind; 2] = [SamplerKind::Sobol, SamplerKind::Independent];

/// Every field of every struct shared with the shaders (lensray-core/src/interface) is read by GLSL where
/// Rust wrote it: std140 ones through a uniform block, std430 ones through a storage buffer,
/// the marked one through push constants too; no struct of the interface's list is left out.
#[test]
fn shader_layouts_match_rust() {
    use lensray_core::interface::glsl::{ProbeBlock, LAYOUT_PROBE_COPIES};
    use lensray_core::interface::shared_structs;

    let Some((mut gpu, log)) = renderer("shader_layouts_match_rust") else {
        return;
    };
    let report = gpu.probe_layouts().expect("layout probe");
    let structs = shared_structs();
    // Each struct of the list, in order, in its layout's block, then the pushed one.
    let probed: Vec<(&str, ProbeBlock, usize)> = report
        .blocks
        .iter()
        .map(|b| (b.rust, b.block, b.copies))
        .collect();
    let mut expected: Vec<(&str, ProbeBlock, usize)> = structs
        .iter()
        .map(|s| (s.rust, ProbeBlock::of(s.layout), LAYOUT_PROBE_COPIES))
        .collect();
    expected.extend(
        structs
            .iter()
            .filter(|s| s.probe_push)
            .map(|s| (s.rust, ProbeBlock::PushConstant, 1)),
    );
    assert_eq!(probed, expected, "the probe must read every shared struct");
    assert!(
        expected.iter().any(|e| e.1 == ProbeBlock::PushConstant),
        "a struct must be read through push constants"
    );
    let scalars: usize = structs
        .iter()
        .map(|s| s.scalars.len() * (LAYOUT_PROBE_COPIES + usize::from(s.probe_push)))
        .sum();
    assert_eq!(report.scalars_checked, scalars);
    println!(
        "layout probe: {} structs, {} blocks, {} scalars",
        structs.len(),
        report.blocks.len(),
        report.scalars_checked
    );
    assert!(
        report.mismatches.is_empty(),
        "{} of {} scalars are read elsewhere than Rust wrote them:\n{}",
        report.mismatches.len(),
        report.scalars_checked,
        report.mismatches.join("\n")
    );
    finish(gpu, log);
}

/// A built aperture of the given shape, without an image.
fn shape(blades: Option<u32>, rotation_degrees: f32, roundness: f32, aspect: f32) -> Aperture {
    ApertureShape {
        blades,
        rotation_degrees,
        roundness,
        aspect,
        image: None,
    }
    .build()
    .expect("a valid aperture")
}

/// The cameras the mirrors are probed with: round, then every kind of shaped aperture
/// (straight blades, odd and even; curved; squeezed; an image), on both projections, then
/// shifted and tilted (`MOVED`) on both.
fn mirror_cameras() -> [Camera; 10] {
    let moved = |orthographic| {
        moved_camera(
            orthographic,
            LensParams::ThinLens {
                aperture_radius: 0.2,
                focus_distance: 4.0,
            },
            97,
            61,
            MOVED,
        )
    };
    let image = odd_aperture_image().build().expect("a valid aperture");
    let perspective = camera(
        false,
        LensParams::ThinLens {
            aperture_radius: 0.2,
            focus_distance: 4.0,
        },
        97,
        61,
    );
    let orthographic = camera(
        true,
        LensParams::ThinLens {
            aperture_radius: 0.1,
            focus_distance: 3.0,
        },
        97,
        61,
    );
    [
        perspective.clone(),
        orthographic.clone(),
        perspective
            .clone()
            .with_aperture(shape(Some(6), 15.0, 0.0, 1.0))
            .expect("a thin lens takes any aperture"),
        perspective
            .clone()
            .with_aperture(shape(Some(5), -30.0, 0.4, 1.5))
            .expect("a thin lens takes any aperture"),
        perspective
            .clone()
            .with_aperture(shape(None, 0.0, 0.0, 2.0))
            .expect("a thin lens takes any aperture"),
        orthographic
            .clone()
            .with_aperture(shape(Some(9), 0.0, 0.7, 0.5))
            .expect("a thin lens takes any aperture"),
        perspective
            .with_aperture(image.clone())
            .expect("a thin lens takes any aperture"),
        orthographic
            .with_aperture(image)
            .expect("a thin lens takes any aperture"),
        moved(false),
        moved(true),
    ]
}

/// 4096 probe queries on `cam`: pixels, seeds, sample indices, dimensions, hash inputs and
/// sampler kinds varied together.
fn mirror_queries(cam: &Camera) -> Vec<ProbeQuery> {
    (0..4096u32)
        .map(|i| ProbeQuery {
            seed: hash_u32(i / 64),
            pixel_x: i % cam.width,
            pixel_y: (i / 7) % cam.height,
            width: cam.width,
            // Small indices and large ones (the shuffled lens index uses all 32 bits).
            sample_index: if i % 5 == 0 { hash_u32(i) } else { i % 33 },
            // Every dimension a render draws, the wavelength's (DIM_WAVELENGTH) included.
            dim: i % 8,
            hash_input: i.wrapping_mul(0x9e37_79b9) ^ (i << 7),
            sampler_kind: KINDS[(i / 2) as usize % 2].id(),
            wavelength_nm: 0.0,
        })
        .collect()
}

/// Checks the sampler mirrors of query `q` bit for bit (hash, key, 1-D sample, lens index, Owen
/// scrambling, Sobol' points, sample dimension, camera sample); returns the Rust camera sample.
fn check_sampler_mirrors(q: &ProbeQuery, r: &ProbeResult) -> CameraSample {
    assert_eq!(r.hash, hash_u32(q.hash_input), "hash_u32({})", q.hash_input);
    let pixel_index = q.pixel_y * q.width + q.pixel_x;
    let key = sample_key(q.seed, pixel_index, q.sample_index);
    assert_eq!(r.key, key, "sample_key for {q:?}");
    assert_eq!(
        r.sample_bits,
        sample_1d(key, q.dim).to_bits(),
        "sample_1d for {q:?}"
    );
    let (x, seed) = (q.hash_input, q.seed);
    assert_eq!(
        [r.lens, r.scrambled, r.shuffled, r.sobol],
        [
            lens_index(x),
            owen_scramble_reversed(x, seed),
            shuffle_index(x, seed),
            sobol_reversed(q.dim % 2, x),
        ],
        "lens index, Owen scrambling and Sobol' points of {x:#x} with seed {seed:#x}"
    );
    let kind = KINDS[q.sampler_kind as usize];
    assert_eq!(kind.id(), q.sampler_kind);
    assert_eq!(
        r.dimension_bits,
        sample_dimension(kind, q.seed, pixel_index, q.sample_index, q.dim).to_bits(),
        "sample_dimension for {q:?}"
    );
    let cs = camera_sample(
        kind,
        q.seed,
        UVec2::new(q.pixel_x, q.pixel_y),
        q.width,
        q.sample_index,
    );
    let gpu_cs = r.camera_sample;
    assert_eq!(
        [cs.film.x, cs.film.y, cs.lens.x, cs.lens.y].map(f32::to_bits),
        gpu_cs.map(f32::to_bits),
        "camera_sample for {q:?}"
    );
    cs
}

/// Checks the camera mirrors of query `q` with camera sample `cs`: the lens point and the ray
/// through a thin lens; returns the camera ray's relative error, bounded over all queries.
fn check_camera_mirrors(cam: &Camera, q: &ProbeQuery, r: &ProbeResult, cs: &CameraSample) -> f32 {
    // Lens points of a bladed aperture or an image: additions, multiplications,
    // divisions and table searches on both sides (`precise` in GLSL), bit for bit. The
    // disk's sine and cosine are the GPU's own, within a few units in the last place.
    let lens = cam.lens.first_order().lens_point(cs.lens);
    let gpu_lens = Vec2::new(r.lens_point[0], r.lens_point[1]);
    let disk = cam.lens.first_order().aperture.fan().is_empty()
        && cam.lens.first_order().aperture.image().is_none();
    if disk {
        let err = (gpu_lens - lens).length() / cam.lens.first_order().reach();
        assert!(err < 1e-6, "lens_point {lens} vs {gpu_lens} for {q:?}");
    } else {
        assert_eq!(
            lens.to_array().map(f32::to_bits),
            gpu_lens.to_array().map(f32::to_bits),
            "lens_point of {:?} for {q:?}",
            cam.lens.first_order().aperture.shape
        );
    }
    // Rays: same formulas, but GPU transcendentals and fused operations may differ in
    // the last bits.
    let ray = cam.first_order_ray(*cs);
    let o = Vec3::new(r.origin[0], r.origin[1], r.origin[2]);
    let d = Vec3::new(r.direction[0], r.direction[1], r.direction[2]);
    let err =
        (o - ray.origin).length() / (1.0 + ray.origin.length()) + (d - ray.direction).length();
    // A thin lens: the ray through the lens is that ray, weight 1 (the app's tests/gpu_lens.rs
    // checks real lenses).
    assert_eq!(
        r.through_lens_origin,
        [r.origin[0], r.origin[1], r.origin[2], 1.0],
        "generate_ray for {q:?}"
    );
    assert_eq!(r.through_lens_direction, r.direction);
    err
}

#[test]
fn sampler_and_camera_mirrors_match_rust() {
    let Some((mut gpu, log)) = renderer("sampler_and_camera_mirrors_match_rust") else {
        return;
    };
    for cam in &mirror_cameras() {
        let queries = mirror_queries(cam);
        let results = gpu.probe_mirrors(cam, &queries).expect("probe");
        let mut worst_ray = 0.0f32;
        for (q, r) in queries.iter().zip(&results) {
            let cs = check_sampler_mirrors(q, r);
            worst_ray = worst_ray.max(check_camera_mirrors(cam, q, r, &cs));
        }
        assert!(worst_ray < 1e-5, "first_order_ray differs by {worst_ray}");
    }
    finish(gpu, log);
}
