//! The packet trace against the one-by-one trace.

use super::*;

/// The packet trace gives `generate_ray`'s rays and weights bit for bit, full packets and a
/// part-filled one, square to the film and tilted and shifted (the CPU renders with it; the
/// GPU mirror is checked against `generate_ray`). Also reports both speeds.
#[test]
fn packets_trace_the_same_rays() {
    let six_blades = Aperture::new(crate::camera::ApertureShape {
        blades: Some(6),
        rotation_degrees: 10.0,
        ..Default::default()
    });
    let moved = Movements {
        shift: [2.0, -1.0],
        tilt_degrees: 6.0,
        tilt_direction_degrees: 120.0,
    };
    // Wide open and round; stopped down behind six blades.
    for (name, f_number, aperture, movements) in [
        ("double-gauss-50", None, Aperture::ROUND, Movements::NONE),
        ("wide-22", Some(4.0), six_blades, Movements::NONE),
        (
            "cooke-triplet-50",
            Some(8.0),
            Aperture::ROUND,
            Movements::NONE,
        ),
        ("aspheric-31", Some(2.8), Aperture::ROUND, Movements::NONE),
        ("double-gauss-50", Some(2.8), Aperture::ROUND, moved),
    ] {
        let lens = crate::optics::builtin::lens(name).expect("built in");
        let params = RealLensParams {
            prescription: Arc::new(lens),
            f_number,
            focus_distance: 3.0,
            sensor_height_mm: 24.0,
            dispersion: true,
            movements,
        };
        let real = RealLens::new(params, 1.5, aperture).expect("a lens");
        packets_match_one_by_one(&real);
    }
}

fn packets_match_one_by_one(real: &RealLens) {
    let samples: Vec<(Vec3, Vec2, f32)> = (0..4100u32)
        .map(|i| {
            let raster = Vec2::new((i * 37 % 300) as f32 + 0.3, (i * 11 % 200) as f32 + 0.7);
            let u = Vec2::new(
                (i.wrapping_mul(2654435761) % 1000) as f32 / 1000.0,
                (i.wrapping_mul(40503) % 997) as f32 / 997.0,
            );
            // Wavelengths across 380-780 nm; every third at the d line.
            let lambda = 380.0 + (i.wrapping_mul(7919) % 401) as f32;
            let k = if i % 3 == 0 {
                0.0
            } else {
                crate::optics::glass::dispersion_offset_f32(lambda)
            };
            (real.film_point(raster, 300, 200), u, k)
        })
        .collect();
    let (mut scalar, mut packets) = (std::time::Duration::MAX, std::time::Duration::MAX);
    let (mut one_by_one, mut packed) = (Vec::new(), Vec::new());
    for _ in 0..5 {
        let start = std::time::Instant::now();
        one_by_one = samples
            .iter()
            .map(|&(f, u, k)| real.generate_ray(f, u, k))
            .collect();
        scalar = scalar.min(start.elapsed());
        let start = std::time::Instant::now();
        packed.clear();
        for chunk in samples.chunks(crate::reference::PACKET_SIZE) {
            let mut out = [None; crate::reference::PACKET_SIZE];
            real.generate_rays(chunk, &mut out);
            packed.extend_from_slice(&out[..chunk.len()]);
        }
        packets = packets.min(start.elapsed());
    }
    println!(
        "{}: one by one {scalar:?}, in packets {packets:?}",
        real.name()
    );
    let bits = |r: &Option<(Ray, f32)>| {
        r.map(|(ray, w)| {
            (
                ray.origin.to_array().map(f32::to_bits),
                ray.direction.to_array().map(f32::to_bits),
                w.to_bits(),
            )
        })
    };
    let passed = one_by_one.iter().filter(|r| r.is_some()).count();
    assert!(passed > 2000, "{}: {passed} of 4100 pass", real.name());
    for (k, (a, b)) in one_by_one.iter().zip(&packed).enumerate() {
        assert_eq!(bits(a), bits(b), "sample {k}: {a:?} vs {b:?}");
    }
}
