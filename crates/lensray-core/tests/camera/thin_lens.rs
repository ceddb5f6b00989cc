//! Items 5 and 6: the lens rays of a film point converge on the focal plane, and their spread
//! is the circle of confusion.

use glam::{DMat3, DVec3, Vec2};
use lensray_core::camera::{Camera, Ray};

use crate::common::*;
use lensray_core::sampler::CameraSample;

/// Film points: centre, the four image corners, points just inside edges, random ones.
fn film_points(r: &RefCam, rng: &mut Rng) -> Vec<Vec2> {
    let (w, h) = (r.width as f32, r.height as f32);
    let mut points = vec![
        Vec2::new(w / 2.0, h / 2.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(w, 0.0),
        Vec2::new(0.0, h),
        Vec2::new(w, h),
        Vec2::new(0.3, h - 0.2),
        Vec2::new(w - 0.5, 0.5),
    ];
    for _ in 0..5 {
        points.push(Vec2::new(rng.f32() * w, rng.f32() * h));
    }
    points
}

/// Lens samples: random ones, the centre, and the whole boundary of the unit square (which the
/// concentric map sends to the rim of the aperture disk; u = 1 is outside [0, 1) but the map is
/// defined there and it completes the rim).
fn lens_samples(rng: &mut Rng) -> Vec<Vec2> {
    let mut samples: Vec<Vec2> = (0..256).map(|_| rng.vec2()).collect();
    samples.push(Vec2::splat(0.5));
    for k in 0..=32 {
        let t = k as f32 / 32.0;
        samples.extend([
            Vec2::new(0.0, t),
            Vec2::new(1.0, t),
            Vec2::new(t, 0.0),
            Vec2::new(t, 1.0),
        ]);
    }
    samples
}

/// The point nearest (least squares) to all the rays' lines, in f64.
fn convergence_point(rays: &[Ray]) -> DVec3 {
    let mut a = DMat3::ZERO;
    let mut b = DVec3::ZERO;
    for ray in rays {
        let d = ray.direction.as_dvec3().normalize();
        let proj = DMat3::IDENTITY - DMat3::from_cols(d * d.x, d * d.y, d * d.z);
        a += proj;
        b += proj * ray.origin.as_dvec3();
    }
    a.inverse() * b
}

fn thin_lens_cameras() -> Vec<(Setup, Camera, RefCam)> {
    setups()
        .into_iter()
        .map(|s| {
            let cam = s.camera();
            let r = s.reference();
            assert!(r.aperture > 0.0, "{}: sample camera needs a lens", s.name);
            (s, cam, r)
        })
        .collect()
}

#[test]
fn lens_rays_of_a_film_point_meet_on_the_focal_plane() {
    let mut rng = Rng::new(30);
    for (setup, cam, r) in thin_lens_cameras() {
        let name = setup.name;
        let samples = lens_samples(&mut rng);
        let lens_z = if setup.is_orthographic() { r.near } else { 0.0 };
        assert_eq!(
            cam.lens_plane_z() as f64,
            lens_z as f32 as f64,
            "{name}: lens plane"
        );
        for film in film_points(&r, &mut rng) {
            let (col, row) = (film.x as f64, film.y as f64);
            // Reference: where the pinhole ray of this film point crosses z_camera = F.
            let expected = r.world_from_camera_coords(r.pinhole_point_camera(col, row, r.focus));
            let scale = (expected - r.eye).length();
            let pinhole_camera = cam.pinhole_ray(film);

            let rays: Vec<Ray> = samples
                .iter()
                .map(|&u| cam.first_order_ray(CameraSample::new(film, u)))
                .collect();
            let meet = convergence_point(&rays);
            assert_close(
                &format!("{name}: film {film:?}: camera depth of the rays' meeting point {meet:?}"),
                r.camera_coords(meet).z,
                r.focus,
                1e-5 * scale,
            );
            let miss = (meet - expected).length();
            assert!(
                miss <= 1e-5 * scale,
                "{name}: film {film:?}: lens rays meet at {meet:?}, the pinhole ray crosses the \
                 focal plane at {expected:?}: {miss:.3e} apart = {:.3e} relative (tol 1e-5)",
                miss / scale
            );
            for (ray, u) in rays.iter().zip(&samples) {
                let (dist, t) = ray_distance(ray, expected);
                assert!(
                    dist <= 1e-5 * scale && t > 0.0,
                    "{name}: film {film:?}, lens sample {u:?}: ray {ray:?} passes {dist:.3e} \
                     ({:.3e} relative, tol 1e-5) from the focal point {expected:?} (t = {t})",
                    dist / scale
                );
                // The ray starts on the lens: the lens plane, within the aperture of the
                // pinhole ray's origin (the lens centre for this film point).
                let o = r.camera_coords(ray.origin.as_dvec3());
                assert_close(
                    &format!("{name}: film {film:?}, lens sample {u:?}: origin's depth"),
                    o.z,
                    lens_z,
                    2e-6 * scale,
                );
                let centre = pinhole_camera.origin.as_dvec3();
                let offset = (o.truncate() - centre.truncate()).length();
                assert!(
                    offset <= r.aperture * (1.0 + 1e-5) + 1e-6 * scale,
                    "{name}: film {film:?}, lens sample {u:?}: origin {o:?} is {offset} from \
                     the lens centre {centre:?}, outside the aperture radius {}",
                    r.aperture
                );
                assert_close(
                    &format!("{name}: |direction| for lens sample {u:?}"),
                    ray.direction.length() as f64,
                    1.0,
                    1e-6,
                );
            }
            // The camera-space focal point too.
            let f = cam
                .lens
                .first_order()
                .focal_point(&pinhole_camera)
                .expect("the facing plane is met in front of the lens")
                .as_dvec3();
            let f_expected = r.pinhole_point_camera(col, row, r.focus);
            assert_vec_close(
                &format!("{name}: ThinLens::focal_point of the pinhole ray through {film:?}"),
                f,
                f_expected,
                2e-6 * scale,
            );
        }
    }
}

/// The measured spread of one film point's lens rays at camera depth z is the thin-lens circle
/// of confusion: A |z - F| / (F - lens_z), and in pixels what `coc_radius_pixels` says.
#[test]
fn lens_ray_spread_matches_circle_of_confusion() {
    let mut rng = Rng::new(31);
    for (setup, cam, r) in thin_lens_cameras() {
        let name = setup.name;
        let samples = lens_samples(&mut rng);
        let lens_z = cam.lens_plane_z() as f64;
        // Pixels per screen unit, then per world unit at depth z.
        let pixels_per_screen_unit = r.height / (2.0 * r.s);
        for film in film_points(&r, &mut rng) {
            let (col, row) = (film.x as f64, film.y as f64);
            let rays: Vec<Ray> = samples
                .iter()
                .map(|&u| cam.first_order_ray(CameraSample::new(film, u)))
                .collect();
            for k in [0.2, 0.5, 0.8, 1.25, 2.0, 5.0] {
                // Depths in front of and behind focus, all in front of the lens plane.
                let z = lens_z + k * (r.focus - lens_z);
                let centre = r.world_from_camera_coords(r.pinhole_point_camera(col, row, z));
                let centre_px = r.raster(centre);
                let (mut spread, mut spread_px) = (0.0f64, 0.0f64);
                for ray in &rays {
                    let c = cross_depth(&r, ray, z);
                    spread = spread.max((c - centre).length());
                    let px = r.raster(c);
                    spread_px = spread_px.max((px - centre_px).truncate().length());
                }
                let label = format!("{name}: film {film:?}, depth {z} (focus {})", r.focus);
                let formula =
                    cam.lens
                        .first_order()
                        .ray_spread_radius(z as f32, lens_z as f32) as f64;
                assert_rel(
                    &format!("{label}: measured spread vs ThinLens::ray_spread_radius"),
                    spread,
                    formula,
                    1e-3,
                );
                let hand = r.aperture * (z - r.focus).abs() / (r.focus - lens_z);
                assert_rel(
                    &format!("{label}: measured spread vs A |z - F| / (F - lens_z)"),
                    spread,
                    hand,
                    1e-3,
                );
                if !setup.is_orthographic() {
                    let hand = r.aperture * (z - r.focus).abs() / r.focus;
                    assert_rel(
                        &format!("{label}: measured spread vs A |z - F| / F"),
                        spread,
                        hand,
                        1e-3,
                    );
                }
                let coc = cam.coc_radius_pixels(glam::Vec2::ZERO, z as f32) as f64;
                assert_rel(
                    &format!("{label}: measured spread in pixels vs coc_radius_pixels"),
                    spread_px,
                    coc,
                    1e-3,
                );
                let converted = formula / r.divisor(z) * pixels_per_screen_unit;
                assert_rel(
                    &format!("{label}: coc_radius_pixels vs ray_spread_radius converted"),
                    coc,
                    converted,
                    1e-4,
                );
            }
        }
    }
}

/// With aperture 0 the thin lens is the pinhole, for every lens sample.
#[test]
fn zero_aperture_lens_is_the_pinhole() {
    let mut rng = Rng::new(32);
    for setup in setups() {
        let cam = setup
            .clone()
            .with_lens(lensray_core::camera::LensParams::ThinLens {
                aperture_radius: 0.0,
                focus_distance: 1e3,
            })
            .camera();
        for _ in 0..64 {
            let film = Vec2::new(rng.f32() * cam.width as f32, rng.f32() * cam.height as f32);
            let pinhole = cam.pinhole_ray(film);
            let u = rng.vec2();
            assert_eq!(
                cam.lens.first_order().generate_ray(&pinhole, u),
                pinhole,
                "{}: aperture 0, lens sample {u:?}",
                setup.name
            );
            assert_eq!(
                cam.coc_radius_pixels(glam::Vec2::ZERO, 3.7),
                0.0,
                "{}: CoC of a pinhole",
                setup.name
            );
        }
    }
}

/// The raster path's sheared projection (`Camera::clip_from_world_through_lens`): a point on
/// the lens ray of film point p and lens sample u lands, rasterized with the matrix of film
/// offset fract(p) and lens sample u, exactly on the centre of p's pixel, for perspective and
/// orthographic cameras; and its depth is reversed (1 at the near plane, 0 at the far one).
#[test]
fn sheared_projection_sends_lens_rays_to_their_pixel_centre() {
    let mut rng = Rng::new(0x5eed_1e25);
    let mut worst = 0.0f64;
    for (setup, cam, r) in thin_lens_cameras() {
        for p in film_points(&r, &mut rng) {
            // Film points strictly inside the image (a pixel to land in).
            let p = p.clamp(
                Vec2::splat(0.25),
                Vec2::new(r.width as f32, r.height as f32) - 0.25,
            );
            let film_u = p - p.floor();
            for lens_u in lens_samples(&mut rng).into_iter().take(40) {
                let ray = cam.first_order_ray(CameraSample::new(p, lens_u));
                let clip_from_world = cam.clip_from_world_through_lens(film_u, lens_u);
                for t in [0.3f32, 1.0, 3.0, 7.0] {
                    let point = ray.at(t * cam.lens.first_order().focus_distance);
                    let z = cam.view_depth(point);
                    if z <= cam.near || z >= cam.far {
                        continue;
                    }
                    let clip = clip_from_world * point.extend(1.0);
                    let ndc = clip.truncate() / clip.w;
                    // Vulkan clip space -> raster: x, y from [-1, 1] to [0, size].
                    let raster = Vec2::new(
                        (ndc.x + 1.0) * 0.5 * r.width as f32,
                        (ndc.y + 1.0) * 0.5 * r.height as f32,
                    );
                    let centre = p.floor() + 0.5;
                    let error = f64::from((raster - centre).abs().max_element());
                    worst = worst.max(error);
                    assert!(
                        error < 2e-3,
                        "{}: film {p}, lens {lens_u}, t {t}: rasterized at {raster}, pixel \
                         centre {centre} (off by {error:.2e} px)",
                        setup.name
                    );
                    let pinhole_depth = cam.project(point).z;
                    assert!(
                        (ndc.z - (1.0 - pinhole_depth)).abs() < 1e-4,
                        "{}: reversed depth {} vs 1 - {pinhole_depth}",
                        setup.name,
                        ndc.z
                    );
                }
            }
        }
    }
    println!("worst distance from the pixel centre: {worst:.2e} px");
}
