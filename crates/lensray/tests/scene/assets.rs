//! The bundled real models: Khronos's AlphaBlendModeTest (every alpha mode, in a GLB with its
//! textures inside) and Poly Haven's scanned apple (a 4096 x 4096 base colour texture, normal
//! and roughness maps lensray does not draw). Each loads as its file says and renders on the CPU.

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::Vec3;
use lensray_core::film::Image;
use lensray_core::reference::Renderer;
use lensray_core::scene::{load, AlphaMode, SceneDescription};
use lensray_core::settings::{shot, Shading, Shot};

fn asset(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(path)
}

/// `description`'s shot and its render, unlit on the CPU at `width` x `height`, 4 samples a
/// pixel, from its automatic framing (neither file has a camera: AlphaBlendModeTest is a board
/// seen face-on, the apple a model seen three-quarter from above the front), on a black
/// background.
fn render_small(description: &SceneDescription, width: u32, height: u32) -> (Shot, Image) {
    let mut settings = description.settings.clone();
    settings.image.width = Some(width);
    settings.image.height = Some(height);
    settings.image.spp = Some(4);
    settings.render.shading = Some(Shading::Unlit);
    settings.render.background = Some([0.0; 3]);
    let shot = shot(&settings, &description.scene).unwrap_or_else(|e| panic!("{e}"));
    let (image, _) = Renderer::new(&description.scene).render(&shot, &mut |_, _| {});
    assert!(image.pixels.iter().all(|p| p.is_finite()), "finite pixels");
    (shot, image)
}

#[test]
fn alpha_blend_mode_test_loads_its_alpha_modes_and_renders() {
    let path = asset("AlphaBlendModeTest/AlphaBlendModeTest.glb");
    let description = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &description.scene;
    assert_eq!(scene.triangle_count(), 61);
    let mode = |name: &str| {
        let m = scene.materials.iter().find(|m| m.name == name);
        m.unwrap_or_else(|| panic!("material {name}")).alpha_mode
    };
    assert_eq!(mode("MatBed"), AlphaMode::Opaque);
    assert_eq!(mode("MatOpaque"), AlphaMode::Opaque);
    assert_eq!(mode("MatBlend"), AlphaMode::Blend);
    assert_eq!(mode("MatCutoff25"), AlphaMode::Mask { cutoff: 0.25 });
    assert_eq!(mode("MatCutoff75"), AlphaMode::Mask { cutoff: 0.75 });
    // No alphaCutoff: glTF's default.
    assert_eq!(mode("MatCutoffDefault"), AlphaMode::Mask { cutoff: 0.5 });
    // MatBed is single-sided (glTF's default), the panels double-sided.
    let sides = |name: &str| {
        scene
            .materials
            .iter()
            .find(|m| m.name == name)
            .map(|m| m.double_sided)
    };
    assert_eq!(
        (sides("MatBed"), sides("MatBlend")),
        (Some(false), Some(true))
    );
    // Its normal maps and single-sided bed are drawn: nothing is left to name.
    assert!(description.notices.is_empty(), "{:?}", description.notices);

    // Each test panel shows its green texture where its alpha passes: the lower the cutoff,
    // the more of it (measured: opaque 289 pixels, cutoff 0.25 183, 0.5 133, 0.75 79).
    let (shot, image) = render_small(&description, 128, 96);
    let green = |name: &str| green_pixels(&description, &shot, &image, name);
    let counts = [
        "TestOpaque",
        "TestCutoff25",
        "TestCutoffDefault",
        "TestCutoff75",
    ]
    .map(green);
    println!("green pixels of the opaque, 0.25, 0.5 and 0.75 panels: {counts:?}");
    assert!(
        counts.windows(2).all(|w| w[0] > w[1]) && counts[3] > 10,
        "green pixels of the opaque, 0.25, 0.5 and 0.75 panels: {counts:?}"
    );
}

/// Pixels of `image` within the projected bounds of mesh `name` whose green exceeds their red
/// and blue.
fn green_pixels(description: &SceneDescription, shot: &Shot, image: &Image, name: &str) -> usize {
    let mesh = description.scene.meshes.iter().find(|m| m.name == name);
    let mesh = mesh.unwrap_or_else(|| panic!("mesh {name}"));
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| {
            let q = shot.camera.project(p);
            (lo.min(q), hi.max(q))
        });
    let (w, h) = (image.width, image.height);
    let inside = |x: u32, y: u32| {
        let (x, y) = (x as f32 + 0.5, y as f32 + 0.5);
        (lo.x..=hi.x).contains(&x) && (lo.y..=hi.y).contains(&y)
    };
    (0..w * h)
        .filter(|&i| {
            let p = image.pixels[i as usize];
            inside(i % w, i / w) && p.y > p.x && p.y > p.z
        })
        .count()
}

#[test]
fn the_scanned_apple_loads_its_4k_texture_and_renders_red() {
    let path = asset("food_apple_01/food_apple_01_4k.gltf");
    let start = Instant::now();
    let description = load(&path).unwrap_or_else(|e| panic!("{e}"));
    println!("loaded in {:.2} s", start.elapsed().as_secs_f64());
    let scene = &description.scene;
    assert_eq!(scene.triangle_count(), 7012);
    // The normal map is read, in the frame of tangents the loader finds.
    assert!(description.notices.is_empty(), "{:?}", description.notices);
    assert_eq!(
        scene.textures.len(),
        3,
        "the base colour, the roughness and the normal map"
    );
    assert!(scene.materials[0].normal_texture.is_some());
    assert!(scene
        .meshes
        .iter()
        .all(|m| m.tangents.len() == m.positions.len()));
    for texture in &scene.textures {
        let level = texture.levels[0];
        assert_eq!((level.width, level.height), (4096, 4096));
    }
    let start = Instant::now();
    let (_, image) = render_small(&description, 64, 48);
    println!("rendered in {:.2} s", start.elapsed().as_secs_f64());
    // The apple is the pixels that are not the black background, most of its bounding
    // sphere's outline (95 % of the half height: 1,630 pixels); its texture is red, with
    // yellow-green flecks (measured: 1,392 pixels, mean 0.191, 0.0130, 0.0075 linear).
    let apple: Vec<Vec3> = image
        .pixels
        .iter()
        .copied()
        .filter(|p| *p != Vec3::ZERO)
        .collect();
    let mean = apple.iter().sum::<Vec3>() / apple.len() as f32;
    println!("{} apple pixels, mean {mean}", apple.len());
    assert!(
        (1100..1630).contains(&apple.len()),
        "{} apple pixels",
        apple.len()
    );
    assert!(
        mean.x > 0.1 && mean.x > 5.0 * mean.y && mean.x > 5.0 * mean.z,
        "the apple's mean colour {mean} is not red"
    );
}

/// The README's apples: five nodes of the scanned apple on a table, the file's camera and key
/// light; the apples' base colour, roughness and normal textures decoded once for all five.
#[test]
fn the_readme_apples_load_with_their_camera_and_light() {
    let description = load(&asset("food_apple_01/apples.gltf")).unwrap_or_else(|e| panic!("{e}"));
    let scene = &description.scene;
    assert_eq!(scene.triangle_count(), 5 * 7012 + 2);
    assert_eq!(scene.textures.len(), 3);
    let level = scene.textures[0].levels[0];
    assert_eq!((level.width, level.height), (4096, 4096));
    assert_eq!(scene.lights.len(), 1);
    assert!((scene.lights[0].position - Vec3::new(-0.5, 0.9, 0.7)).length() < 1e-6);
    assert_eq!(description.cameras.len(), 1);
    assert_eq!(description.cameras[0].name, "view");
    let resolved = shot(&description.settings, scene).unwrap_or_else(|e| panic!("{e}"));
    assert!((resolved.camera.frame.eye - Vec3::new(0.02, 0.16, 0.62)).length() < 1e-6);
}
