//! The automatic framing of a scene without a camera: a three-quarter view from above the
//! front (glTF's +Z), at the distance where the scene's bounding sphere fills the lens's field
//! of view, focused at the sphere's centre.

use glam::Vec3;
use lensray_core::camera::{Camera, Lens};
use lensray_core::scene::{load_obj, Scene};
use lensray_core::settings::{
    shot, Settings, BOARD_ELEVATION_DEGREES, FRAMING_AZIMUTH_DEGREES, FRAMING_ELEVATION_DEGREES,
};

/// A box 4 m long (x), 1.5 m high and 2 m deep away from the origin, as OBJ: a milk truck's
/// proportions.
const TRUCK_OBJ: &str = "v 1 0 -3\nv 5 0 -3\nv 5 1.5 -3\nv 1 1.5 -3\nv 1 0 -1\nv 5 0 -1\nv 5 1.5 -1\nv 1 1.5 -1\n\
f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\nf 1 5 8\nf 1 8 4\nf 2 6 7\nf 2 7 3\nf 4 3 7\nf 4 7 8\nf 1 2 6\nf 1 6 5\n";

/// What a case changes in the default settings.
type Setup = fn(&mut Settings);

/// A real lens of assets/lenses: a 22 mm wide angle.
const WIDE_22: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../assets/lenses/wide-22.dat"
);

fn truck() -> Scene {
    obj_scene(TRUCK_OBJ)
}

fn obj_scene(obj: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.obj");
    std::fs::write(&path, obj).unwrap();
    load_obj(&path).unwrap().scene
}

/// A closed box from `min` to `max` as OBJ, every face wound counter-clockwise seen from
/// outside (so its faces' normals sum to zero: it faces no side more than another).
fn box_obj(min: Vec3, max: Vec3) -> String {
    let faces = "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 5 8\nf 1 8 4\n\
                 f 2 3 7\nf 2 7 6\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\n";
    let mut obj = String::new();
    for z in [min.z, max.z] {
        for (x, y) in [
            (min.x, min.y),
            (max.x, min.y),
            (max.x, max.y),
            (min.x, max.y),
        ] {
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    obj + faces
}

/// The outline of the sphere (`centre`, `radius`) as `camera` sees it: its largest distance
/// from the image's centre, and whether all of it lies inside the image (in pixels).
fn outline(camera: &Camera, centre: Vec3, radius: f32) -> (f32, bool) {
    let frame = &camera.frame;
    let to_centre = centre - frame.eye;
    let distance = to_centre.length();
    let axis = to_centre / distance;
    let side = axis.cross(frame.true_up).normalize();
    let up = side.cross(axis);
    let sin = radius / distance;
    let cos = (1.0 - sin * sin).sqrt();
    let reach = (distance * distance - radius * radius).sqrt();
    let (w, h) = (camera.width as f32, camera.height as f32);
    let mut largest = 0.0f32;
    let mut inside = true;
    for k in 0..72 {
        let phi = (k as f32 * 5.0).to_radians();
        let direction = axis * cos + (side * phi.cos() + up * phi.sin()) * sin;
        let p = camera.project(frame.eye + direction * reach);
        largest = largest.max((p.x - 0.5 * w).hypot(p.y - 0.5 * h));
        inside &= (0.0..=w).contains(&p.x) && (0.0..=h).contains(&p.y);
    }
    (largest, inside)
}

#[test]
fn a_scene_without_a_camera_is_framed_from_above_the_front_by_the_lens() {
    let scene = truck();
    let (centre, radius) = scene.bounding_sphere().unwrap();
    // The box's farthest corners are its own: the sphere is half its diagonal.
    assert!((centre - Vec3::new(3.0, 0.75, -2.0)).length() < 1e-6);
    assert!((radius - 0.5 * Vec3::new(4.0, 1.5, 2.0).length()).abs() < 1e-5);
    let lenses: [(&str, Setup); 4] = [
        ("the default 40 degrees", |_| {}),
        ("35 mm", |s| s.camera.focal_length_mm = Some(35.0)),
        ("50 mm, portrait", |s| {
            s.camera.focal_length_mm = Some(50.0);
            (s.image.width, s.image.height) = (Some(48), Some(64));
        }),
        ("wide-22.dat", |s| {
            s.camera.lens.prescription = Some(WIDE_22.to_string())
        }),
    ];
    for (name, setup) in lenses {
        let mut settings = Settings::default();
        setup(&mut settings);
        let camera = shot(&settings, &scene)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .camera;
        let eye = camera.frame.eye;
        // Looking at the centre, from 35 degrees around toward +x and 25 degrees up.
        let from_centre = eye - centre;
        let distance = from_centre.length();
        let azimuth = from_centre.x.atan2(from_centre.z).to_degrees();
        let elevation = (from_centre.y / distance).asin().to_degrees();
        assert!(
            (camera.frame.forward + from_centre / distance).length() < 1e-5,
            "{name}: the camera looks at the sphere's centre"
        );
        assert!(
            (f64::from(azimuth) - FRAMING_AZIMUTH_DEGREES).abs() < 1e-3
                && (f64::from(elevation) - FRAMING_ELEVATION_DEGREES).abs() < 1e-3,
            "{name}: seen from {azimuth} degrees around and {elevation} up"
        );
        let focus = match &camera.lens {
            Lens::Thin(thin) => thin.focus_distance,
            Lens::Real { first_order, .. } => first_order.focus_distance,
        };
        let (reach, inside) = outline(&camera, centre, radius);
        let half = 0.5 * camera.width.min(camera.height) as f32;
        println!(
            "{name}: {distance:.3} m away, focused at {focus:.3} m, the sphere's outline reaches {:.1} % of the narrower half side",
            100.0 * reach / half
        );
        // A pinhole has no focus; the thin lens focuses where it was put.
        if settings.camera.focal_length_mm.is_some() {
            assert!(
                ((focus - distance) / distance).abs() < 1e-4,
                "{name}: focused at {focus}, the centre is {distance} away"
            );
        }
        assert!(inside, "{name}: the sphere's outline leaves the frame");
        assert!(
            (0.8..=1.0).contains(&(reach / half)),
            "{name}: the sphere's outline reaches {reach} px of the narrower half side's {half}"
        );
    }
}

#[test]
fn a_board_is_framed_face_on_from_a_little_above_filling_the_frame() {
    // A row of samples 8.6 m wide, 2.4 m high and 1.3 m deep (AlphaBlendModeTest's bounds),
    // facing +Z, and a chart 2 m square and 5 cm thick facing +X.
    let boards = [
        (
            "a row facing +Z",
            Vec3::new(-4.3, 0.0, -0.7),
            Vec3::new(4.3, 2.4, 0.6),
            0.0,
        ),
        (
            "a chart facing +X",
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(1.05, 1.0, 1.0),
            90.0f32,
        ),
    ];
    for (name, min, max, facing) in boards {
        let scene = obj_scene(&box_obj(min, max));
        for (lens, setup) in [("40 degrees", None), ("50 mm", Some(50.0))] {
            let mut settings = Settings::default();
            settings.camera.focal_length_mm = setup;
            let camera = shot(&settings, &scene).unwrap().camera;
            let centre = 0.5 * (min + max);
            let from_centre = camera.frame.eye - centre;
            let azimuth = from_centre.x.atan2(from_centre.z).to_degrees();
            let elevation = (from_centre.y / from_centre.length()).asin().to_degrees();
            assert!(
                (azimuth - facing).abs() < 1e-3
                    && (f64::from(elevation) - BOARD_ELEVATION_DEGREES).abs() < 1e-3,
                "{name}, {lens}: seen from {azimuth} degrees around and {elevation} up"
            );
            // Every corner inside the frame, the farthest at the margin's 1 / 1.05.
            let (w, h) = (camera.width as f32, camera.height as f32);
            let reach = scene
                .bounds()
                .unwrap()
                .corners()
                .map(|c| camera.project(c))
                .iter()
                .map(|p| ((p.x / w - 0.5).abs() * 2.0).max((p.y / h - 0.5).abs() * 2.0))
                .fold(0.0f32, f32::max);
            println!(
                "{name}, {lens}: the farthest corner reaches {:.1} % of the half frame",
                100.0 * reach
            );
            assert!(
                (reach - 1.0 / 1.05).abs() < 1e-3,
                "{name}, {lens}: the farthest corner reaches {reach} of the half frame, not 1 / 1.05"
            );
        }
    }
}

/// A board whose triangles face -Z (a one-sided chart made to be seen from behind glTF's
/// front) is framed from -Z: from where its face shows.
#[test]
fn a_board_is_framed_from_the_side_its_face_shows() {
    // Counter-clockwise seen from -Z: its normal is -Z.
    let chart = "v -1 -1 0\nv -1 1 0\nv 1 1 0\nv 1 -1 0\nf 1 2 3\nf 1 3 4\n";
    let scene = obj_scene(chart);
    let camera = shot(&Settings::default(), &scene).unwrap().camera;
    let from_centre = camera.frame.eye;
    let azimuth = from_centre.x.atan2(from_centre.z).to_degrees();
    assert!(
        (azimuth.abs() - 180.0).abs() < 1e-3,
        "seen from {azimuth} degrees around, not from -Z"
    );
}
