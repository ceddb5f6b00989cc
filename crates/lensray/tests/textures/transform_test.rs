//! Khronos' TextureTransformTest sample (glTF-Sample-Assets, `Models/TextureTransformTest`),
//! rebuilt here from its published values with textures of our own: six 1 x 1 quads, the top
//! row reading texture coordinates (0, 0) - (0.5, 0.5) through the offsets (0.5, 0), (0, 0.5) and
//! (0.5, 0.5); the bottom row reading (0, 0) - (1, 1) through a rotation of 22.5 degrees, a scale
//! of 1.5 and all three together (offset (-0.2, -0.1), rotation 0.3, scale 1.5); the nodes, the
//! marker quads (green: correct, yellow: the transform not applied, red: the rotation the
//! other way) and the clamping sampler where the sample has them. The sample's images are not
//! used: the quadrant texture has the "not applied" yellow where the sample's UV texture has
//! it, and a distinct colour in each quadrant an offset should show; the arrow texture's green
//! tip lies on the diagonal the sample's arrow points along.

use glam::{Vec2, Vec3};
use lensray::paths::{PathChoice, PathKind};
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams};
use lensray_core::film::Image;
use lensray_core::scene::Scene;
use lensray_core::settings::{Shading, Shot};

use crate::gpu_support::{self, render_scene, settings, write_png};

const GREEN: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const YELLOW: Vec3 = Vec3::new(1.0, 1.0, 0.0);
const RED: Vec3 = Vec3::new(1.0, 0.0, 0.0);
const WHITE: Vec3 = Vec3::ONE;
/// The colours the offset squares should show: the quadrants at (0.5, 0), (0, 0.5), (0.5, 0.5).
const CYAN: Vec3 = Vec3::new(0.0, 1.0, 1.0);
const MAGENTA: Vec3 = Vec3::new(1.0, 0.0, 1.0);
const BLUE: Vec3 = Vec3::new(0.0, 0.0, 1.0);

/// The sample's arrow, untransformed, points from the texture's origin at the yellow marker's
/// place, (0.7778, 0.7778) (its node at (0.2778, -0.2778) from the quad's centre); our arrow's
/// tip lies on that diagonal, inside the quad whichever of the sample's transforms reads it.
const SAMPLE_TIP: Vec2 = Vec2::splat(0.5 + 0.277_817_46);
const TIP: Vec2 = Vec2::splat(0.6);
const TIP_RADIUS: f32 = 0.07;

/// The quadrant texture (v down): yellow where texture coordinates (0, 0) - (0.5, 0.5) read it
/// (what an offset square shows where the offset is not applied), cyan, magenta and blue where
/// the offsets (0.5, 0), (0, 0.5), (0.5, 0.5) move them; a white dot near each quadrant's
/// (low u, low v) corner tells a mirrored read.
fn quadrant_texel(uv: Vec2) -> Vec3 {
    let corner = Vec2::new(
        if uv.x < 0.5 { 0.0 } else { 0.5 },
        if uv.y < 0.5 { 0.0 } else { 0.5 },
    );
    if (uv - corner - Vec2::splat(0.1)).length() < 0.06 {
        return WHITE;
    }
    match (uv.x < 0.5, uv.y < 0.5) {
        (true, true) => YELLOW,
        (false, true) => CYAN,
        (true, false) => MAGENTA,
        (false, false) => BLUE,
    }
}

/// The arrow texture: light grey, a dark shaft along the diagonal from near the origin to the
/// green tip at `TIP`.
fn arrow_texel(uv: Vec2) -> Vec3 {
    if (uv - TIP).length() < TIP_RADIUS {
        return GREEN;
    }
    let along = uv.dot(Vec2::ONE) / 2.0;
    let across = (uv.x - uv.y).abs() / 2f32.sqrt();
    if across < 0.025 && (0.08..TIP.x).contains(&along) {
        Vec3::splat(0.05)
    } else {
        Vec3::splat(0.75)
    }
}

fn write_texture(path: &std::path::Path, texel: fn(Vec2) -> Vec3) {
    let n = 64;
    image::RgbaImage::from_fn(n, n, |x, y| {
        let c = texel(Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / n as f32) * 255.0;
        image::Rgba([c.x as u8, c.y as u8, c.z as u8, 255])
    })
    .save(path)
    .expect("write png");
}

/// One of the sample's six squares: its node's place, which texture coordinates it reads
/// (true: (0, 0) - (0.5, 0.5)) and its transform.
struct Square {
    name: &'static str,
    at: Vec2,
    half_texcoords: bool,
    offset: Vec2,
    rotation: f32,
    scale: Vec2,
}

const SQUARES: [Square; 6] = [
    Square {
        name: "Offset U",
        at: Vec2::new(-1.1, 0.55),
        half_texcoords: true,
        offset: Vec2::new(0.5, 0.0),
        rotation: 0.0,
        scale: Vec2::ONE,
    },
    Square {
        name: "Offset V",
        at: Vec2::new(0.0, 0.55),
        half_texcoords: true,
        offset: Vec2::new(0.0, 0.5),
        rotation: 0.0,
        scale: Vec2::ONE,
    },
    Square {
        name: "Offset UV",
        at: Vec2::new(1.1, 0.55),
        half_texcoords: true,
        offset: Vec2::new(0.5, 0.5),
        rotation: 0.0,
        scale: Vec2::ONE,
    },
    Square {
        name: "Rotation",
        at: Vec2::new(-1.1, -0.55),
        half_texcoords: false,
        offset: Vec2::ZERO,
        rotation: std::f32::consts::FRAC_PI_8,
        scale: Vec2::ONE,
    },
    Square {
        name: "Scale",
        at: Vec2::new(0.0, -0.55),
        half_texcoords: false,
        offset: Vec2::ZERO,
        rotation: 0.0,
        scale: Vec2::splat(1.5),
    },
    Square {
        name: "All",
        at: Vec2::new(1.1, -0.55),
        half_texcoords: false,
        offset: Vec2::new(-0.2, -0.1),
        rotation: 0.3,
        scale: Vec2::splat(1.5),
    },
];

/// The sample's marker quads: parent square, place from its centre, size, colour.
const MARKERS: [(usize, Vec2, f32, Vec3); 6] = [
    (3, Vec2::new(-0.079_048_22, -0.516_267_5), 0.15, GREEN),
    (3, Vec2::new(0.277_817_46, -0.277_817_46), 0.15, YELLOW),
    (3, Vec2::new(0.516_267_5, 0.079_048_22), 0.15, RED),
    (4, Vec2::new(0.018_544_97, -0.018_544_97), 0.1, GREEN),
    (4, Vec2::new(0.277_817_46, -0.277_817_46), 0.15, YELLOW),
    (5, Vec2::new(-0.07, -0.25), 0.1, GREEN),
];

impl Square {
    /// The texture coordinates whose texel this square shows at `texcoord` under the viewers'
    /// `KHR_texture_transform` (scale, rotation u' = cos u + sin v, v' = -sin u + cos v,
    /// offset); `sign` -1 turns the rotation the other way (the sample's red marker).
    fn uv(&self, texcoord: Vec2, sign: f32) -> Vec2 {
        let (s, c) = (sign * self.rotation).sin_cos();
        let p = texcoord * self.scale;
        Vec2::new(c * p.x + s * p.y, -s * p.x + c * p.y) + self.offset
    }

    /// The inverse of `uv`: where on the square (texture coordinates) the texel `uv` shows.
    fn texcoord_of(&self, uv: Vec2, sign: f32) -> Vec2 {
        let (s, c) = (sign * self.rotation).sin_cos();
        let p = uv - self.offset;
        Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y) / self.scale
    }

    /// The square's point (its centre at `at`, v down) of texture coordinates `texcoord`
    /// (the quad's full range).
    fn point(&self, texcoord: Vec2) -> Vec3 {
        let t = if self.half_texcoords {
            texcoord * 2.0
        } else {
            texcoord
        };
        (self.at + Vec2::new(t.x - 0.5, 0.5 - t.y)).extend(0.0)
    }
}

/// The sample's file rebuilt: its nodes, meshes, accessors (one quad, texture coordinates
/// (0, 0) - (1, 1) and (0, 0) - (0.5, 0.5)), materials, transforms and sampler, with our textures.
fn gltf_json() -> String {
    let transform = |s: &Square| {
        format!(
            r#"{{"offset": [{}, {}], "rotation": {}, "scale": [{}, {}]}}"#,
            s.offset.x, s.offset.y, s.rotation, s.scale.x, s.scale.y
        )
    };
    let mut materials: Vec<String> = SQUARES
        .iter()
        .map(|s| {
            let texture = usize::from(!s.half_texcoords);
            format!(
                r#"{{"name": "{}", "pbrMetallicRoughness": {{"metallicFactor": 0, "baseColorTexture": {{"index": {texture}, "extensions": {{"KHR_texture_transform": {}}}}}}}}}"#,
                s.name,
                transform(s)
            )
        })
        .collect();
    for c in [GREEN, YELLOW, RED] {
        materials.push(format!(
            r#"{{"pbrMetallicRoughness": {{"metallicFactor": 0, "baseColorFactor": [{}, {}, {}, 1]}}}}"#,
            c.x, c.y, c.z
        ));
    }
    let meshes: Vec<String> = (0..materials.len())
        .map(|m| {
            let uv = if m < 3 { 2 } else { 1 };
            format!(
                r#"{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": {uv}}}, "indices": 3, "material": {m}}}]}}"#
            )
        })
        .collect();
    let mut nodes: Vec<String> = SQUARES
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let children: Vec<String> = (0..MARKERS.len())
                .filter(|&m| MARKERS[m].0 == i)
                .map(|m| (6 + m).to_string())
                .collect();
            // glTF allows no empty list of children.
            let children = if children.is_empty() {
                String::new()
            } else {
                format!(r#", "children": [{}]"#, children.join(", "))
            };
            format!(
                r#"{{"name": "{}", "mesh": {i}, "translation": [{}, {}, 0]{children}}}"#,
                s.name, s.at.x, s.at.y
            )
        })
        .collect();
    for (_, at, size, colour) in MARKERS {
        let mesh = 6 + [GREEN, YELLOW, RED]
            .iter()
            .position(|&c| c == colour)
            .unwrap_or(0);
        nodes.push(format!(
            r#"{{"mesh": {mesh}, "translation": [{}, {}, 0.01], "scale": [{size}, {size}, {size}]}}"#,
            at.x, at.y
        ));
    }
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0, 1, 2, 3, 4, 5]}}],
  "nodes": [{}], "meshes": [{}], "materials": [{}],
  "textures": [{{"source": 0, "sampler": 0}}, {{"source": 1, "sampler": 0}}],
  "images": [{{"uri": "quadrants.png"}}, {{"uri": "arrow.png"}}],
  "samplers": [{{"wrapS": 33071, "wrapT": 33071, "magFilter": 9729, "minFilter": 9729}}],
  "buffers": [{{"uri": "quad.bin", "byteLength": 124}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                  {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": 80, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": 112, "byteLength": 12}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]}},
                {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
                {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}},
                {{"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
  "extensionsUsed": ["KHR_texture_transform"]}}"#,
        nodes.join(",\n    "),
        meshes.join(",\n    "),
        materials.join(",\n    ")
    )
}

fn scene(dir: &std::path::Path) -> Scene {
    write_texture(&dir.join("quadrants.png"), quadrant_texel);
    write_texture(&dir.join("arrow.png"), arrow_texel);
    let floats: [f32; 28] = [
        -0.5, 0.5, 0.0, -0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, // positions
        0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, // (0, 0) - (1, 1)
        0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0, // (0, 0) - (0.5, 0.5)
    ];
    let mut bin: Vec<u8> = floats.iter().flat_map(|v| v.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("quad.bin"), &bin).expect("write bin");
    let path = dir.join("TextureTransformTest.gltf");
    std::fs::write(&path, gltf_json()).expect("write gltf");
    lensray_core::scene::load_gltf(&path)
        .expect("the rebuilt sample loads")
        .scene
}

/// Square on, orthographic, 60 pixels to the unit, the whole sample in frame.
fn camera() -> Camera {
    CameraParams {
        eye: Vec3::new(0.0, 0.0, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: ProjectionParams::Orthographic { height: 2.4 },
        lens: LensParams::Pinhole,
        near: 0.1,
        far: 10.0,
        width: 216,
        height: 144,
        movements: lensray_core::camera::Movements::NONE,
    }
    .build()
    .expect("valid camera")
}

/// One expectation: the colour at a point of the sample, or a colour it must not be.
struct Check {
    what: String,
    at: Vec3,
    colour: Vec3,
    is: bool,
}

/// What the sample says each square shows, where, in our textures' colours.
fn checks() -> Vec<Check> {
    let check = |what: String, at, colour, is| Check {
        what,
        at,
        colour,
        is,
    };
    let mut out = Vec::new();
    for (s, colour) in SQUARES[..3].iter().zip([CYAN, MAGENTA, BLUE]) {
        let name = s.name;
        out.push(check(
            format!("{name}: centre"),
            s.point(Vec2::splat(0.3)),
            colour,
            true,
        ));
        out.push(check(
            format!("{name}: not yellow"),
            s.point(Vec2::splat(0.3)),
            YELLOW,
            false,
        ));
        out.push(check(
            format!("{name}: dot at its corner"),
            s.point(Vec2::splat(0.1)),
            WHITE,
            true,
        ));
        out.push(check(
            format!("{name}: no dot opposite"),
            s.point(Vec2::splat(0.4)),
            WHITE,
            false,
        ));
    }
    for s in &SQUARES[3..] {
        let name = s.name;
        let tip = s.texcoord_of(TIP, 1.0);
        out.push(check(
            format!("{name}: the arrow's tip"),
            s.point(tip),
            GREEN,
            true,
        ));
        out.push(check(
            format!("{name}: no tip where the transform is not applied"),
            s.point(TIP),
            GREEN,
            false,
        ));
        if s.rotation != 0.0 {
            let reversed = s.texcoord_of(TIP, -1.0);
            out.push(check(
                format!("{name}: no tip where the rotation turns the other way"),
                s.point(reversed),
                GREEN,
                false,
            ));
        }
    }
    for (parent, at, _, colour) in MARKERS {
        let at = (SQUARES[parent].at + at).extend(0.0);
        out.push(check(
            format!("{}'s marker quad", SQUARES[parent].name),
            at,
            colour,
            true,
        ));
    }
    out
}

/// The sample's marker quads sit where the viewers' transform takes its arrow's tip
/// (`SAMPLE_TIP`): green where the transform takes it (for "All" within 0.025, a quarter of its
/// marker's width: the sample places that one to two decimals, 0.02 from the transform's
/// place), yellow where no transform leaves it, red where the reversed rotation takes it.
fn assert_the_markers_follow_the_transform() {
    for (parent, at, _, colour) in MARKERS {
        let s = &SQUARES[parent];
        let texcoord = match colour {
            c if c == GREEN => s.texcoord_of(SAMPLE_TIP, 1.0),
            c if c == RED => s.texcoord_of(SAMPLE_TIP, -1.0),
            _ => SAMPLE_TIP,
        };
        let want = s.point(texcoord).truncate() - s.at;
        let tolerance = if s.name == "All" { 0.025 } else { 1e-5 };
        let off = (want - at).length();
        if colour != YELLOW {
            let back = s.uv(texcoord, if colour == RED { -1.0 } else { 1.0 });
            assert!(
                (back - SAMPLE_TIP).length() < 1e-5,
                "{}: the transform does not invert: {back} against {SAMPLE_TIP}",
                s.name
            );
        }
        assert!(
            off < tolerance,
            "{}: the sample's {colour} marker at {at}, the transform's place {want} (off by {off})",
            s.name
        );
    }
}

fn failures(image: &Image, camera: &Camera) -> Vec<String> {
    let mut out = Vec::new();
    for c in checks() {
        let p = camera.project(c.at);
        let (x, y) = (p.x.floor() as u32, p.y.floor() as u32);
        let got = image.pixels[(y * image.width + x) as usize];
        let error = (got - c.colour).abs().max_element();
        if (error < 0.1) != c.is {
            let want = if c.is { "want" } else { "must not be" };
            out.push(format!(
                "{}: pixel ({x}, {y}) is {got}, {want} {} (largest channel difference {error:.3})",
                c.what, c.colour
            ));
        }
    }
    out
}

/// Each square of the rebuilt TextureTransformTest shows what the sample says it should: the
/// offset squares their quadrant (not the yellow), the right way round; the arrow's green tip
/// where the transform takes it (and not where an unapplied or reversed transform would); the
/// marker quads in place; on the CPU and on the ray-query path, which matches the CPU image
/// within the usual bounds.
#[test]
fn texture_transform_test_squares_show_their_correct_markers() {
    let test = "texture_transform_test_squares_show_their_correct_markers";
    assert_the_markers_follow_the_transform();
    let dir = tempfile::tempdir().expect("a temporary folder");
    let scene = scene(dir.path());
    let camera = camera();
    let shot = Shot {
        camera: camera.clone(),
        render: settings(Shading::Unlit, 1),
    };
    let cpu = PathChoice::Only(PathKind::Cpu);
    let (Some(reference), Some(gpu)) = (
        render_scene(test, cpu, &scene, &shot),
        render_scene(test, PathKind::RayQuery.into(), &scene, &shot),
    ) else {
        return;
    };
    let checked = checks().len();
    write_png(&reference, "texture-transform-test-cpu.png");
    for (path, image) in [("cpu", &reference), ("rayquery", &gpu)] {
        let failed = failures(image, &camera);
        if !failed.is_empty() {
            write_png(&reference, "texture-transform-test-cpu.png");
            write_png(&gpu, "texture-transform-test-rayquery.png");
            panic!(
                "{path}: {} of {checked} checks failed:\n{}",
                failed.len(),
                failed.join("\n")
            );
        }
    }
    let diff = gpu_support::compare(&gpu, &reference, 1.0 / 255.0);
    println!("{checked} checks pass on cpu and rayquery; rayquery vs cpu {diff:?}");
    assert!(
        diff.within >= 0.999 && diff.mean_abs < 1e-3,
        "rayquery differs from the CPU: {diff:?}"
    );
}
