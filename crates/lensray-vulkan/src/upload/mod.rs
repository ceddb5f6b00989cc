//! The upload of a shot into the structs the shaders read: the scene flattened into the arrays the shaders and the acceleration
//! structure builds read, and the camera / settings into the structs of `lensray_core::interface`
//! (their GLSL layouts are generated from the same definition).

use bytemuck::Zeroable;
use glam::Mat4;

use lensray_core::camera::Footprint;
use lensray_core::camera::{Camera, CocLens, Projection};
use lensray_core::film::tonemap::Display;
use lensray_core::interface::{
    GpuCamera, GpuCocLens, GpuFootprint, GpuLens, GpuLight, GpuMaterial, GpuTexture, GpuTextureRef,
    RasterPush, ResolvePush, TraceParams, ViewParams, ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE,
    APERTURE_MAX_FAN, ENVIRONMENT_MAP_LIGHTS, ENVIRONMENT_MAP_SEEN, LENS_MAX_SURFACES,
    LENS_PUPIL_BINS, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT, PROJECTION_ORTHOGRAPHIC,
    PROJECTION_PERSPECTIVE, SHADING_LIT, SHADING_UNLIT, SURFACE_ALPHA_TESTED, SURFACE_SINGLE_SIDED,
    SURFACE_TEXTURED, TEXTURE_NONE, TRI_HAS_COLOURS, TRI_HAS_NORMALS, TRI_HAS_TANGENTS,
    TRI_SINGLE_SIDED, WRAP_CLAMP_TO_EDGE, WRAP_MIRRORED_REPEAT, WRAP_REPEAT,
};
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::order::sided_order;
use lensray_core::scene::texture::Wrap;
use lensray_core::scene::{AlphaMode, Material, TextureRef};
use lensray_core::scene::{Light, LightKind, Mesh, Scene};
use lensray_core::settings::{Shading, Shot};

mod camera;
mod emitters;
pub(crate) mod motion;

pub(crate) use camera::*;
pub(crate) use emitters::FlatEmitters;

use crate::core::error::GpuError;
use crate::scene::texels::flatten as flatten_textures;

/// One mesh's range in the flattened arrays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MeshRange {
    pub first_triangle: u32,
    pub triangle_count: u32,
    /// No triangle's material is alpha-tested: ray queries may skip the test.
    pub opaque: bool,
    /// Every triangle's material is single-sided (each mesh's single- and double-sided
    /// triangles are two ranges): its instance culls back faces.
    pub single_sided: bool,
}

/// Consecutive triangles whose surfaces have the same SURFACE_* bits (`surface_bits`): the raster
/// passes draw each run with the pipeline specialized for them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SurfaceRun {
    pub first_triangle: u32,
    pub triangle_count: u32,
    pub surfaces: u32,
}

/// Every mesh concatenated, its triangles in a spatial order (`scene::order`): one vertex array (vec4 positions and normals, std430 friendly),
/// global vertex indices, per-triangle info, materials.
#[derive(Clone, Debug, Default)]
pub(crate) struct FlatScene {
    pub positions: Vec<[f32; 4]>,
    pub normals: Vec<[f32; 4]>,
    /// Per vertex; (0, 0) for meshes without texture coordinates.
    pub texcoords: Vec<[f32; 2]>,
    /// Per vertex the second set; (0, 0) for meshes without one; one (0, 0) when no mesh has
    /// one (the shaders read (0, 0) past its end).
    pub texcoords1: Vec<[f32; 2]>,
    /// Per vertex (RGBA); zeros for meshes without colours; one zero when no mesh has any.
    pub colours: Vec<[f32; 4]>,
    /// Per vertex; zeros for meshes without tangents; one zero when no mesh has any.
    pub tangents: Vec<[f32; 4]>,
    /// The moving vertices' attributes at each step (`motion.rs`); one zero when nothing moves.
    pub motion_vertices: Vec<[f32; 4]>,
    pub indices: Vec<u32>,
    pub tri_info: Vec<u32>,
    pub materials: Vec<GpuMaterial>,
    pub textures: Vec<GpuTexture>,
    /// Every texture's texels, every level it is read at.
    pub texels: Vec<u32>,
    /// The textures read from a coarser level to fit (name, size, size read at).
    pub coarsened: Vec<(String, [u32; 2], [u32; 2])>,
    /// At least one: a scene without lights holds one LIGHT_NONE.
    pub lights: Vec<GpuLight>,
    /// The emissive triangles and their distribution.
    pub emitters: FlatEmitters,
    pub meshes: Vec<MeshRange>,
    /// Every triangle in one run, in order.
    pub surface_runs: Vec<SurfaceRun>,
    /// What the traced shading meets on any surface (SURFACE_*).
    pub surfaces: u32,
}

/// Instance custom indices have 24 bits: the first triangle of every mesh must fit.
const MAX_TRIANGLES: usize = 1 << 24;

impl FlatScene {
    /// The arrays of `scene`, its texels in at most `texel_limit` bytes (`scene::texels`), the
    /// meshes `motion` names moving through its steps while the shutter is open.
    pub(crate) fn new(
        scene: &Scene,
        motion: Option<&ObjectMotion>,
        texel_limit: u64,
    ) -> Result<Self, GpuError> {
        let total = scene.triangle_count();
        if total > MAX_TRIANGLES {
            return Err(GpuError::Invalid(format!(
                "{total} triangles: the GPU path handles at most {MAX_TRIANGLES}"
            )));
        }
        // Indices, material ids and normals in range, positions finite.
        scene.validate().map_err(GpuError::Invalid)?;
        let mut flat = FlatScene {
            materials: scene.materials.iter().map(gpu_material).collect(),
            ..Default::default()
        };
        if flat.materials.is_empty() {
            // Shaders index a non-empty array; no triangle may refer to it (checked above).
            flat.materials.push(GpuMaterial::zeroed());
        }
        let textures = flatten_textures(&scene.textures, texel_limit)?;
        (flat.textures, flat.texels) = (textures.textures, textures.texels);
        flat.coarsened = textures.coarsened;
        if flat.textures.is_empty() {
            // Shaders index non-empty arrays; no material refers to these.
            flat.textures.push(GpuTexture::zeroed());
            flat.texels.push(0);
        }
        flat.lights = scene.lights.iter().map(gpu_light).collect();
        if flat.lights.is_empty() {
            flat.lights.push(GpuLight::zeroed());
        }
        flat.surfaces = scene
            .materials
            .iter()
            .map(traced_surface_bits)
            .fold(0, |a, b| a | b);
        let any_colours = scene.meshes.iter().any(|m| !m.colours.is_empty());
        let any_tangents = scene.meshes.iter().any(|m| !m.tangents.is_empty());
        let any_texcoords1 = scene.meshes.iter().any(|m| !m.texcoords1.is_empty());
        for (m, mesh) in scene.meshes.iter().enumerate() {
            let flag = |present: bool, bit: u32| if present { bit } else { 0 };
            let flags = flag(!mesh.normals.is_empty(), TRI_HAS_NORMALS)
                | flag(!mesh.colours.is_empty(), TRI_HAS_COLOURS)
                | flag(!mesh.tangents.is_empty(), TRI_HAS_TANGENTS);
            let base = flat.positions.len() as u32;
            flat.push_vertices(mesh, any_colours, any_tangents, any_texcoords1);
            if let Some(steps) =
                motion.and_then(|motion| motion.meshes.iter().find(|s| s.index == m))
            {
                let (positions, moving) = (&mut flat.positions, &mut flat.motion_vertices);
                motion::push_moving_mesh(positions, moving, base as usize, steps);
            }
            // Every acceleration-structure builder gets the triangles in a spatial order, each
            // side's in one range (the CPU reference numbers them so too).
            let material = |t: usize| &scene.materials[mesh.material_ids[t] as usize];
            let first_range = flat.meshes.len();
            for t in sided_order(&mesh.positions, &mesh.triangles, |t| {
                !material(t).double_sided
            }) {
                let t = t as usize;
                let single_sided = !material(t).double_sided;
                let triangle = flat.tri_info.len() as u32;
                let opaque = !material(t).is_alpha_tested();
                match flat.meshes[first_range..].last_mut() {
                    Some(range) if range.single_sided == single_sided => {
                        range.triangle_count += 1;
                        range.opaque &= opaque;
                    }
                    _ => flat.meshes.push(MeshRange {
                        first_triangle: triangle,
                        triangle_count: 1,
                        opaque,
                        single_sided,
                    }),
                }
                flat.indices
                    .extend(mesh.triangles[t].iter().map(|&i| base + i));
                let surfaces = surface_bits(material(t), flags);
                push_surface(&mut flat.surface_runs, triangle, surfaces);
                let side = if single_sided { TRI_SINGLE_SIDED } else { 0 };
                flat.tri_info.push(mesh.material_ids[t] | flags | side);
            }
        }
        if any_colours {
            // The traced shading reads the vertex colours where it reads textures.
            flat.surfaces |= SURFACE_TEXTURED;
        }
        for steps in motion.map_or(&[][..], |motion| &motion.lights) {
            let light = &mut flat.lights[steps.index];
            motion::push_moving_light(light, &mut flat.motion_vertices, steps);
        }
        for array in [
            &mut flat.colours,
            &mut flat.tangents,
            &mut flat.motion_vertices,
        ] {
            if array.is_empty() {
                // Shaders index non-empty arrays; no triangle's flags let them read this one.
                array.push([0.0; 4]);
            }
        }
        if flat.texcoords1.is_empty() {
            // Shaders index non-empty arrays; they read (0, 0) past this one's end.
            flat.texcoords1.push([0.0; 2]);
        }
        flat.emitters = FlatEmitters::new(&flat.positions, &flat.indices, &flat.tri_info, scene);
        Ok(flat)
    }

    /// Appends the vertices of `mesh`: zeros for what it lacks, colours, tangents and second
    /// texture coordinates only where some mesh has them.
    fn push_vertices(
        &mut self,
        mesh: &Mesh,
        any_colours: bool,
        any_tangents: bool,
        any_texcoords1: bool,
    ) {
        let count = mesh.positions.len();
        self.positions
            .extend(mesh.positions.iter().map(|p| p.extend(1.0).to_array()));
        extend_texcoords(&mut self.texcoords, &mesh.texcoords, count);
        if any_texcoords1 {
            extend_texcoords(&mut self.texcoords1, &mesh.texcoords1, count);
        }
        let normals: Vec<glam::Vec4> = mesh.normals.iter().map(|n| n.extend(0.0)).collect();
        extend_or_zeros(&mut self.normals, &normals, count);
        if any_colours {
            extend_or_zeros(&mut self.colours, &mesh.colours, count);
        }
        if any_tangents {
            extend_or_zeros(&mut self.tangents, &mesh.tangents, count);
        }
    }
}

/// `texcoords`, or `count` zeros where it is empty.
fn extend_texcoords(flat: &mut Vec<[f32; 2]>, texcoords: &[glam::Vec2], count: usize) {
    if texcoords.is_empty() {
        flat.extend(std::iter::repeat_n([0.0; 2], count));
    } else {
        flat.extend(texcoords.iter().map(|t| t.to_array()));
    }
}

/// `values` as vec4s, or `count` zeros where it is empty.
fn extend_or_zeros(flat: &mut Vec<[f32; 4]>, values: &[glam::Vec4], count: usize) {
    if values.is_empty() {
        flat.extend(std::iter::repeat_n([0.0; 4], count));
    } else {
        flat.extend(values.iter().map(|v| v.to_array()));
    }
}

/// What a raster fragment of `m` on a triangle with `flags` (TRI_HAS_*) looks up (SURFACE_*):
/// the G-buffer's albedo samples only the diffuse texture, and the vertex colours; a
/// single-sided surface's draws cull back faces.
fn surface_bits(m: &Material, flags: u32) -> u32 {
    let textured = if m.diffuse_texture.is_some() || flags & TRI_HAS_COLOURS != 0 {
        SURFACE_TEXTURED
    } else {
        0
    };
    let alpha_tested = if m.is_alpha_tested() {
        SURFACE_ALPHA_TESTED
    } else {
        0
    };
    let single_sided = if m.double_sided {
        0
    } else {
        SURFACE_SINGLE_SIDED
    };
    textured | alpha_tested | single_sided
}

/// What the traced shading of a hit on `m` looks up (SURFACE_*): it samples the emission,
/// metallic-roughness and occlusion textures too.
fn traced_surface_bits(m: &Material) -> u32 {
    let textured = if m.is_textured() { SURFACE_TEXTURED } else { 0 };
    surface_bits(m, 0) | textured
}

/// Appends triangle `triangle` with `surfaces` to the runs (the last one when it has them).
fn push_surface(runs: &mut Vec<SurfaceRun>, triangle: u32, surfaces: u32) {
    match runs.last_mut() {
        Some(run) if run.surfaces == surfaces => run.triangle_count += 1,
        _ => runs.push(SurfaceRun {
            first_triangle: triangle,
            triangle_count: 1,
            surfaces,
        }),
    }
}

/// A material as the shaders read it.
fn gpu_material(m: &Material) -> GpuMaterial {
    let (alpha_mode, cutoff) = match m.alpha_mode {
        AlphaMode::Opaque => (ALPHA_OPAQUE, 0.0),
        AlphaMode::Mask { cutoff } => (ALPHA_MASK, cutoff),
        AlphaMode::Blend => (ALPHA_BLEND, 0.0),
    };
    GpuMaterial {
        diffuse: m.diffuse.extend(m.alpha).to_array(),
        emission: m.emission.extend(cutoff).to_array(),
        diffuse_texture: gpu_texture_ref(m.diffuse_texture.as_ref()),
        emission_texture: gpu_texture_ref(m.emission_texture.as_ref()),
        alpha_texture: gpu_texture_ref(m.alpha_texture.as_ref()),
        alpha_mode,
        metallic: m.metallic,
        roughness: m.roughness,
        specular: m.specular,
        metallic_roughness_texture: gpu_texture_ref(m.metallic_roughness_texture.as_ref()),
        occlusion_texture: gpu_texture_ref(m.occlusion_texture.as_ref()),
        occlusion_strength: m.occlusion_strength,
        normal_scale: m.normal_scale,
        pad0: 0,
        pad1: 0,
        normal_texture: gpu_texture_ref(m.normal_texture.as_ref()),
        clearcoat: m.clearcoat,
        clearcoat_roughness: m.clearcoat_roughness,
        clearcoat_normal_scale: m.clearcoat_normal_scale,
        pad3: 0,
        clearcoat_texture: gpu_texture_ref(m.clearcoat_texture.as_ref()),
        clearcoat_roughness_texture: gpu_texture_ref(m.clearcoat_roughness_texture.as_ref()),
        sheen_colour: m.sheen_colour.extend(m.sheen_roughness).to_array(),
        sheen_colour_texture: gpu_texture_ref(m.sheen_colour_texture.as_ref()),
        sheen_roughness_texture: gpu_texture_ref(m.sheen_roughness_texture.as_ref()),
        attenuation: m.attenuation.extend(0.0).to_array(),
        transmission: m.transmission,
        ior: m.ior,
        thin: u32::from(m.thin),
        pad4: 0,
        transmission_texture: gpu_texture_ref(m.transmission_texture.as_ref()),
        clearcoat_normal_texture: gpu_texture_ref(m.clearcoat_normal_texture.as_ref()),
    }
}

fn gpu_texture_ref(texture_ref: Option<&TextureRef>) -> GpuTextureRef {
    let Some(r) = texture_ref else {
        return GpuTextureRef {
            texture: TEXTURE_NONE,
            ..GpuTextureRef::zeroed()
        };
    };
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => WRAP_REPEAT,
        Wrap::ClampToEdge => WRAP_CLAMP_TO_EDGE,
        Wrap::MirroredRepeat => WRAP_MIRRORED_REPEAT,
    };
    let (m, t) = (r.uv_from_texcoord.matrix2, r.uv_from_texcoord.translation);
    GpuTextureRef {
        transform_u: [m.x_axis.x, m.y_axis.x, t.x, 0.0],
        transform_v: [m.x_axis.y, m.y_axis.y, t.y, 0.0],
        texture: r.texture,
        wrap_u: wrap(r.wrap[0]),
        wrap_v: wrap(r.wrap[1]),
        texcoord_set: r.texcoord_set,
    }
}

/// The trace pass's parameters of `shot`.
pub(crate) fn trace_params(shot: &Shot) -> TraceParams {
    let (camera, settings) = (&shot.camera, &shot.render);
    TraceParams {
        camera: gpu_camera(camera),
        background: settings.background.extend(0.0).to_array(),
        environment: settings.environment.extend(0.0).to_array(),
        width: camera.width,
        height: camera.height,
        seed: settings.seed,
        shading: match settings.shading {
            Shading::Lit => SHADING_LIT,
            _ => SHADING_UNLIT,
        },
        sampler_kind: settings.sampler.id(),
        shared_samples: u32::from(settings.shared_samples),
        bounces: settings.bounces,
        // `TracePass::record_params` makes it ENVIRONMENT_MAP_NONE where the scene has no map.
        environment_map: if settings.environment_seen {
            ENVIRONMENT_MAP_SEEN
        } else {
            ENVIRONMENT_MAP_LIGHTS
        },
        footprint: gpu_footprint(&camera.footprint()),
    }
}

fn gpu_light(light: &Light) -> GpuLight {
    let (kind, cos_inner, cos_outer) = match light.kind {
        LightKind::Point => (LIGHT_POINT, 1.0, 1.0),
        LightKind::Spot {
            cos_inner,
            cos_outer,
        } => (LIGHT_SPOT, cos_inner, cos_outer),
        LightKind::Directional => (LIGHT_DIRECTIONAL, 1.0, 1.0),
    };
    GpuLight {
        position: light.position.extend(1.0).to_array(),
        direction: light.direction.extend(0.0).to_array(),
        intensity: light.intensity.extend(0.0).to_array(),
        kind,
        range: light.range,
        cos_inner,
        cos_outer,
    }
}

fn gpu_footprint(f: &Footprint) -> GpuFootprint {
    GpuFootprint {
        eye: f
            .eye
            .extend(if f.orthographic { 1.0 } else { 0.0 })
            .to_array(),
        forward: f.forward.extend(0.0).to_array(),
        pixel_dx: f.pixel_dx.extend(0.0).to_array(),
        pixel_dy: f.pixel_dy.extend(0.0).to_array(),
    }
}

/// The circle of confusion's lens data of `camera` (`CocLens`) as the shaders read it.
pub(crate) fn gpu_coc_lens(camera: &Camera) -> GpuCocLens {
    let coc = CocLens::of(camera);
    GpuCocLens {
        projection: projection_code(camera),
        focus_distance: coc.focus_distance,
        scale: coc.scale,
        tilt_origin: coc.tilt_origin,
        tilt_dx: coc.tilt_dx,
        tilt_dy: coc.tilt_dy,
    }
}

/// View `view` (VIEW_*) of `camera`.
pub(crate) fn view_params(camera: &Camera, view: u32) -> ViewParams {
    ViewParams {
        view,
        far_z: camera.far,
        coc: gpu_coc_lens(camera),
    }
}

/// View `view` (VIEW_*) of `camera`, over the camera's image; the final view shown as
/// `display` says.
pub(crate) fn resolve_push(camera: &Camera, view: u32, display: &Display) -> ResolvePush {
    ResolvePush {
        width: camera.width,
        height: camera.height,
        exposure: display.exposure,
        tonemap: display.tonemap.code(),
        shown: view_params(camera, view),
        flare: 0,
    }
}

pub(crate) fn raster_push(camera: &Camera) -> RasterPush {
    let clip: Mat4 = camera.clip_from_world();
    let ortho = if camera.is_orthographic() { 1.0 } else { 0.0 };
    RasterPush {
        clip_from_world: clip.to_cols_array(),
        eye: camera.frame.eye.extend(1.0).to_array(),
        forward: camera.frame.forward.extend(ortho).to_array(),
    }
}

#[cfg(test)]
mod tests {

    use glam::{Vec2, Vec3};
    use lensray_core::camera::{CameraParams, LensParams, ProjectionParams};
    use lensray_core::sampler::CameraSample;

    /// The raster pass uses `clip_from_world()` as is: Vulkan's clip space has y down and depth
    /// in [0, 1]. A point on the pinhole ray through raster point (x, y) must land at
    /// NDC (2x/w - 1, 2y/h - 1), with depth 0 on the near plane and 1 on the far plane.
    #[test]
    fn clip_from_world_is_vulkan_clip_space() {
        for projection in [
            ProjectionParams::Perspective { vfov_degrees: 50.0 },
            ProjectionParams::Orthographic { height: 3.0 },
        ] {
            let cam = CameraParams {
                eye: Vec3::new(1.0, 2.0, 3.0),
                target: Vec3::new(-0.5, 0.2, -1.0),
                up: Vec3::Y,
                projection,
                lens: LensParams::Pinhole,
                near: 0.5,
                far: 20.0,
                width: 160,
                height: 90,
                movements: lensray_core::camera::Movements::NONE,
            }
            .build()
            .unwrap();
            let clip = cam.clip_from_world();
            for raster in [
                Vec2::new(0.5, 0.5),
                Vec2::new(159.5, 10.25),
                Vec2::new(80.0, 89.0),
            ] {
                let ray = cam.first_order_ray(CameraSample::new(raster, Vec2::splat(0.5)));
                for depth in [cam.near, 2.0, cam.far] {
                    // The point of the ray at view depth `depth`.
                    let t =
                        (depth - cam.view_depth(ray.origin)) / ray.direction.dot(cam.frame.forward);
                    let p = ray.at(t);
                    let h = clip * p.extend(1.0);
                    let ndc = h.truncate() / h.w;
                    let expected_x = 2.0 * raster.x / 160.0 - 1.0;
                    let expected_y = 2.0 * raster.y / 90.0 - 1.0;
                    // The course's depth in [0, 1]: (z - n) / (f - n) orthographic,
                    // f (z - n) / (z (f - n)) perspective.
                    let (n, f) = (cam.near, cam.far);
                    let expected_z = if cam.is_orthographic() {
                        (depth - n) / (f - n)
                    } else {
                        f * (depth - n) / (depth * (f - n))
                    };
                    assert!(
                        (ndc.x - expected_x).abs() < 1e-4,
                        "{projection:?} x {ndc} {raster}"
                    );
                    assert!(
                        (ndc.y - expected_y).abs() < 1e-4,
                        "{projection:?} y {ndc} {raster}"
                    );
                    assert!(
                        (ndc.z - expected_z).abs() < 1e-4,
                        "{projection:?} z {ndc} at {depth}"
                    );
                    assert!(h.w > 0.0);
                }
            }
        }
    }
}
