use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::*;

/// A 2:1 map whose texel (column, row) holds `f(column, row)`.
fn map_of(width: u32, height: u32, f: impl Fn(u32, u32) -> Vec3) -> EnvironmentMap {
    let texels = (0..height)
        .flat_map(|row| (0..width).map(move |column| (column, row)))
        .map(|(column, row)| f(column, row))
        .collect();
    EnvironmentMap::new(width, height, texels).expect("sizes agree")
}

/// A smooth sky: bright near the top, a warm hot spot, dark below the horizon.
fn sky() -> EnvironmentMap {
    map_of(64, 32, |column, row| {
        let up = 1.0 - row as f32 / 32.0;
        let spot = if (10..13).contains(&column) && (8..11).contains(&row) {
            40.0
        } else {
            0.0
        };
        Vec3::new(0.2 + up + spot, 0.3 + up, 0.5 + up * 1.5 + spot * 0.5)
    })
}

/// The sky with a sun: one texel 50,000 times brighter than the sky around it, as a clear
/// day's HDR holds.
fn sky_with_sun() -> EnvironmentMap {
    let mut map = sky();
    map.texels[6 * 64 + 40] = Vec3::new(5e4, 4.8e4, 4.5e4);
    map
}

/// The integral of `f` over directions with theta in [0, `theta_max`], by the midpoint rule
/// over `n_theta` x `n_phi` cells of (theta, phi).
fn quadrature(n_theta: u32, n_phi: u32, theta_max: f32, f: impl Fn(Vec3) -> f32) -> f64 {
    let mut sum = 0.0f64;
    for i in 0..n_theta {
        let theta = (i as f32 + 0.5) / n_theta as f32 * theta_max;
        for j in 0..n_phi {
            let phi = (j as f32 + 0.5) / n_phi as f32 * 2.0 * PI;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let area = theta.sin() * (theta_max / n_theta as f32) * (2.0 * PI / n_phi as f32);
            sum += f64::from(f(d) * area);
        }
    }
    sum
}

/// The R2 sequence (Roberts 2018): points of [0, 1)^2 with low discrepancy.
fn r2(i: u32) -> Vec2 {
    const A: f64 = 0.754_877_666_246_692_7;
    const B: f64 = 0.569_840_290_998_053_2;
    let i = f64::from(i) + 0.5;
    Vec2::new((i * A).fract() as f32, (i * B).fract() as f32)
}

#[test]
fn the_centre_column_looks_along_minus_z_and_the_top_row_up() {
    let map = map_of(8, 4, |_, _| Vec3::ONE);
    let centre = map.world_from_uv(Vec2::new(0.5, 0.5));
    assert!((centre - Vec3::NEG_Z).length() < 1e-6, "{centre}");
    assert!((map.world_from_uv(Vec2::new(0.3, 0.0)) - Vec3::Y).length() < 1e-6);
    // u grows towards +X.
    let quarter = map.world_from_uv(Vec2::new(0.75, 0.5));
    assert!((quarter - Vec3::X).length() < 1e-6, "{quarter}");
    // Turned 90 degrees counter-clockwise seen from above, what was ahead (-Z) is on the left
    // (-X).
    let turned = map.turned(90.0, 1.0);
    let ahead = turned.world_from_uv(Vec2::new(0.5, 0.5));
    assert!((ahead - Vec3::NEG_X).length() < 1e-6, "{ahead}");
}

#[test]
fn uv_and_direction_are_inverses() {
    let map = sky().turned(37.0, 2.0);
    for i in 0..500 {
        let uv = r2(i) * Vec2::new(1.0, 0.98) + Vec2::new(0.0, 0.01);
        let back = map.uv_from_world(map.world_from_uv(uv));
        let du = (back.x - uv.x).abs().min(1.0 - (back.x - uv.x).abs());
        assert!(du < 1e-5 && (back.y - uv.y).abs() < 1e-5, "{uv} -> {back}");
    }
}

#[test]
fn the_density_integrates_to_one_over_the_sphere() {
    let map = sky().turned(-20.0, 3.0);
    let sampler = EnvironmentSampler::new(&map).expect("the sky emits");
    // 4 points a texel each way.
    let integral = quadrature(128, 256, PI, |d| sampler.pdf(&map, d));
    assert!(
        (integral - 1.0).abs() < 2e-3,
        "integral of the pdf: {integral}"
    );
}

#[test]
fn a_sample_carries_the_density_of_its_direction_and_the_radiance_there() {
    let map = sky().turned(15.0, 0.5);
    let sampler = EnvironmentSampler::new(&map).expect("the sky emits");
    for i in 0..2000 {
        let s = sampler.sample(&map, r2(i)).expect("a sample");
        let pdf = sampler.pdf(&map, s.direction);
        assert!(
            (pdf - s.pdf).abs() <= 1e-3 * s.pdf,
            "sample {i}: carried pdf {} vs pdf of its direction {pdf}",
            s.pdf
        );
        assert_eq!(s.radiance, map.radiance(s.direction), "sample {i}");
        assert!((s.direction.length() - 1.0).abs() < 1e-5);
    }
}

#[test]
fn one_bright_texel_draws_every_sample() {
    let map = map_of(16, 8, |c, r| {
        if (c, r) == (5, 2) {
            Vec3::splat(7.0)
        } else {
            Vec3::ZERO
        }
    });
    let sampler = EnvironmentSampler::new(&map).expect("one texel emits");
    for i in 0..300 {
        let s = sampler.sample(&map, r2(i)).expect("a sample");
        assert_eq!(s.texel, (5, 2));
        assert_eq!(map.texel_at(map.uv_from_world(s.direction)), (5, 2));
        assert_eq!(s.radiance, Vec3::splat(7.0));
    }
    assert!(EnvironmentSampler::new(&map_of(16, 8, |_, _| Vec3::ZERO)).is_none());
}

/// Irradiance at an upward-facing point under a sky with a sun, E = integral of L cos(theta):
/// by quadrature, by sampling the environment, and by sampling the cosine. Both estimates
/// agree with the quadrature; the environment's samples, drawn where the light is, vary far
/// less (the variance of one sample's estimate).
#[test]
fn sampling_the_environment_estimates_irradiance_with_less_variance_than_the_cosine() {
    let map = sky_with_sun().turned(50.0, 1.0);
    let sampler = EnvironmentSampler::new(&map).expect("the sky emits");
    let n = Vec3::Y;
    // The upper hemisphere, in the cells of a 256 x 512 sphere.
    let exact = quadrature(128, 512, PI / 2.0, |d| {
        luminance(map.radiance(d)) * d.dot(n)
    });
    let count = 4096;
    let (mut map_values, mut cosine_values) = (Vec::new(), Vec::new());
    for i in 0..count {
        let s = sampler.sample(&map, r2(i)).expect("a sample");
        map_values.push(f64::from(
            luminance(s.radiance) * s.direction.dot(n).max(0.0) / s.pdf,
        ));
        let u = r2(i);
        let (r, phi) = (u.x.sqrt(), 2.0 * PI * u.y);
        let d = Vec3::new(r * phi.cos(), (1.0 - u.x).sqrt(), r * phi.sin());
        cosine_values.push(f64::from(luminance(map.radiance(d)) * PI));
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let variance = |v: &[f64]| {
        let m = mean(v);
        v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64
    };
    let (by_map, by_cosine) = (mean(&map_values), mean(&cosine_values));
    let (var_map, var_cosine) = (variance(&map_values), variance(&cosine_values));
    println!("variance of one sample: environment {var_map:.4}, cosine {var_cosine:.4}");
    assert!(var_map < 0.05 * var_cosine, "{var_map} vs {var_cosine}");
    let (error_map, error_cosine) = ((by_map - exact).abs(), (by_cosine - exact).abs());
    println!("irradiance: quadrature {exact:.4}, environment {by_map:.4}, cosine {by_cosine:.4}");
    assert!(
        error_map < 0.01 * exact,
        "environment sampling off by {error_map}"
    );
    // The cosine's few samples that find the sun make its estimate noisy: within 4 standard
    // errors of the quadrature.
    let standard_error = (var_cosine / f64::from(count)).sqrt();
    assert!(
        error_cosine < 4.0 * standard_error,
        "cosine sampling off by {error_cosine}, standard error {standard_error}"
    );
}

#[test]
fn hdr_and_exr_files_load_to_the_same_texels() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (w, h) = (8u32, 4u32);
    let texels: Vec<[f32; 3]> = (0..w * h)
        .map(|i| [i as f32 * 0.5, 1.0, 0.25 * (i % 3) as f32])
        .collect();
    let image =
        image::Rgb32FImage::from_raw(w, h, texels.iter().flatten().copied().collect()).unwrap();
    let exr = dir.path().join("sky.exr");
    let hdr = dir.path().join("sky.hdr");
    image::DynamicImage::ImageRgb32F(image.clone())
        .save(&exr)
        .expect("exr");
    image::DynamicImage::ImageRgb32F(image)
        .save(&hdr)
        .expect("hdr");
    let (from_exr, mended) = EnvironmentMap::load(&exr).expect("exr loads");
    assert_eq!(mended, Mended::default());
    let (from_hdr, _) = EnvironmentMap::load(&hdr).expect("hdr loads");
    assert_eq!((from_exr.width, from_exr.height), (w, h));
    for (i, (a, b)) in from_exr.texels.iter().zip(&from_hdr.texels).enumerate() {
        assert_eq!(*a, Vec3::from(texels[i]), "exr texel {i}");
        // RGBE keeps 8 bits of mantissa under a shared exponent.
        assert!(
            (*a - *b).abs().max_element() <= a.max_element() / 128.0 + 1e-6,
            "{a} {b}"
        );
    }
    let bad = dir.path().join("sky.png");
    let message = EnvironmentMap::load(&bad).unwrap_err().to_string();
    assert!(message.contains("use .hdr or .exr"), "{message}");
    let missing = EnvironmentMap::load(&dir.path().join("none.hdr")).unwrap_err();
    assert!(missing.to_string().starts_with("environment "), "{missing}");
}

#[test]
fn the_studio_lights_where_it_says_and_samples_them() {
    let map = studio::studio(256);
    assert_eq!((map.width, map.height), (256, 128));
    let key = map.radiance(studio::direction(-45.0, 35.0));
    assert_eq!(
        key,
        Vec3::new(30.0, 27.0, 24.0),
        "the key light, front left"
    );
    let floor = map.radiance(studio::direction(0.0, -60.0));
    assert!(floor.max_element() < 0.1, "the floor: {floor}");
    // Samples land on the lights (panels and lamps are > 1; the room is < 0.2) in the share of
    // the power they hold: luminance times sin(theta), summed over texels.
    let (mut lights, mut all) = (0.0f64, 0.0f64);
    for (i, t) in map.texels.iter().enumerate() {
        let row = i as u32 / map.width;
        let power = f64::from(luminance(*t) * ((row as f32 + 0.5) / 128.0 * PI).sin());
        all += power;
        if luminance(*t) > 1.0 {
            lights += power;
        }
    }
    let sampler = EnvironmentSampler::new(&map).expect("the studio emits");
    let on_lights = (0..4000)
        .filter(|&i| luminance(sampler.sample(&map, r2(i)).expect("a sample").radiance) > 1.0)
        .count() as f64
        / 4000.0;
    println!(
        "share of samples on lights {on_lights:.4}, of power {:.4}",
        lights / all
    );
    assert!(
        lights / all > 0.8,
        "the lights hold {:.3} of the power",
        lights / all
    );
    assert!(
        (on_lights - lights / all).abs() < 0.01,
        "{on_lights} vs {}",
        lights / all
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("studio.hdr");
    studio::write_environment(&map, &path).expect("written");
    let (back, _) = EnvironmentMap::load(&path).expect("read back");
    assert_eq!(
        back.radiance(studio::direction(-45.0, 35.0)),
        Vec3::new(30.0, 27.0, 24.0)
    );
}
