//! Procedural geometry and the generated scenes (`cornell_box`, `sphere_row`, `dense`, `bokeh`).
//!
//! Conventions: world right-handed, y up, metres. Every primitive is wound counter-clockwise seen
//! from outside (the geometric normal `cross(b - a, c - a)` points out of solids and to the front
//! of quads), and carries unit vertex normals.

use std::f32::consts::{PI, TAU};

use glam::Vec3;

use super::file::SceneDescription;
use super::{Bounds, Material, Mesh, Scene};
use crate::settings::Shading;
use crate::settings::{
    CameraSettings, ImageSettings, LightSettings, Lights, ProjectionKind, RenderStyle, Settings,
};

/// Collects meshes and materials into a [`Scene`].
#[derive(Clone, Debug, Default)]
pub struct SceneBuilder {
    pub scene: Scene,
}

impl SceneBuilder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a material and returns its index.
    pub fn material(&mut self, name: &str, diffuse: Vec3, emission: Vec3) -> u32 {
        self.scene.materials.push(Material {
            name: name.into(),
            diffuse,
            emission,
            ..Default::default()
        });
        (self.scene.materials.len() - 1) as u32
    }

    pub fn add(&mut self, mesh: Mesh) {
        self.scene.meshes.push(mesh);
    }

    pub fn finish(self) -> Scene {
        self.scene
    }
}

/// Triangles of a [`uv_sphere`] with these parameters.
pub fn uv_sphere_triangles(segments: u32, stacks: u32) -> usize {
    2 * segments as usize * (stacks as usize - 1)
}

/// A UV sphere: `segments` (>= 3) around the y axis, `stacks` (>= 2) from pole to pole, one vertex
/// per pole, smooth normals. `2 * segments * (stacks - 1)` triangles.
pub fn uv_sphere(
    name: &str,
    center: Vec3,
    radius: f32,
    segments: u32,
    stacks: u32,
    material: u32,
) -> Mesh {
    assert!(segments >= 3 && stacks >= 2, "sphere too coarse");
    let rings = stacks - 1;
    let mut normals = Vec::with_capacity((rings * segments + 2) as usize);
    normals.push(Vec3::Y);
    for k in 1..stacks {
        let theta = PI * k as f32 / stacks as f32;
        let (sin_t, cos_t) = theta.sin_cos();
        for j in 0..segments {
            let phi = TAU * j as f32 / segments as f32;
            let (sin_p, cos_p) = phi.sin_cos();
            normals.push(Vec3::new(sin_t * cos_p, cos_t, sin_t * sin_p));
        }
    }
    normals.push(Vec3::NEG_Y);
    let bottom = normals.len() as u32 - 1;
    let ring = |k: u32, j: u32| 1 + k * segments + j % segments;

    let mut triangles = Vec::with_capacity(uv_sphere_triangles(segments, stacks));
    for j in 0..segments {
        triangles.push([0, ring(0, j + 1), ring(0, j)]);
    }
    for k in 0..rings - 1 {
        for j in 0..segments {
            let (u0, u1, l0, l1) = (
                ring(k, j),
                ring(k, j + 1),
                ring(k + 1, j),
                ring(k + 1, j + 1),
            );
            triangles.push([u0, u1, l0]);
            triangles.push([u1, l1, l0]);
        }
    }
    for j in 0..segments {
        triangles.push([bottom, ring(rings - 1, j), ring(rings - 1, j + 1)]);
    }
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: name.into(),
        positions: normals.iter().map(|&n| center + radius * n).collect(),
        material_ids: vec![material; triangles.len()],
        normals,
        triangles,
        ..Default::default()
    }
}

/// A grid of `nu` x `nv` cells spanning the parallelogram `corner + s u + t v`, `s, t` in [0, 1],
/// facing `cross(u, v)`, texture coordinates (s, t); `material(i, j)` gives cell (i along u, j
/// along v) its material.
pub fn grid(
    name: &str,
    corner: Vec3,
    u: Vec3,
    v: Vec3,
    (nu, nv): (u32, u32),
    mut material: impl FnMut(u32, u32) -> u32,
) -> Mesh {
    assert!(nu >= 1 && nv >= 1, "empty grid");
    let normal = u.cross(v).normalize();
    let mut positions = Vec::with_capacity(((nu + 1) * (nv + 1)) as usize);
    let mut texcoords = Vec::with_capacity(positions.capacity());
    for j in 0..=nv {
        for i in 0..=nu {
            let (s, t) = (i as f32 / nu as f32, j as f32 / nv as f32);
            positions.push(corner + u * s + v * t);
            texcoords.push(glam::Vec2::new(s, t));
        }
    }
    let index = |i: u32, j: u32| j * (nu + 1) + i;
    let mut triangles = Vec::with_capacity(2 * (nu * nv) as usize);
    let mut material_ids = Vec::with_capacity(2 * (nu * nv) as usize);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
            let m = material(i, j);
            material_ids.extend([m, m]);
        }
    }
    Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: name.into(),
        normals: vec![normal; positions.len()],
        positions,
        texcoords,
        texcoords1: Vec::new(),
        triangles,
        material_ids,
    }
}

/// One quad `corner, corner + u, corner + u + v, corner + v` facing `cross(u, v)`: 2 triangles.
pub fn quad(name: &str, corner: Vec3, u: Vec3, v: Vec3, material: u32) -> Mesh {
    grid(name, corner, u, v, (1, 1), |_, _| material)
}

/// A checkerboard on the plane y = `height`, facing +y, covering `[x0, x1] x [z0, z1]` with square
/// tiles of side `tile` (the extent is rounded up to whole tiles); the tile at the minimum corner
/// gets `materials[0]`.
pub fn checkerboard(
    name: &str,
    (x0, x1): (f32, f32),
    (z0, z1): (f32, f32),
    height: f32,
    tile: f32,
    materials: [u32; 2],
) -> Mesh {
    let nx = ((x1 - x0) / tile).ceil().max(1.0) as u32;
    let nz = ((z1 - z0) / tile).ceil().max(1.0) as u32;
    // u along +z, v along +x: cross(z, x) = +y.
    grid(
        name,
        Vec3::new(x0, height, z0),
        Vec3::new(0.0, 0.0, nz as f32 * tile),
        Vec3::new(nx as f32 * tile, 0.0, 0.0),
        (nz, nx),
        |i, j| materials[((i + j) % 2) as usize],
    )
}

/// A box with flat faces (24 vertices, 12 triangles): centre, half extents along its own axes,
/// turned by `yaw` radians about +y.
pub fn cuboid(name: &str, center: Vec3, half: Vec3, yaw: f32, material: u32) -> Mesh {
    let (s, c) = yaw.sin_cos();
    let axes = [
        Vec3::new(c, 0.0, -s) * half.x,
        Vec3::Y * half.y,
        Vec3::new(s, 0.0, c) * half.z,
    ];
    let mut mesh = Mesh {
        colours: Vec::new(),
        tangents: Vec::new(),
        name: name.into(),
        ..Mesh::default()
    };
    for i in 0..3 {
        let (n, u, v) = (axes[i], axes[(i + 1) % 3], axes[(i + 2) % 3]);
        // cross(u, v) is along +n for the cyclic order; swapping the edges turns the face round.
        append(
            &mut mesh,
            quad("", center + n - u - v, 2.0 * u, 2.0 * v, material),
        );
        append(
            &mut mesh,
            quad("", center - n - u - v, 2.0 * v, 2.0 * u, material),
        );
    }
    mesh
}

/// Appends `other`'s geometry to `mesh` (both with normals, or both without).
pub fn append(mesh: &mut Mesh, other: Mesh) {
    let offset = mesh.positions.len() as u32;
    mesh.positions.extend(other.positions);
    mesh.normals.extend(other.normals);
    mesh.triangles
        .extend(other.triangles.iter().map(|t| t.map(|i| i + offset)));
    mesh.material_ids.extend(other.material_ids);
}

/// A saturated colour of hue `h` in turns ([0, 1) around the colour wheel), linear RGB.
pub fn hue(h: f32, saturation: f32, value: f32) -> Vec3 {
    let h6 = h.rem_euclid(1.0) * 6.0;
    let f = |n: f32| {
        let k = (n + h6) % 6.0;
        value - value * saturation * (k.min(4.0 - k)).clamp(0.0, 1.0)
    };
    Vec3::new(f(5.0), f(3.0), f(1.0))
}

/// Rounds to 4 decimals (0.1 mm) so settings print as short numbers.
pub fn round4(x: f32) -> f64 {
    (x as f64 * 1e4).round() / 1e4
}

fn round3(v: Vec3) -> [f64; 3] {
    [round4(v.x), round4(v.y), round4(v.z)]
}

/// Perspective thin-lens camera settings looking from `eye` at `target`, focused on the plane
/// through `subject` (`focus_distance` is measured along the view axis), with near and far
/// planes enclosing `bounds`.
pub fn camera_settings(
    eye: Vec3,
    target: Vec3,
    subject: Vec3,
    vfov_degrees: f64,
    aperture_radius: f64,
    bounds: Option<Bounds>,
) -> CameraSettings {
    let forward = (target - eye).normalize();
    let far = bounds
        .map(|b| {
            b.corners()
                .iter()
                .map(|&c| (c - eye).dot(forward))
                .fold(0.0f32, f32::max)
        })
        .unwrap_or(100.0);
    CameraSettings {
        projection: Some(ProjectionKind::Perspective),
        eye: Some(round3(eye)),
        target: Some(round3(target)),
        up: Some([0.0, 1.0, 0.0]),
        vfov_degrees: Some(vfov_degrees),
        aperture_radius: Some(aperture_radius),
        focus_distance: Some(round4((subject - eye).dot(forward))),
        near: Some(0.05),
        far: Some((far as f64 * 1.1 + 1.0).ceil()),
        ..CameraSettings::default()
    }
}

/// A generated scene with the settings every generator sets: 640x480, lit, and its point light
/// (`None`: the scene's emissive surfaces light it).
pub(crate) fn describe(
    scene: Scene,
    camera: CameraSettings,
    spp: u32,
    background: [f64; 3],
    light: Option<(Vec3, [f64; 3])>,
    source: &str,
) -> SceneDescription {
    SceneDescription {
        scene,
        settings: Settings {
            camera,
            image: ImageSettings {
                width: Some(640),
                height: Some(480),
                spp: Some(spp),
                seed: None,
                sampler: None,
                fps: None,
            },
            render: RenderStyle {
                shading: Some(Shading::Lit),
                background: Some(background),
                ..RenderStyle::default()
            },
            light: Lights(
                light
                    .map(|(position, intensity)| LightSettings {
                        position: Some(round3(position)),
                        intensity: Some(intensity),
                        ..LightSettings::default()
                    })
                    .into_iter()
                    .collect(),
            ),
        },
        source: source.into(),
        ..SceneDescription::default()
    }
}

/// A Cornell-box-style room 2 m wide, deep and high (x in [-1, 1], y in [0, 2], z in [-1, 1], open
/// towards +z): red left wall, green right wall, white floor, ceiling and back wall, a tall box
/// and a sphere, lit only by an emissive patch 2 mm under the ceiling (drawn as a light,
/// `reference::emitters`). The camera looks in through the open side, focused on the sphere.
/// 2232 triangles.
pub fn cornell_box() -> SceneDescription {
    let mut b = SceneBuilder::new();
    let white = b.material("white", Vec3::splat(0.73), Vec3::ZERO);
    let red = b.material("red", Vec3::new(0.65, 0.05, 0.05), Vec3::ZERO);
    let green = b.material("green", Vec3::new(0.12, 0.45, 0.15), Vec3::ZERO);
    let light = b.material("light", Vec3::splat(0.78), Vec3::splat(30.0));
    let blue = b.material("blue", Vec3::new(0.1, 0.2, 0.6), Vec3::ZERO);
    let (x, y, z) = (Vec3::X * 2.0, Vec3::Y * 2.0, Vec3::Z * 2.0);
    let lo = Vec3::new(-1.0, 0.0, -1.0);
    b.add(quad("floor", lo, z, x, white));
    b.add(quad("ceiling", lo + y, x, z, white));
    b.add(quad("back_wall", lo, x, y, white));
    b.add(quad("left_wall", lo, y, z, red));
    b.add(quad("right_wall", lo + x, z, y, green));
    b.add(quad(
        "ceiling_light",
        Vec3::new(-0.3, 1.998, -0.25),
        Vec3::X * 0.6,
        Vec3::Z * 0.5,
        light,
    ));
    b.add(cuboid(
        "tall_box",
        Vec3::new(-0.38, 0.6, -0.35),
        Vec3::new(0.28, 0.6, 0.28),
        0.3,
        white,
    ));
    let subject = Vec3::new(0.42, 0.35, 0.3);
    b.add(uv_sphere("sphere", subject, 0.35, 48, 24, blue));
    let scene = b.finish();
    let eye = Vec3::new(0.0, 1.0, 3.6);
    let camera = camera_settings(
        eye,
        Vec3::new(0.0, 1.0, 0.0),
        subject,
        40.0,
        0.06,
        scene.bounds(),
    );
    describe(
        scene,
        camera,
        32,
        [0.0, 0.0, 0.0],
        None,
        "generated cornell_box",
    )
}

/// Five spheres of distinct colours in a diagonal row receding in depth (1.5 m apart) on a grey
/// ground plane, focused on the middle one. 4802 triangles.
pub fn sphere_row() -> SceneDescription {
    let mut b = SceneBuilder::new();
    let ground = b.material("ground", Vec3::splat(0.5), Vec3::ZERO);
    let colours = [
        ("red", Vec3::new(0.8, 0.05, 0.05)),
        ("yellow", Vec3::new(0.8, 0.65, 0.05)),
        ("green", Vec3::new(0.05, 0.6, 0.1)),
        ("blue", Vec3::new(0.05, 0.15, 0.8)),
        ("magenta", Vec3::new(0.7, 0.05, 0.6)),
    ];
    b.add(quad(
        "ground",
        Vec3::new(-10.0, 0.0, -20.0),
        Vec3::Z * 30.0,
        Vec3::X * 20.0,
        ground,
    ));
    let radius = 0.4;
    let mut centers = Vec::new();
    for (i, (name, colour)) in colours.iter().enumerate() {
        let t = i as f32 - 2.0;
        let center = Vec3::new(0.45 * t, radius, -1.5 * t);
        let m = b.material(name, *colour, Vec3::ZERO);
        b.add(uv_sphere(
            &format!("sphere_{name}"),
            center,
            radius,
            32,
            16,
            m,
        ));
        centers.push(center);
    }
    let scene = b.finish();
    let subject = centers[2];
    let camera = camera_settings(
        Vec3::new(0.0, 1.2, 6.5),
        subject,
        subject,
        40.0,
        0.08,
        scene.bounds(),
    );
    describe(
        scene,
        camera,
        32,
        [0.5, 0.65, 0.85],
        Some((Vec3::new(3.0, 8.0, 6.0), [300.0, 300.0, 300.0])),
        "generated sphere_row",
    )
}

/// Triangles of the [`dense`] benchmark scene unless told otherwise (`lensray generate dense
/// --triangles`, `lensray bench --dense-triangles`).
pub const DEFAULT_DENSE_TRIANGLES: usize = 1_000_000;

/// Side of the grid of spheres in [`dense`].
pub const DENSE_GRID: u32 = 10;

/// A benchmark scene of at least `min_triangles` triangles: a 10 x 10 grid of finely tessellated
/// spheres (tessellation chosen to reach the count) on a checkerboard, seen obliquely and focused
/// on the middle of the grid.
pub fn dense(min_triangles: usize) -> SceneDescription {
    let mut b = SceneBuilder::new();
    let light_tile = b.material("tile_light", Vec3::splat(0.75), Vec3::ZERO);
    let dark_tile = b.material("tile_dark", Vec3::splat(0.1), Vec3::ZERO);
    let colours: Vec<u32> = (0..10)
        .map(|i| {
            b.material(
                &format!("hue_{i}"),
                hue(i as f32 / 10.0, 0.85, 0.8),
                Vec3::ZERO,
            )
        })
        .collect();
    let ground = checkerboard(
        "ground",
        (-16.0, 16.0),
        (-32.0, 8.0),
        0.0,
        1.0,
        [light_tile, dark_tile],
    );
    let spheres = (DENSE_GRID * DENSE_GRID) as usize;
    let needed = min_triangles.saturating_sub(ground.triangles.len());
    let mut segments = 6;
    let stacks = |segments: u32| (segments / 2).max(2);
    while spheres * uv_sphere_triangles(segments, stacks(segments)) < needed {
        segments += 2;
    }
    b.add(ground);
    let (spacing, radius) = (1.25, 0.5);
    let half = (DENSE_GRID - 1) as f32 * spacing / 2.0;
    for j in 0..DENSE_GRID {
        for i in 0..DENSE_GRID {
            let center = Vec3::new(i as f32 * spacing - half, radius, -(j as f32) * spacing);
            let m = colours[((i + j) % 10) as usize];
            b.add(uv_sphere(
                &format!("sphere_{i}_{j}"),
                center,
                radius,
                segments,
                stacks(segments),
                m,
            ));
        }
    }
    let scene = b.finish();
    let subject = Vec3::new(0.0, radius, -half);
    let camera = camera_settings(
        Vec3::new(-4.0, 3.0, 6.0),
        subject,
        subject,
        40.0,
        0.1,
        scene.bounds(),
    );
    describe(
        scene,
        camera,
        16,
        [0.5, 0.65, 0.85],
        Some((Vec3::new(-6.0, 12.0, 4.0), [600.0, 600.0, 600.0])),
        "generated dense",
    )
}

/// Depths (camera-space z, the subject at 6) and counts of [`bokeh`]'s rows of lights.
const BOKEH_ROWS: [(f32, u32); 4] = [(3.2, 3), (4.2, 4), (11.0, 5), (16.0, 6)];

/// A scene for the aperture's shape: a grey sphere in focus at 6 m on a dark background, lit by
/// a point light, and rows of small emissive spheres (3 cm at 6 m, warm and cool hues) at 3.2 and
/// 4.2 m in front of it and 11 and 16 m behind it, spread across the view so that each
/// out-of-focus light draws the aperture, turned by 180 degrees in front of the focal plane.
pub fn bokeh() -> SceneDescription {
    let mut b = SceneBuilder::new();
    let grey = b.material("subject", Vec3::splat(0.6), Vec3::ZERO);
    let eye = Vec3::new(0.0, 0.0, 6.0);
    let subject = Vec3::ZERO;
    b.add(uv_sphere("subject", subject, 0.5, 48, 24, grey));
    let vfov = 30.0f32;
    let half_height = (0.5 * vfov).to_radians().tan();
    for (row, &(depth, count)) in BOKEH_ROWS.iter().enumerate() {
        // Spread over 80 % of the view's width at that depth, each row at its own height.
        let half_width = 0.8 * half_height * depth * 4.0 / 3.0;
        let y = [0.72, -0.36, 0.36, -0.72][row] * half_height * depth;
        for i in 0..count {
            let t = (i as f32 + 0.5) / count as f32;
            let x = (2.0 * t - 1.0) * half_width;
            let colour = hue(
                0.08 + 0.55 * ((row as u32 * 7 + i) % 5) as f32 / 5.0,
                0.5,
                1.0,
            );
            let light = b.material(&format!("light_{row}_{i}"), Vec3::ZERO, 12.0 * colour);
            let center = eye - Vec3::Z * depth + Vec3::new(x, y, 0.0);
            let radius = 0.03 * depth / 6.0;
            b.add(uv_sphere(
                &format!("light_{row}_{i}"),
                center,
                radius,
                12,
                6,
                light,
            ));
        }
    }
    let scene = b.finish();
    let camera = camera_settings(eye, subject, subject, vfov as f64, 0.25, scene.bounds());
    describe(
        scene,
        camera,
        256,
        [0.01, 0.01, 0.015],
        Some((Vec3::new(2.0, 3.0, 7.0), [40.0, 40.0, 40.0])),
        "generated bokeh",
    )
}
