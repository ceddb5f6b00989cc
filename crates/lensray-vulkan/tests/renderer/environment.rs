//! The GLSL mirror of the environment map (shaders/include/environment.glsl) against
//! lensray-core's scene::environment on the device, validation on: the same point draws the same
//! texel (exactly: the tables are the host's, the comparisons the same float operations), and
//! the directions, densities and lookups agree to the precision of the GPU's trigonometry.

use glam::{Vec2, Vec3};
use lensray_core::scene::environment::{EnvironmentMap, EnvironmentSampler};
use lensray_vulkan::probe_environment;

use crate::support::*;

/// A 2:1 sky with a sun, black below the horizon (rows of weight 0 at the end of the table).
fn sky() -> EnvironmentMap {
    let (w, h) = (64u32, 32u32);
    let texels = (0..w * h)
        .map(|i| {
            let (column, row) = (i % w, i / w);
            if row >= h / 2 {
                Vec3::ZERO
            } else if (column, row) == (40, 6) {
                Vec3::new(5e4, 4.8e4, 4.5e4)
            } else {
                Vec3::new(0.2, 0.3, 0.5) * (1.0 + row as f32 * 0.1)
                    + Vec3::splat(column as f32 * 0.01)
            }
        })
        .collect();
    EnvironmentMap::new(w, h, texels)
        .expect("sizes agree")
        .turned(30.0, 2.0)
}

/// Points to sample by (R2 and the tables' own boundaries) and directions to look up (a
/// Fibonacci sphere).
fn queries(sampler: &EnvironmentSampler) -> Vec<(Vec2, Vec3)> {
    let total = sampler.total();
    let mut points: Vec<Vec2> = (0..4096)
        .map(|i| {
            let i = i as f64 + 0.5;
            Vec2::new(
                (i * 0.754_877_666_246_692_7).fract() as f32,
                (i * 0.569_840_290_998_053_2).fract() as f32,
            )
        })
        .collect();
    points.extend(
        sampler
            .rows_cdf()
            .iter()
            .map(|&c| Vec2::new(0.5, c / total)),
    );
    points.extend([Vec2::ZERO, Vec2::splat(1.0 - f32::EPSILON)]);
    let count = points.len();
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    points
        .into_iter()
        .enumerate()
        .map(|(i, u)| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f32;
            (u, Vec3::new(r * phi.cos(), y, r * phi.sin()))
        })
        .collect()
}

#[test]
fn environment_mirror_draws_the_same_texels() {
    let Some((gpu, log)) = renderer("environment_mirror_draws_the_same_texels") else {
        return;
    };
    let map = sky();
    let sampler = EnvironmentSampler::new(&map).expect("the sky emits");
    let queries = queries(&sampler);
    let results = probe_environment(&gpu, &map, Some(&sampler), &queries).expect("probe");
    let (mut worst_direction, mut worst_pdf, mut boundary_lookups) = (0.0f32, 0.0f32, 0);
    let mut worst_uv = 0.0f32;
    for (k, (&(u, d), got)) in queries.iter().zip(&results).enumerate() {
        let want = sampler.sample(&map, u);
        let want_texel = want.map(|s| s.texel.0 + s.texel.1 * map.width);
        assert_eq!(
            got.texel, want_texel,
            "query {k}: point {u} drew another texel"
        );
        if let Some(s) = want {
            assert_eq!(got.radiance, s.radiance, "query {k}: the texel's radiance");
            worst_direction = worst_direction.max((got.direction - s.direction).length());
            worst_pdf = worst_pdf.max((got.pdf - s.pdf).abs() / s.pdf);
        }
        let uv = map.uv_from_world(d);
        let du = (got.lookup_uv.x - uv.x).abs();
        let duv = du.min(1.0 - du).max((got.lookup_uv.y - uv.y).abs());
        worst_uv = worst_uv.max(duv);
        // Vulkan lets atan and acos be off by 4096 ulps; lavapipe's put (u, v) within 5e-5.
        assert!(
            duv < 1e-4,
            "query {k}: direction {d} at {} on the GPU, {uv} on the host",
            got.lookup_uv
        );
        if got.lookup_radiance != map.radiance(d) {
            // Only where the two land either side of a texel's edge.
            let texel = uv * Vec2::new(map.width as f32, map.height as f32);
            let edge = (texel - texel.round()).abs().min_element();
            assert!(
                edge < 1e-3,
                "query {k}: {d} looks up another texel, {edge} from an edge"
            );
            boundary_lookups += 1;
        } else {
            // The density goes as 1 / sin(theta), theta = pi v: the GPU's acos puts v a few
            // ulps off, which near the poles moves sin(theta) by pi dv cot(theta) relatively.
            let pdf = sampler.pdf(&map, d);
            let dv = (got.lookup_uv.y - uv.y).abs();
            let theta = uv.y * std::f32::consts::PI;
            let bound = 1e-5 + 2.0 * std::f32::consts::PI * dv / theta.tan().abs().max(1e-6);
            let relative = if pdf == 0.0 {
                got.lookup_pdf.abs()
            } else {
                (got.lookup_pdf - pdf).abs() / pdf
            };
            assert!(
                relative <= bound,
                "query {k}: pdf {pdf} vs {} ({relative:.2e} relative, bound {bound:.2e}, v {} vs {})",
                got.lookup_pdf,
                uv.y,
                got.lookup_uv.y
            );
        }
    }
    println!(
        "environment mirror: {} queries, worst direction {worst_direction:.2e}, worst pdf \
         {worst_pdf:.2e} (relative), worst uv {worst_uv:.2e}, {boundary_lookups} lookups on a \
         texel's edge",
        queries.len()
    );
    assert!(
        worst_direction < 2e-6,
        "directions differ by {worst_direction}"
    );
    assert!(
        worst_pdf < 1e-4,
        "densities differ by {worst_pdf} (relative)"
    );
    assert!(
        boundary_lookups <= 4,
        "{boundary_lookups} lookups on an edge"
    );
    finish(gpu, log);
}
