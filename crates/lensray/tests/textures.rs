//! Textures and alpha on every path: the GPU paths render the textured test card as the CPU
//! reference does (texture filtering, wrap modes, transforms, second texture coordinate sets,
//! masks, blended cuts and shadows through masks), and a texture at the focal plane stays as
//! sharp as through a pinhole; `KHR_texture_transform` as glTF viewers apply it, a texture's
//! `texCoord` read, and Khronos' TextureTransformTest sample rebuilt
//! (`textures/transform_test.rs`).

mod gpu_support;
#[path = "textures/transform_test.rs"]
mod transform_test;

use glam::{Vec2, Vec3};
use gpu_support::{
    assert_gpu_paths_match_cpu, orthographic_along_z, render_scene, settings, write_png,
};
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::scene::test_card::test_card;
use lensray_core::scene::{Light, Scene, TextureRef};
use lensray_core::settings::{Shading, Shot};

fn card_camera(lens: LensParams, width: u32, height: u32) -> Camera {
    camera_towards(Vec3::new(0.0, 0.8, 0.0), lens, width, height)
}

fn camera_towards(target: Vec3, lens: LensParams, width: u32, height: u32) -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, 1.2, 4.0),
        target,
        up: Vec3::Y,
        projection: ProjectionParams::Perspective { vfov_degrees: 50.0 },
        lens,
        near: 0.1,
        far: 100.0,
        width,
        height,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera")
}

fn shot(shading: Shading, spp: u32) -> Shot {
    let lens = LensParams::ThinLens {
        aperture_radius: 0.06,
        focus_distance: 4.3,
    };
    Shot {
        camera: card_camera(lens, 80, 60),
        render: settings(shading, spp),
    }
}

/// The test card under one point light, with textures that read a second texture coordinate
/// set: the gradient card's (its set turned a quarter from the first), the leaf's colour and
/// alpha (its set mirrored), and the sign's emission, whose mesh has no second set (it reads
/// (0, 0)).
fn lit_card() -> Scene {
    let mut scene = Scene {
        lights: vec![Light::point(Vec3::new(1.5, 3.0, 3.0), Vec3::splat(25.0))],
        ..test_card()
    };
    let turned: fn(Vec2) -> Vec2 = |t| Vec2::new(t.y, 1.0 - t.x);
    let mirrored: fn(Vec2) -> Vec2 = |t| Vec2::new(1.0 - t.x, t.y);
    for (name, second) in [("card", turned), ("leaf", mirrored)] {
        let mesh = scene.meshes.iter_mut().find(|m| m.name == name).unwrap();
        mesh.texcoords1 = mesh.texcoords.iter().map(|&t| second(t)).collect();
    }
    let set1 = |t: &mut Option<TextureRef>| t.as_mut().unwrap().texcoord_set = 1;
    let m = &mut scene.materials;
    set1(&mut m[1].diffuse_texture);
    set1(&mut m[2].diffuse_texture);
    set1(&mut m[2].alpha_texture);
    set1(&mut m[4].emission_texture);
    scene
}

/// Every traced GPU path and the raster path render the lit, textured, alpha-tested card as the
/// CPU reference does, as do the G-buffer's albedo AOV and the CPU's.
#[test]
fn gpu_paths_render_textures_and_alpha_as_the_cpu_does() {
    let test = "gpu_paths_render_textures_and_alpha_as_the_cpu_does";
    let shots = [Shading::Lit, Shading::Albedo].map(|s| (format!("textures-{s:?}"), shot(s, 8)));
    assert_gpu_paths_match_cpu(test, &lit_card(), &shots);
}

/// The gradient card at the focal plane reads the same texture level through a wide aperture as
/// through a pinhole: its pixels match the pinhole render's (the lens only spreads what is off
/// the focal plane), where a footprint that included the lens would blur it.
#[test]
fn a_texture_in_focus_is_as_sharp_as_through_a_pinhole() {
    let test = "a_texture_in_focus_is_as_sharp_as_through_a_pinhole";
    // The card alone, facing the camera square on at depth 4.5.
    let mut card = test_card();
    card.meshes = vec![card.meshes.swap_remove(1)];
    let (width, height) = (96, 72);
    let level = Vec3::new(0.0, 1.2, 0.0);
    let unlit = |lens| Shot {
        camera: camera_towards(level, lens, width, height),
        render: settings(Shading::Unlit, 64),
    };
    let wide = LensParams::ThinLens {
        aperture_radius: 0.25,
        focus_distance: 4.5,
    };
    let cpu = PathChoice::Only(PathKind::Cpu);
    let (Some(pinhole), Some(blurred)) = (
        render_scene(test, cpu, &card, &unlit(LensParams::Pinhole)),
        render_scene(test, cpu, &card, &unlit(wide)),
    ) else {
        return;
    };
    // The card's pixels, two pixels in from its edges (the only places the lens may spread
    // the background over it).
    let camera = camera_towards(level, LensParams::Pinhole, width, height);
    let corner = camera.project(Vec3::new(-1.6, 1.6, -0.5));
    let far = camera.project(Vec3::new(-0.4, 0.2, -0.5));
    let (lo, hi) = (
        Vec2::new(corner.x, corner.y) + 2.0,
        Vec2::new(far.x, far.y) - 2.0,
    );
    let mut worst = 0.0f32;
    let mut count = 0;
    for y in lo.y.ceil() as u32..hi.y.floor() as u32 {
        for x in lo.x.ceil() as u32..hi.x.floor() as u32 {
            let i = (y * width + x) as usize;
            worst = worst.max((pinhole.pixels[i] - blurred.pixels[i]).abs().max_element());
            count += 1;
        }
    }
    assert!(count > 200, "{count} card pixels");
    if worst > 0.01 {
        write_png(&pinhole, "texture-focus-pinhole.png");
        write_png(&blurred, "texture-focus-wide.png");
        panic!("the in-focus card differs from the pinhole's by {worst} at most");
    }
}

/// The quadrants of the texture `transformed_quad` writes, as glTF's UV space has them (v
/// down): red top left, green top right, blue bottom left, white bottom right.
fn quadrant_colour(uv: Vec2) -> Vec3 {
    match (uv.x.rem_euclid(1.0) < 0.5, uv.y.rem_euclid(1.0) < 0.5) {
        (true, true) => Vec3::X,
        (false, true) => Vec3::Y,
        (true, false) => Vec3::Z,
        (false, false) => Vec3::ONE,
    }
}

/// A glTF file of one 2 x 2 quad in the plane z = 0, facing +z, its corner (-1, 1) at texture
/// coordinates (0, 0) and (1, -1) at (1, 1), textured with the quadrant texture (32 x 32,
/// repeating) through `KHR_texture_transform`'s `transform` (JSON members).
fn transformed_quad(dir: &std::path::Path, transform: &str) -> Scene {
    let info = format!(r#""extensions": {{"KHR_texture_transform": {{{transform}}}}}"#);
    textured_quad(dir, &info, None)
}

/// The quad of `transformed_quad` with the base colour texture's other members `info` (JSON),
/// and TEXCOORD_1 where `second_set` gives its four corners'.
fn textured_quad(dir: &std::path::Path, info: &str, second_set: Option<[f32; 8]>) -> Scene {
    let texture = image::RgbaImage::from_fn(32, 32, |x, y| {
        let c = quadrant_colour(Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / 32.0) * 255.0;
        image::Rgba([c.x as u8, c.y as u8, c.z as u8, 255])
    });
    texture.save(dir.join("quadrants.png")).expect("write png");
    let floats: [f32; 20] = [
        -1.0, 1.0, 0.0, -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, // positions
        0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, // texture coordinates
    ];
    let mut bin: Vec<u8> = floats.iter().flat_map(|v| v.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    // TEXCOORD_1 after the indices: accessor 3.
    let (mut second, mut second_view, mut second_accessor) = ("", "", "");
    if let Some(set) = second_set {
        bin.extend(set.iter().flat_map(|v| v.to_le_bytes()));
        second = r#", "TEXCOORD_1": 3"#;
        second_view = r#", {"buffer": 0, "byteOffset": 92, "byteLength": 32}"#;
        second_accessor =
            r#", {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"}"#;
    }
    std::fs::write(dir.join("quad.bin"), &bin).expect("write bin");
    let byte_length = bin.len();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1{second}}}, "indices": 2, "material": 0}}]}}],
  "materials": [{{"doubleSided": true, "pbrMetallicRoughness": {{"metallicFactor": 0.0,
    "baseColorTexture": {{"index": 0, {info}}}}}}}],
  "textures": [{{"source": 0}}], "images": [{{"uri": "quadrants.png"}}],
  "buffers": [{{"uri": "quad.bin", "byteLength": {byte_length}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                  {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}{second_view}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
                {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
                {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}{second_accessor}],
  "extensionsUsed": ["KHR_texture_transform"]}}"#
    );
    let path = dir.join("quad.gltf");
    std::fs::write(&path, json).expect("write gltf");
    lensray_core::scene::load_gltf(&path)
        .expect("the quad loads")
        .scene
}

/// The quad of `textured_quad` seen square on, orthographic, filling a `width` x `height` image
/// (pixel centres map linearly onto it), unlit, one sample a pixel.
fn square_on(width: u32, height: u32) -> Shot {
    orthographic_along_z(3.0, width, height, 1)
}

/// A base colour texture with `texCoord: 1` reads TEXCOORD_1 on the CPU reference: the quad's
/// second set mirrors the first left to right, so every pixel away from a quadrant edge shows
/// the quadrant of the mirrored coordinates, the other side's colour from the first set's.
#[test]
fn a_texture_reads_the_set_its_tex_coord_names() {
    let test = "a_texture_reads_the_set_its_tex_coord_names";
    let dir = tempfile::tempdir().expect("a temporary folder");
    // Corners (-1, 1), (-1, -1), (1, -1), (1, 1): set 0 (0, 0), (0, 1), (1, 1), (1, 0).
    let mirrored = [1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0];
    let scene = textured_quad(dir.path(), r#""texCoord": 1"#, Some(mirrored));
    let (width, height) = (48, 48);
    let cpu = PathChoice::Only(PathKind::Cpu);
    let Some(image) = render_scene(test, cpu, &scene, &square_on(width, height)) else {
        return;
    };
    let (mut checked, mut worst) = (0, 0.0f32);
    for (i, got) in image.pixels.iter().enumerate() {
        let (x, y) = ((i as u32 % width) as f32, (i as u32 / width) as f32);
        let set0 = Vec2::new(x + 0.5, y + 0.5) / width as f32;
        let set1 = Vec2::new(1.0 - set0.x, set0.y);
        // A pixel within two pixels of a quadrant edge (the texture's own edges too, where it
        // repeats) may mix two colours.
        let near_edge = |t: f32| {
            let f = (t * 2.0).rem_euclid(1.0);
            0.5 * f.min(1.0 - f) < 2.0 / width as f32
        };
        if near_edge(set0.x) || near_edge(set0.y) {
            continue;
        }
        let want = quadrant_colour(set1);
        assert_ne!(want, quadrant_colour(set0), "the sets tell apart at {set0}");
        let error = (*got - want).abs().max_element();
        worst = worst.max(error);
        if error > 0.02 {
            write_png(&image, "texcoord-set-1-cpu.png");
            panic!("pixel ({x}, {y}) at set 0 {set0}, set 1 {set1} is {got}, not {want} (off by {error})");
        }
        checked += 1;
    }
    println!("{checked} pixels show set 1's quadrant, off by {worst} at most");
    assert!(
        checked > 1500,
        "only {checked} pixels away from quadrant edges"
    );
}

/// `KHR_texture_transform` as glTF viewers apply it (the glTF Sample Viewer, three.js,
/// Babylon.js; the TextureTransformTest sample's green marker): scale, then the rotation
/// u' = cos u + sin v, v' = -sin u + cos v, then the offset. The extension's sample GLSL has the
/// transposed rotation, which turns the other way (KhronosGroup/glTF issue #1563).
fn viewer_uv(uv: Vec2, offset: Vec2, rotation: f32, scale: Vec2, transposed: bool) -> Vec2 {
    let (s, c) = rotation.sin_cos();
    let s = if transposed { -s } else { s };
    let p = uv * scale;
    Vec2::new(c * p.x + s * p.y, -s * p.x + c * p.y) + offset
}

/// A quad textured by quadrant through a rotation of +90 degrees, and through an offset, a
/// non-uniform scale and a rotation of 30 degrees, shows at each pixel the quadrant the
/// viewers' convention predicts, on the CPU and on the ray-query path (which also matches the
/// CPU image within the usual bounds); the transposed rotation predicts other quadrants.
#[test]
fn texture_transforms_rotate_as_gltf_viewers_do() {
    let test = "texture_transforms_rotate_as_gltf_viewers_do";
    let dir = tempfile::tempdir().expect("a temporary folder");
    let cases = [
        ("rotate-90", Vec2::ZERO, 90f32.to_radians(), Vec2::ONE),
        (
            "offset-scale-rotate",
            Vec2::new(0.2, 0.6),
            30f32.to_radians(),
            Vec2::new(1.5, 0.75),
        ),
    ];
    let (width, height) = (48, 48);
    for (name, offset, rotation, scale) in cases {
        let transform = format!(
            r#""offset": [{}, {}], "rotation": {rotation}, "scale": [{}, {}]"#,
            offset.x, offset.y, scale.x, scale.y
        );
        let scene = transformed_quad(dir.path(), &transform);
        let shot = square_on(width, height);
        let cpu = PathChoice::Only(PathKind::Cpu);
        let (Some(reference), Some(gpu)) = (
            render_scene(test, cpu, &scene, &shot),
            render_scene(test, PathKind::RayQuery.into(), &scene, &shot),
        ) else {
            return;
        };
        let (mut checked, mut transposed_differs) = (0, 0);
        for (i, (c, g)) in reference.pixels.iter().zip(&gpu.pixels).enumerate() {
            let (x, y) = ((i as u32 % width) as f32, (i as u32 / width) as f32);
            let texcoord = Vec2::new(x + 0.5, y + 0.5) / width as f32;
            let uv = viewer_uv(texcoord, offset, rotation, scale, false);
            // Pixels whose texture coordinates lie within a pixel's reach (scaled up to 1.5
            // times, plus the filter's texels at up to the second level) of a quadrant's edge
            // may mix two colours.
            let near_edge = |t: f32| {
                let f = (t * 2.0).rem_euclid(1.0);
                0.5 * f.min(1.0 - f) < 0.1
            };
            if near_edge(uv.x) || near_edge(uv.y) {
                continue;
            }
            let want = quadrant_colour(uv);
            let transposed = viewer_uv(texcoord, offset, rotation, scale, true);
            transposed_differs += usize::from(quadrant_colour(transposed) != want);
            for (path, got) in [("cpu", c), ("rayquery", g)] {
                let error = (*got - want).abs().max_element();
                if error > 0.02 {
                    write_png(&reference, &format!("transform-{name}-cpu.png"));
                    write_png(&gpu, &format!("transform-{name}-rayquery.png"));
                    panic!("{name} {path}: pixel ({x}, {y}) at uv {uv} is {got}, not {want} (off by {error})");
                }
            }
            checked += 1;
        }
        let diff = gpu_support::compare(&gpu, &reference, 1.0 / 255.0);
        println!("{name}: {checked} pixels as predicted, {transposed_differs} of them another colour under the transposed rotation; rayquery vs cpu {diff:?}");
        assert!(
            checked > 500,
            "{name}: only {checked} pixels away from quadrant edges"
        );
        assert!(
            transposed_differs > checked / 4,
            "{name}: the test cannot tell the rotation's direction ({transposed_differs} of {checked})"
        );
        assert!(
            diff.within >= 0.999 && diff.mean_abs < 1e-3,
            "{name}: rayquery differs from the CPU: {diff:?}"
        );
    }
}
