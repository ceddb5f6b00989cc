//! The built-in default scene and the generators: invariants, winding, framing.

use glam::Vec3;
use lensray_core::scene::builtin::{
    default_scene, default_sphere_centers, DEFAULT_EYE, DEFAULT_SUBJECT,
};
use lensray_core::scene::generate::{cornell_box, cuboid, dense, uv_sphere};
use lensray_core::scene::{Material, Scene};
use lensray_core::settings::{ProjectionKind, Shading};

use crate::all_generated;

/// Checks the invariants and that every triangle winds counter-clockwise around its normals.
fn check_scene(name: &str, scene: &Scene) {
    assert_eq!(scene.validate(), Ok(()), "{name}");
    for mesh in &scene.meshes {
        assert!(
            !mesh.triangles.is_empty(),
            "{name}/{}: empty mesh",
            mesh.name
        );
        assert_eq!(
            mesh.normals.len(),
            mesh.positions.len(),
            "{name}/{}",
            mesh.name
        );
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            let geometric = (b - a).cross(c - a);
            assert!(
                geometric.length() > 0.0,
                "{name}/{}: triangle {t} is degenerate",
                mesh.name
            );
            for &i in tri {
                let n = mesh.normals[i as usize];
                assert!(
                    (n.length() - 1.0).abs() < 1e-5,
                    "{name}/{}: normal {n}",
                    mesh.name
                );
                assert!(
                    geometric.dot(n) > 0.0,
                    "{name}/{}: triangle {t} {tri:?} winds against its normal {n}",
                    mesh.name
                );
            }
        }
    }
}

#[test]
fn built_in_default_scene() {
    let d = default_scene();
    check_scene("default", &d.scene);
    let n = d.scene.triangle_count();
    assert!((2_000..=10_000).contains(&n), "{n} triangles");
    assert_eq!(d.source, "built-in default");
    let c = &d.settings.camera;
    assert_eq!(c.projection, Some(ProjectionKind::Perspective));
    assert!(c.aperture_radius.unwrap() > 0.0);
    let eye = c.eye.unwrap();
    let target = c.target.unwrap();
    let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
    assert_eq!(v(eye), DEFAULT_EYE);
    let forward = (v(target) - v(eye)).normalize();
    let depth = |p: Vec3| (p - DEFAULT_EYE).dot(forward);
    let focus = c.focus_distance.unwrap() as f32;
    assert!(
        (focus - depth(DEFAULT_SUBJECT)).abs() < 1e-3,
        "focus {focus}"
    );
    // Spheres well in front of and well behind the focal plane, all inside near..far.
    let depths: Vec<f32> = default_sphere_centers().iter().map(|&p| depth(p)).collect();
    assert!(depths.iter().any(|&z| z < 0.5 * focus), "{depths:?}");
    assert!(depths.iter().any(|&z| z > 1.4 * focus), "{depths:?}");
    let bounds = d.scene.bounds().unwrap();
    for corner in bounds.corners() {
        let z = depth(corner) as f64;
        assert!(z < c.far.unwrap(), "corner at depth {z} beyond far");
    }
    assert!(c.near.unwrap() < depths[0] as f64 - 0.5);
    // Distinct colours.
    let mut colours: Vec<[u32; 3]> = d
        .scene
        .materials
        .iter()
        .map(|m| m.diffuse.to_array().map(f32::to_bits))
        .collect();
    colours.sort();
    colours.dedup();
    assert_eq!(colours.len(), d.scene.materials.len());
    let s = &d.settings;
    assert_eq!((s.image.width, s.image.height), (Some(640), Some(480)));
    assert_eq!(s.render.shading, Some(Shading::Lit));
    assert!(s.light.0[0].position.is_some() && s.light.0[0].intensity.is_some());
    assert!(s.render.background.is_some());
}

#[test]
fn generators() {
    for (name, d) in all_generated() {
        check_scene(name, &d.scene);
        let c = &d.settings.camera;
        assert!(c.aperture_radius.unwrap() > 0.0, "{name}");
        let bounds = d.scene.bounds().unwrap();
        assert!(bounds.diagonal().length() > 1.0, "{name}");
    }

    let cornell = cornell_box();
    let wall_colour = |wall: &str| {
        let mesh = cornell
            .scene
            .meshes
            .iter()
            .find(|m| m.name == wall)
            .unwrap();
        cornell.scene.materials[mesh.material_ids[0] as usize].diffuse
    };
    let (left, right, back) = (
        wall_colour("left_wall"),
        wall_colour("right_wall"),
        wall_colour("back_wall"),
    );
    assert!(left.x > 2.0 * left.y, "left wall should be red: {left}");
    assert!(
        right.y > 2.0 * right.x,
        "right wall should be green: {right}"
    );
    assert!(
        back.x == back.y && back.y == back.z,
        "back wall should be white: {back}"
    );
    assert!(
        cornell
            .scene
            .materials
            .iter()
            .any(|m| m.emission.max_element() > 0.0),
        "no emissive material"
    );
    // The ceiling patch lights the room as an emitter: no point light doubles it.
    assert!(
        cornell.settings.light.0.is_empty(),
        "the Cornell box has a point light besides its emissive patch"
    );

    for min in [0, 5_000, 30_000, 123_457] {
        let n = dense(min).scene.triangle_count();
        assert!(n >= min, "dense({min}) has {n} triangles");
        assert!(
            n <= min.max(10_000) * 13 / 10,
            "dense({min}) has {n} triangles: too many"
        );
    }
}

#[test]
fn dense_reaches_a_million_triangles() {
    let d = dense(1_000_000);
    let n = d.scene.triangle_count();
    assert!((1_000_000..1_100_000).contains(&n), "{n} triangles");
}

#[test]
fn primitives_wind_outwards() {
    let mut scene = Scene::default();
    scene.materials.push(Material::default());
    for (i, yaw) in [0.0f32, 0.3, -2.0].into_iter().enumerate() {
        scene.meshes.push(cuboid(
            &format!("box{i}"),
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.5, 1.0, 2.0),
            yaw,
            0,
        ));
    }
    scene
        .meshes
        .push(uv_sphere("coarse", Vec3::ONE, 2.0, 3, 2, 0));
    scene
        .meshes
        .push(uv_sphere("fine", Vec3::ONE, 0.01, 64, 33, 0));
    check_scene("primitives", &scene);
    // Normals point away from the centre.
    for mesh in &scene.meshes {
        let center = if mesh.name.starts_with("box") {
            Vec3::new(1.0, 2.0, 3.0)
        } else {
            Vec3::ONE
        };
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!(
                (*p - center).dot(*n) > 0.0,
                "{}: normal {n} at {p}",
                mesh.name
            );
        }
    }
}
