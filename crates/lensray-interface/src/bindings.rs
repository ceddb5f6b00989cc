//! Descriptor bindings, declared once. A *group* is a named list of bindings that travel
//! together (the scene's arrays, the trace pass's buffers, a real lens); a *set* is the one
//! descriptor set of a pipeline: its stages, its push constants and the groups it holds. From
//! these declarations come
//! - each binding's number: its place in the list of every group (`binding_groups!`'s order), the
//!   same in every set that holds the group, so a group is bound the same way everywhere;
//! - the set layouts (`SetDecl::bindings`), which lensray-vulkan turns into Vulkan's;
//! - a typed value per group (`SceneGroup<R>`: a field per binding, of its resource's type), which
//!   lensray-vulkan binds whole, so that no binding can be missed or given the wrong resource;
//! - the GLSL that declares each set's bindings (`set_glsl`), which build.rs writes to
//!   `set_<name>.glsl` and the set's shaders include; it also defines `GROUP_<NAME>` for each
//!   group, which shared includes test (e.g. `camera.glsl`'s aperture-image code).
//!
//! Adding a binding to a pass: one line in its group here, its use in the shader, and a field in
//! the value the pass binds (the compiler asks for it).

use std::fmt::Write as _;

/// What a binding holds, and how GLSL declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DescriptorKind {
    /// `layout(std430, ...) <glsl>;` (a `buffer` block).
    StorageBuffer,
    /// `layout(std140, ...) <glsl>;` (a `uniform` block).
    UniformBuffer,
    /// `layout(..., <format>) <glsl>;` (an `image2D`), in GENERAL layout.
    StorageImage { format: &'static str },
    /// `layout(...) <glsl>;` (an `accelerationStructureEXT`).
    AccelerationStructure,
}

/// One binding of a group: the field's name, what it holds, and the GLSL that follows its
/// `layout(...)` (qualifiers, block or type, and the name the shaders use).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BindingDecl {
    pub name: &'static str,
    pub kind: DescriptorKind,
    pub glsl: &'static str,
}

/// A group of bindings, as `binding_groups!` declares it.
#[derive(Debug, PartialEq, Eq)]
pub struct GroupDecl {
    pub name: &'static str,
    /// The `GROUP_*` macro the set headers define.
    pub macro_name: &'static str,
    pub bindings: &'static [BindingDecl],
}

impl GroupDecl {
    /// The number of the group's first binding: the bindings of every group declared before it.
    pub fn first_binding(&self) -> u32 {
        let mut first = 0;
        for group in GROUPS {
            if group.name == self.name {
                return first;
            }
            first += group.bindings.len() as u32;
        }
        panic!("group {} is not in GROUPS", self.name)
    }
}

/// The stages that read a set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stages {
    Compute,
    /// The vertex and fragment stages of a raster pass.
    Raster,
    /// The stages of a ray-tracing pipeline: ray generation, closest hit, any hit and miss.
    RayTracing,
}

/// A pipeline's descriptor set, as `descriptor_sets!` declares it.
#[derive(Debug, PartialEq, Eq)]
pub struct SetDecl {
    /// Its GLSL header is `set_<name>.glsl`.
    pub name: &'static str,
    pub stages: Stages,
    /// Bytes of the pipeline's push constants (0: none).
    pub push_bytes: u32,
    pub groups: &'static [&'static GroupDecl],
}

/// One binding of a set: its number and what it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SetBinding {
    pub binding: u32,
    pub decl: BindingDecl,
}

impl SetDecl {
    /// Every binding of the set, group after group.
    pub fn bindings(&self) -> Vec<SetBinding> {
        self.groups
            .iter()
            .flat_map(|group| {
                let first = group.first_binding();
                group
                    .bindings
                    .iter()
                    .enumerate()
                    .map(move |(i, decl)| SetBinding {
                        binding: first + i as u32,
                        decl: *decl,
                    })
            })
            .collect()
    }

    /// Whether the set holds `group`.
    pub fn holds(&self, group: &GroupDecl) -> bool {
        self.groups.iter().any(|g| g.name == group.name)
    }
}

/// The resource types a host binds, by kind (lensray-vulkan: its buffers, image views and
/// acceleration structures).
pub trait Resources {
    type BufferResource;
    type ImageResource;
    type AccelResource;
}

/// No resources: the groups' declarations, without values.
pub enum NoResources {}

impl Resources for NoResources {
    type BufferResource = ();
    type ImageResource = ();
    type AccelResource = ();
}

/// One resource of a group's value, in the order of its declaration.
pub enum Resource<'r, R: Resources> {
    Buffer(&'r R::BufferResource),
    Image(&'r R::ImageResource),
    Accel(&'r R::AccelResource),
}

/// A group's value: a resource per binding.
pub trait BindingGroup<R: Resources> {
    const DECL: &'static GroupDecl;
    /// The resources, in the order of `DECL.bindings`.
    fn resources(&self) -> Vec<Resource<'_, R>>;
}

/// A pipeline's descriptor set.
pub trait DescriptorSet {
    const DECL: &'static SetDecl;
}

/// The field type of a binding of kind `$kind` in a group over resources `$r`.
macro_rules! binding_type {
    (storage_buffer, $r:ident) => {
        $r::BufferResource
    };
    (uniform_buffer, $r:ident) => {
        $r::BufferResource
    };
    (storage_image, $r:ident) => {
        $r::ImageResource
    };
    (acceleration_structure, $r:ident) => {
        $r::AccelResource
    };
}

macro_rules! binding_kind {
    (storage_buffer) => {
        DescriptorKind::StorageBuffer
    };
    (uniform_buffer) => {
        DescriptorKind::UniformBuffer
    };
    (storage_image, $format:literal) => {
        DescriptorKind::StorageImage { format: $format }
    };
    (acceleration_structure) => {
        DescriptorKind::AccelerationStructure
    };
}

macro_rules! binding_resource {
    (storage_buffer, $value:expr) => {
        Resource::Buffer($value)
    };
    (uniform_buffer, $value:expr) => {
        Resource::Buffer($value)
    };
    (storage_image, $value:expr) => {
        Resource::Image($value)
    };
    (acceleration_structure, $value:expr) => {
        Resource::Accel($value)
    };
}

/// Declares every group of bindings, in binding-number order: a struct per group (a field per
/// binding) and `GROUPS`. A binding is `name: kind(args) = "glsl"`, kind one of
/// `storage_buffer()`, `uniform_buffer()`, `storage_image("format")`, `acceleration_structure()`.
macro_rules! binding_groups {
    (
        $(
            $(#[doc = $gdoc:literal])*
            $group:ident ($macro_name:literal) {
                $( $(#[doc = $bdoc:literal])* $field:ident : $kind:ident ( $($arg:literal)? ) = $glsl:literal ),* $(,)?
            }
        )*
    ) => {
        $(
            $(#[doc = $gdoc])*
            pub struct $group<R: Resources> {
                $( $(#[doc = $bdoc])* pub $field: binding_type!($kind, R), )*
            }

            impl<R: Resources> BindingGroup<R> for $group<R> {
                const DECL: &'static GroupDecl = &GroupDecl {
                    name: stringify!($group),
                    macro_name: $macro_name,
                    bindings: &[$(
                        BindingDecl {
                            name: stringify!($field),
                            kind: binding_kind!($kind $(, $arg)?),
                            glsl: $glsl,
                        }
                    ),*],
                };
                fn resources(&self) -> Vec<Resource<'_, R>> {
                    vec![$( binding_resource!($kind, &self.$field) ),*]
                }
            }
        )*

        /// Every group, in declaration order: the binding numbers follow it.
        pub const GROUPS: &[&GroupDecl] = &[$( <$group<NoResources> as BindingGroup<NoResources>>::DECL ),*];
    };
}

/// Declares the pipelines' sets: `Name("file name", Stages, PushType) { Group, ... }`.
macro_rules! descriptor_sets {
    (
        $(
            $(#[doc = $sdoc:literal])*
            $set:ident ($name:literal, $stages:ident, $push:ty) { $($group:ident),* $(,)? }
        )*
    ) => {
        $(
            $(#[doc = $sdoc])*
            pub struct $set;

            impl DescriptorSet for $set {
                const DECL: &'static SetDecl = &SetDecl {
                    name: $name,
                    stages: Stages::$stages,
                    push_bytes: std::mem::size_of::<$push>() as u32,
                    groups: &[$( <$group<NoResources> as BindingGroup<NoResources>>::DECL ),*],
                };
            }
        )*

        /// Every set: build.rs writes a GLSL header for each.
        pub const SETS: &[&SetDecl] = &[$( <$set as DescriptorSet>::DECL ),*];
    };
}

/// The GLSL header of `set`: the interface, a `GROUP_*` macro per group, and the declaration of
/// every binding.
pub fn set_glsl(set: &SetDecl) -> String {
    let guard = format!("LENSRAY_SET_{}_GLSL", set.name.to_uppercase());
    let mut out = format!(
        "// Generated by lensray-vulkan's build.rs from lensray-interface's bindings.rs: the\n\
         // descriptor set `{}`. Edit the declaration there, not this file.\n\
         #ifndef {guard}\n#define {guard}\n\n#include \"interface.glsl\"\n\n",
        set.name
    );
    for group in set.groups {
        let _ = writeln!(out, "#define {}", group.macro_name);
    }
    out.push('\n');
    for b in set.bindings() {
        let layout = match b.decl.kind {
            DescriptorKind::StorageBuffer => format!("std430, set = 0, binding = {}", b.binding),
            DescriptorKind::UniformBuffer => format!("std140, set = 0, binding = {}", b.binding),
            DescriptorKind::StorageImage { format } => {
                format!("set = 0, binding = {}, {format}", b.binding)
            }
            DescriptorKind::AccelerationStructure => format!("set = 0, binding = {}", b.binding),
        };
        let _ = writeln!(out, "layout({layout}) {};", b.decl.glsl);
    }
    out.push_str("\n#endif\n");
    out
}

binding_groups! {
    /// The scene's arrays (shaders/include/scene.glsl, texture.glsl, lights.glsl), flattened by
    /// lensray-vulkan's upload/.
    SceneGroup("GROUP_SCENE") {
        positions: storage_buffer() = "readonly buffer Positions { vec4 positions[]; }",
        normals: storage_buffer() = "readonly buffer Normals { vec4 normals[]; }",
        indices: storage_buffer() = "readonly buffer Indices { uint indices[]; }",
        tri_info: storage_buffer() = "readonly buffer TriInfo { uint tri_info[]; }",
        materials: storage_buffer() = "readonly buffer Materials { Material materials[]; }",
        /// Per vertex its texture coordinates (TEXCOORD_0).
        texcoords: storage_buffer() = "readonly buffer Texcoords { vec2 texcoords[]; }",
        /// Per vertex its second texture coordinates (TEXCOORD_1) when some mesh has them
        /// (zeros for the others); one element, zero, when no mesh has any: a vertex past the
        /// end reads (0, 0) (texture.glsl's vertex_texcoords).
        texcoords1: storage_buffer() = "readonly buffer Texcoords1 { vec2 texcoords1[]; }",
        /// Per vertex its colour (RGBA) where its triangles have TRI_HAS_COLOURS; one element
        /// when no mesh has colours.
        colours: storage_buffer() = "readonly buffer Colours { vec4 colours[]; }",
        /// Per vertex its tangent (xyz; w: the bitangent's sign) where its triangles have
        /// TRI_HAS_TANGENTS; one element when no mesh has tangents.
        tangents: storage_buffer() = "readonly buffer Tangents { vec4 tangents[]; }",
        textures: storage_buffer() = "readonly buffer Textures { Texture textures[]; }",
        /// Every texture's texels, RGBA8 in a uint, every mip level.
        texels: storage_buffer() = "readonly buffer Texels { uint texels[]; }",
        /// The scene's lights; a scene without lights holds one LIGHT_NONE.
        lights: storage_buffer() = "readonly buffer Lights { Light lights[]; }",
        /// The emissive triangles (shaders/include/emitters.glsl, lensray-core's
        /// scene/emitters.rs); a scene without emitters holds one, of cdf 0.
        emitter_triangles: storage_buffer() = "readonly buffer EmitterTriangles { uint emitter_triangles[]; }",
        /// Per emissive triangle the share of the power up to it; the last is 1.
        emitter_cdf: storage_buffer() = "readonly buffer EmitterCdf { float emitter_cdf[]; }",
        /// Per triangle the density per unit area of an emitter draw's point on it (0 where it
        /// does not emit); one 0 when no triangle emits.
        emitter_area_pdf: storage_buffer() = "readonly buffer EmitterAreaPdf { float emitter_area_pdf[]; }",
        /// The vertices that move while the shutter is open, MOTION_STEPS of each attribute a
        /// vertex: moving row r's positions from 3 r MOTION_STEPS, then its normals, then its
        /// tangents (scene.glsl's vertex_position); one zero when nothing moves.
        motion_vertices: storage_buffer() = "readonly buffer MotionVertices { vec4 motion_vertices[]; }",
    }
    /// The software traversal's BVH (shaders/include/hit_software.glsl, lensray-vulkan's
    /// scene/bvh.rs): its nodes, and its triangles in leaf order.
    BvhGroup("GROUP_BVH") {
        bvh_nodes: storage_buffer() = "readonly buffer BvhNodes { BvhNode bvh_nodes[]; }",
        bvh_triangles: storage_buffer() = "readonly buffer BvhTriangles { BvhTriangle bvh_triangles[]; }",
    }
    /// The scene's top-level acceleration structure (shaders/include/hit_rayquery.glsl).
    TlasGroup("GROUP_TLAS") {
        tlas: acceleration_structure() = "uniform accelerationStructureEXT tlas",
    }
    /// The trace pass's parameters and ray counter (shaders/passes/trace.comp).
    TraceGroup("GROUP_TRACE") {
        params: uniform_buffer() = "uniform ParamsBlock { TraceParams params; }",
        /// 64-bit counts as pairs of words (low, high): words 0-1 the rays traced (a 4K render
        /// at 256 spp passes 2^32), 2-3 those of a pipeline's first dispatch, 4-5 the hybrid's
        /// lit pre-pass's.
        counters: storage_buffer() = "buffer Counters { uint rays_traced; uint rays_traced_high; }",
    }
    /// The band of sums the trace pass adds to (xyz: sum, w: samples), a band of rows of the
    /// image.
    AccumulationGroup("GROUP_ACCUMULATION") {
        accum: storage_buffer() = "buffer Accum { vec4 accum[]; }",
    }
    /// What the hybrid path's plan gives the trace pass (docs/hybrid.md).
    HybridTraceGroup("GROUP_HYBRID_TRACE") {
        /// One vec4 per pixel of the whole image: xyz the shortcut value, w the samples to
        /// trace (w >= 1: samples i < w are traced, later ones skipped) or HYBRID_SHORTCUT (the
        /// pixel takes the shortcut value, checked by tracing with probability 1 /
        /// HYBRID_CHECK_INVERSE). hybrid_plan.comp writes it.
        plan: storage_buffer() = "buffer Plan { vec4 plan[]; }",
        /// Lit: one float per pixel of the whole image, the camera-space depth of the surface
        /// the G-buffer sees at the pixel centre (0: none), written by the plan; the lit
        /// shortcut samples reproject through it.
        surface_depth: storage_buffer() = "readonly buffer SurfaceDepth { float surface_depth[]; }",
    }
    /// What the raster path's visibility pass gives the trace pass (docs/raster.md): one uint
    /// per pixel of the whole image, what the raster pass of the current sample sees there: the
    /// global triangle index + 1, or 0 (nothing).
    RasterTraceGroup("GROUP_RASTER_TRACE") {
        visibility: storage_buffer() = "readonly buffer Visibility { uint visibility[]; }",
    }
    /// An aperture image's tables (lensray-core's camera/aperture/image.rs,
    /// `ApertureImage::table`: the marginal cumulative distribution over rows, then each row's
    /// over its columns); a placeholder when the aperture is no image.
    ApertureGroup("GROUP_APERTURE") {
        aperture_table: storage_buffer() = "readonly buffer ApertureTable { float aperture_table[]; }",
    }
    /// A real lens (shaders/include/real_lens.glsl).
    LensGroup("GROUP_LENS") {
        lens: storage_buffer() = "readonly buffer LensBlock { Lens lens; }",
    }
    /// The hybrid plan's inputs and outputs (shaders/passes/hybrid_plan.comp): the G-buffer
    /// images, the per-tile CoC maxima (then the dilated ones), the summed-area table of edge
    /// marks ((width + 1) x (height + 1) uints), the plan and the surface depths.
    HybridPlanGroup("GROUP_HYBRID_PLAN") {
        g_normal: storage_image("rgba32f") = "readonly uniform image2D g_normal",
        g_albedo: storage_image("rgba32f") = "readonly uniform image2D g_albedo",
        g_depth: storage_image("r32f") = "readonly uniform image2D g_depth",
        tiles: storage_buffer() = "buffer Tiles { float tile_max[]; }",
        edges: storage_buffer() = "buffer Edges { uint table[]; }",
        /// The trace pass's `plan`. Lit, the pre-pass (trace.comp's TRACE_MODE_SHORTCUT) leaves
        /// each pixel's shortcut value in xyz and its shadow state in w; ENTRIES writes the
        /// entries over them (keeping xyz).
        plan: storage_buffer() = "buffer Plan { vec4 plan[]; }",
        /// The trace pass's `surface_depth`, written by the entries step.
        surface_depth: storage_buffer() = "writeonly buffer SurfaceDepth { float surface_depth[]; }",
    }
    /// The preview's resolve pass (shaders/present/resolve.comp).
    ResolveGroup("GROUP_RESOLVE") {
        accum: storage_buffer() = "readonly buffer Accum { vec4 accum[]; }",
        g_normal: storage_image("rgba32f") = "readonly uniform image2D g_normal",
        g_albedo: storage_image("rgba32f") = "readonly uniform image2D g_albedo",
        g_depth: storage_image("r32f") = "readonly uniform image2D g_depth",
        display: storage_image("rgba8") = "writeonly uniform image2D display",
        /// The lens's own light per pixel (`--flare`, `--starburst`), linear, added to the
        /// final view when the push constants say so.
        flare: storage_buffer() = "readonly buffer FlareLight { vec4 flare[]; }",
    }
    /// A real lens's ghosts (shaders/passes/ghosts.comp): the paths (i, j, 1 for a ghost, 0
    /// for the direct path), per wavelength (nm, its dispersion offset, the fixed-point scale
    /// of its ghosts' film plane and of its direct one), per surface its coating (1 if
    /// layered, the layer's index and thickness in nm), the traced rays (GHOST_VERTEX_VEC4S
    /// each: the film point in bins, the share carried, the rims' reach; the stop's crossings;
    /// the third crossing, their count, 1 if traced), and the film: per wavelength a ghosts'
    /// plane and a direct plane of fixed-point sums. The camera gives the aperture's shape.
    GhostGroup("GROUP_GHOSTS") {
        ghost_paths: storage_buffer() = "readonly buffer GhostPaths { uvec4 ghost_paths[]; }",
        ghost_wavelengths: storage_buffer() = "readonly buffer GhostWavelengths { vec4 ghost_wavelengths[]; }",
        ghost_coatings: storage_buffer() = "readonly buffer GhostCoatings { vec4 ghost_coatings[]; }",
        ghost_vertices: storage_buffer() = "buffer GhostVertices { vec4 ghost_vertices[]; }",
        ghost_film: storage_buffer() = "buffer GhostFilm { uint ghost_film[]; }",
        camera: uniform_buffer() = "uniform CameraBlock { Camera cam; }",
    }
    /// The mirror probes' queries and answers (shaders/probes/mirrors.comp).
    MirrorProbeGroup("GROUP_MIRROR_PROBE") {
        queries: storage_buffer() = "readonly buffer Queries { ProbeQuery queries[]; }",
        results: storage_buffer() = "writeonly buffer Results { ProbeResult results[]; }",
        camera: uniform_buffer() = "uniform CameraBlock { Camera cam; }",
    }
    /// The sampler-cost probe's sums (shaders/probes/sampler_cost.comp).
    SamplerCostGroup("GROUP_SAMPLER_COST") {
        sums: storage_buffer() = "writeonly buffer Sums { vec4 sums[]; }",
    }
    /// An environment map (shaders/include/environment.glsl): its parameters, its texels (rgb,
    /// row-major from the top row) and its sampling tables (`EnvironmentSampler`): per row the
    /// cumulative weights of its texels (width + 1 a row, from 0), and the rows' (height + 1).
    EnvironmentGroup("GROUP_ENVIRONMENT") {
        environment: storage_buffer() = "readonly buffer EnvironmentBlock { Environment environment; }",
        env_texels: storage_buffer() = "readonly buffer EnvironmentTexels { vec4 env_texels[]; }",
        env_row_cdfs: storage_buffer() = "readonly buffer EnvironmentRowCdfs { float env_row_cdfs[]; }",
        env_rows_cdf: storage_buffer() = "readonly buffer EnvironmentRowsCdf { float env_rows_cdf[]; }",
    }
    /// The environment probe's queries (two vec4s each: the point to sample by, the direction
    /// to look up) and answers (shaders/probes/environment.comp).
    EnvironmentProbeGroup("GROUP_ENVIRONMENT_PROBE") {
        env_queries: storage_buffer() = "readonly buffer EnvironmentQueries { vec4 env_queries[]; }",
        /// Per query ENVIRONMENT_PROBE_RESULT_FLOATS floats: the sample's direction, pdf,
        /// radiance and texel index (column + row * width; -1: no sample), then the looked-up
        /// direction's pdf, radiance and (u, v), two unused.
        env_results: storage_buffer() = "writeonly buffer EnvironmentResults { float env_results[]; }",
    }
    /// The spectral probe's queries and answers (shaders/probes/spectral.comp).
    SpectralProbeGroup("GROUP_SPECTRAL_PROBE") {
        queries: storage_buffer() = "readonly buffer Queries { vec2 queries[]; }",
        /// Per query SPECTRAL_PROBE_RESULT_FLOATS floats: sample_wavelength(u), the interval as
        /// a float, rgb_weights(that wavelength) column by column, rgb_weights(the given
        /// wavelength), unused.
        results: storage_buffer() = "writeonly buffer Results { float results[]; }",
    }
    /// The tone-map probe's colours and answers (shaders/probes/tonemap.comp).
    TonemapProbeGroup("GROUP_TONEMAP_PROBE") {
        /// Linear colours (w unused).
        queries: storage_buffer() = "readonly buffer Queries { vec4 queries[]; }",
        /// Per query: pbr_neutral, then agx, of its colour (w unused).
        results: storage_buffer() = "writeonly buffer Results { vec4 results[]; }",
    }
}

descriptor_sets! {
    /// trace.comp with ray queries.
    TraceRayQuerySet("trace_rayquery", Compute, crate::TracePush) {
        SceneGroup, TlasGroup, TraceGroup, AccumulationGroup, HybridTraceGroup, RasterTraceGroup,
        ApertureGroup, LensGroup, EnvironmentGroup,
    }
    /// trace.comp with the software traversal.
    TraceSoftwareSet("trace_software", Compute, crate::TracePush) {
        SceneGroup, BvhGroup, TraceGroup, AccumulationGroup, HybridTraceGroup, RasterTraceGroup,
        ApertureGroup, LensGroup, EnvironmentGroup,
    }
    /// trace.comp as the ray generation of a ray-tracing pipeline, with its hit and miss
    /// shaders (rt_hit.rchit, rt_hit.rahit, rt_miss.rmiss).
    TraceRtPipelineSet("trace_rtpipeline", RayTracing, crate::TracePush) {
        SceneGroup, TlasGroup, TraceGroup, AccumulationGroup, HybridTraceGroup, RasterTraceGroup,
        ApertureGroup, LensGroup, EnvironmentGroup,
    }
    /// The G-buffer pass (gbuffer.vert, gbuffer.frag).
    GBufferSet("gbuffer", Raster, crate::RasterPush) { SceneGroup }
    /// The raster path's visibility pass (visibility.vert, visibility.frag).
    VisibilitySet("visibility", Raster, crate::VisibilityPush) { SceneGroup }
    /// The preview's view pass (gbuffer.vert, view.frag).
    ViewSet("view", Raster, crate::ViewPush) { SceneGroup }
    /// The hybrid plan (hybrid_plan.comp).
    HybridPlanSet("hybrid_plan", Compute, crate::HybridPlanPush) { HybridPlanGroup }
    /// The preview's resolve pass (resolve.comp).
    ResolveSet("resolve", Compute, crate::ResolvePush) { ResolveGroup }
    /// A real lens's ghosts (ghosts.comp).
    GhostSet("ghosts", Compute, crate::GhostPush) { GhostGroup, ApertureGroup, LensGroup }
    /// The GLSL mirror probes (mirrors.comp).
    MirrorProbeSet("mirror_probe", Compute, u32) { MirrorProbeGroup, ApertureGroup, LensGroup }
    /// The sampler-cost probe (sampler_cost.comp).
    SamplerCostSet("sampler_cost", Compute, crate::SamplerCostPush) { SamplerCostGroup }
    /// The spectral probe (spectral.comp).
    SpectralProbeSet("spectral_probe", Compute, u32) { SpectralProbeGroup }
    /// The environment probe (environment.comp).
    EnvironmentProbeSet("environment_probe", Compute, u32) { EnvironmentGroup, EnvironmentProbeGroup }
    /// The tone-map probe (tonemap.comp).
    TonemapProbeSet("tonemap_probe", Compute, u32) { TonemapProbeGroup }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_group_has_the_same_numbers_in_every_set() {
        // The G-buffer's set is the scene group alone: the trace sets start with it.
        let gbuffer = GBufferSet::DECL.bindings();
        let scene: Vec<SetBinding> = TraceRayQuerySet::DECL.bindings()[..gbuffer.len()].to_vec();
        assert_eq!(scene, gbuffer);
        assert_eq!(scene.len(), 16, "the scene group's bindings");
        assert_eq!(scene[0].binding, 0);
        let trace = AccumulationGroup::<NoResources>::DECL;
        let in_rayquery = TraceRayQuerySet::DECL.bindings();
        let in_software = TraceSoftwareSet::DECL.bindings();
        let accum =
            |set: &[SetBinding]| set.iter().find(|b| b.decl.name == "accum").unwrap().binding;
        assert_eq!(accum(&in_rayquery), trace.first_binding());
        assert_eq!(accum(&in_rayquery), accum(&in_software));
    }

    #[test]
    fn numbers_are_unique_and_names_unique_within_a_set() {
        for set in SETS {
            let bindings = set.bindings();
            for (i, a) in bindings.iter().enumerate() {
                for b in &bindings[i + 1..] {
                    assert_ne!(a.binding, b.binding, "{}", set.name);
                    assert_ne!(a.decl.name, b.decl.name, "{}", set.name);
                }
            }
        }
    }

    #[test]
    fn the_header_declares_each_binding_with_its_layout() {
        let glsl = set_glsl(TraceSoftwareSet::DECL);
        assert!(glsl.contains("#define GROUP_BVH\n"), "{glsl}");
        assert!(glsl.contains("layout(std430, set = 0, binding = 0) readonly buffer Positions { vec4 positions[]; };"), "{glsl}");
        let params = TraceGroup::<NoResources>::DECL.first_binding();
        assert!(glsl.contains(&format!("layout(std140, set = 0, binding = {params}) uniform ParamsBlock {{ TraceParams params; }};")), "{glsl}");
        let resolve = set_glsl(ResolveSet::DECL);
        assert!(
            resolve.contains(", rgba8) writeonly uniform image2D display;"),
            "{resolve}"
        );
    }
}
