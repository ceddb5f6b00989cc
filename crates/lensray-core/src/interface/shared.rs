// The one definition of what the host and the shaders share: constants, binding numbers,
// workgroup sizes and the structs of uniform blocks, push constants and storage buffers.
// build.rs writes `interface.glsl` from it; the shaders include that, so a shader that names a
// constant or field that is gone here fails to build. Compiled twice (crate and build.rs):
// no crate paths, no inner attributes.

use super::glsl::*;

shader_interface! {
    constants {
        /// Shading modes traced by the compute pass (`render::Shading`).
        SHADING_UNLIT: u32 = 0;
        SHADING_LIT: u32 = 1;
        /// `Camera.projection`.
        PROJECTION_PERSPECTIVE: u32 = 0;
        PROJECTION_ORTHOGRAPHIC: u32 = 1;
        /// Bit 31 of a triangle's info word: its mesh has vertex normals. Bits 0..30: material.
        TRI_HAS_NORMALS: u32 = 0x8000_0000;
        /// Far end of camera rays on the GPU (ray queries take a finite tMax; the CPU uses
        /// infinity, which no scene within f32 range can tell apart).
        T_MAX: f32 = 1e30;
        /// Shadow rays start this far off the surface along the facing geometric normal, times
        /// (1 + the largest coordinate magnitude): float spacing grows with the coordinates.
        SHADOW_ORIGIN_OFFSET: f32 = 1e-4;
        PI: f32 = std::f32::consts::PI;
        /// Most triangles of an aperture's fan (camera::aperture): `Camera.aperture_fan` holds
        /// two vertices per vec4.
        APERTURE_MAX_FAN: u32 = 64;

        /// What the preview window shows (`preview::ViewMode`, shaders/present/resolve.comp): the
        /// thin-lens accumulation, a G-buffer AOV, or each pixel's circle of confusion.
        VIEW_FINAL: u32 = 0;
        VIEW_ALBEDO: u32 = 1;
        VIEW_NORMAL: u32 = 2;
        VIEW_DEPTH: u32 = 3;
        VIEW_COC: u32 = 4;

        /// Sample dimensions the camera takes (sampler::camera_sample); later consumers take
        /// dimensions from DIM_FIRST_FREE on.
        DIM_FILM_X: u32 = 0;
        DIM_FILM_Y: u32 = 1;
        DIM_LENS_X: u32 = 2;
        DIM_LENS_Y: u32 = 3;
        /// The environment's cosine-distributed direction (scene::light::cosine_direction).
        DIM_ENVIRONMENT_X: u32 = 4;
        DIM_ENVIRONMENT_Y: u32 = 5;
        DIM_FIRST_FREE: u32 = 6;
        /// `TraceParams.sampler_kind` (`sampler::SamplerKind`).
        SAMPLER_SOBOL: u32 = 0;
        SAMPLER_INDEPENDENT: u32 = 1;
        /// Columns of the lens pair's index map (sampler/sobol.rs, lens_index): a fixed linear
        /// remapping of the sample index's 16 low bits, found by a search for joint film x lens
        /// stratification (`cargo bench --bench sampler -- --search-lens-index`).
        LENS_INDEX_COLUMNS: [u32; 16] = [
            1, 3, 4, 13, 22, 41, 85, 194, 429, 803, 1522, 3562, 4535, 14805, 21617, 40615,
        ];

        /// Workgroups: trace.comp is TRACE_GROUP_SIZE x TRACE_GROUP_SIZE (a coherent tile).
        TRACE_GROUP_SIZE: u32 = 8;
        PROBE_GROUP_SIZE: u32 = 64;

        /// Scene arrays (shaders/include/scene.glsl), in the set the including shader names.
        SCENE_BINDING_POSITIONS: u32 = 0;
        SCENE_BINDING_NORMALS: u32 = 1;
        SCENE_BINDING_INDICES: u32 = 2;
        SCENE_BINDING_TRI_INFO: u32 = 3;
        SCENE_BINDING_MATERIALS: u32 = 4;
        /// Scene textures (shaders/include/texture.glsl), in the scene's set: per vertex its
        /// texture coordinates (vec2), the textures (`Texture`), every texture's texels (RGBA8
        /// in a uint, every mip level).
        SCENE_BINDING_TEXCOORDS: u32 = 16;
        SCENE_BINDING_TEXTURES: u32 = 17;
        SCENE_BINDING_TEXELS: u32 = 18;
        /// The scene's lights (`Light`, shaders/include/lights.glsl), in the scene's set; a
        /// scene without lights holds one LIGHT_NONE.
        SCENE_BINDING_LIGHTS: u32 = 19;
        /// `Light.kind` (`scene::LightKind`).
        LIGHT_NONE: u32 = 0;
        LIGHT_POINT: u32 = 1;
        LIGHT_SPOT: u32 = 2;
        LIGHT_DIRECTIONAL: u32 = 3;
        /// `TextureRef.wrap_u` / `wrap_v` (`scene::texture::Wrap`).
        WRAP_REPEAT: u32 = 0;
        WRAP_CLAMP_TO_EDGE: u32 = 1;
        WRAP_MIRRORED_REPEAT: u32 = 2;
        /// `TextureRef.texture` of a material slot without a texture.
        TEXTURE_NONE: u32 = 0xffff_ffff;
        /// `Material.alpha_mode` (`scene::AlphaMode`).
        ALPHA_OPAQUE: u32 = 0;
        ALPHA_MASK: u32 = 1;
        ALPHA_BLEND: u32 = 2;
        /// Salts of the keys of a sample's camera ray and shadow ray, whose hash with a triangle
        /// draws whether the ray stops at a BLEND surface (`scene::blend_threshold`).
        BLEND_CAMERA_SALT: u32 = 0x626c_6e64;
        BLEND_SHADOW_SALT: u32 = 0x7368_6477;
        /// The aperture-centre ray of the AOVs and G-buffer draws nothing: a BLEND surface
        /// stops it where its alpha exceeds this.
        AOV_BLEND_THRESHOLD: f32 = 0.5;
        /// trace.comp: after the scene arrays.
        TRACE_BINDING_TLAS: u32 = 5;
        TRACE_BINDING_ACCUM: u32 = 6;
        TRACE_BINDING_COUNTERS: u32 = 7;
        TRACE_BINDING_PARAMS: u32 = 8;
        /// trace.comp, software traversal (shaders/include/hit_software.glsl): the BVH's nodes and its
        /// triangles in leaf order.
        TRACE_BINDING_BVH_NODES: u32 = 9;
        TRACE_BINDING_BVH_TRIANGLES: u32 = 10;
        /// trace.comp, hybrid path (lensray-vulkan/src/renderer/batch.rs, docs/hybrid.md): one vec4
        /// per pixel of the whole image: xyz the shortcut value, w the samples to trace (w >= 1:
        /// samples i < w are traced, later ones skipped) or HYBRID_SHORTCUT (the pixel takes the
        /// shortcut value, checked by tracing with probability 1 / HYBRID_CHECK_INVERSE).
        TRACE_BINDING_PLAN: u32 = 11;
        /// trace.comp, raster path (docs/raster.md): one uint per pixel of
        /// the whole image, what the raster pass of the current sample sees there: the global
        /// triangle index + 1, or 0 (nothing).
        TRACE_BINDING_VISIBILITY: u32 = 12;
        /// trace.comp, hybrid path, lit: one float per pixel of the whole image, the
        /// camera-space depth of the surface the G-buffer sees at the pixel centre (0: none),
        /// written by the plan; the lit shortcut samples reproject through it.
        TRACE_BINDING_SURFACE_DEPTH: u32 = 13;
        /// trace.comp: the aperture image's tables (`ApertureImage::table`: the marginal
        /// cumulative distribution over rows, then each row's over its columns), floats; a
        /// placeholder when the aperture is no image.
        TRACE_BINDING_APERTURE: u32 = 14;
        /// trace.comp: the real lens (`Lens`, camera::real_lens; shaders/include/real_lens.glsl).
        TRACE_BINDING_LENS: u32 = 15;
        /// Most surfaces of a real lens on the GPU, and the exit pupil's bins
        /// (camera::real_lens::PUPIL_BINS).
        LENS_MAX_SURFACES: u32 = 32;
        LENS_PUPIL_BINS: u32 = 64;
        /// `TracePush.mode`: trace every sample (rayquery, software); the hybrid's traced mode
        /// (reads the plan); the hybrid's lit pre-pass, before the plan's steps: per pixel the
        /// aperture-centre ray at the pixel centre (its hit rasterized by the visibility pass
        /// through the lens centre), shaded, into the plan entry's xyz (the lit
        /// shortcut value), and whether its shadow ray was blocked into w (1 or 0: the plan's
        /// edge test sees shadow boundaries through it; its entries step overwrites w).
        TRACE_MODE_ALL: u32 = 0;
        TRACE_MODE_HYBRID: u32 = 1;
        TRACE_MODE_SHORTCUT: u32 = 2;
        /// The raster path's shading pass: one sample (sample_begin), whose visibility the
        /// raster pass drew with the matrix of that (shared) camera sample; shades the
        /// triangle it names along the sample's lens ray.
        TRACE_MODE_RASTER: u32 = 3;
        /// Plan entry w of a shortcut pixel.
        HYBRID_SHORTCUT: f32 = -1.0;
        /// A shortcut pixel's sample is traced too with probability 1 / HYBRID_CHECK_INVERSE
        /// (and weighted by HYBRID_CHECK_INVERSE), which makes the shortcut unbiased.
        HYBRID_CHECK_INVERSE: u32 = 32;
        /// Salt of that choice's hash (apart from the sampler's own uses of the sample key).
        HYBRID_CHECK_SALT: u32 = 0x68796272;
        /// The hybrid's plan (lensray-vulkan/src/probes/hybrid_plan.rs `Plan::new` on the host,
        /// the same rules in shaders/passes/hybrid_plan.comp on the device): side of the square
        /// tiles over which the circle of confusion is maximised, pixels (also the workgroup tile
        /// of hybrid_plan.comp).
        HYBRID_TILE: u32 = 8;
        /// Pixels of a row that a device runs in lockstep and that share one decision (lavapipe:
        /// one row of an 8x8 workgroup). hybrid_plan.comp takes it to be HYBRID_TILE.
        HYBRID_SEGMENT: u32 = 8;
        /// Dilated CoC radius (pixels) under which a pixel may take the shortcut with a window
        /// of its neighbours only; also half a pixel, the film samples' reach from its centre
        /// (`probes::hybrid_plan::window_radius`).
        HYBRID_SHORTCUT_COC: f32 = 0.5;
        /// How far (in tiles) a tile's CoC is spread at most: a bound on the dilation's cost.
        HYBRID_MAX_REACH_TILES: u32 = 16;
        /// hybrid_plan.comp: invocations per workgroup (each plans a tile, a row, a column or
        /// a segment).
        HYBRID_PLAN_GROUP_SIZE: u32 = 64;
        /// `HybridPlanPush.step`: the dispatches of one plan, in order. TILES: per tile its
        /// pixels' CoC maximum and edge marks; ROWS, COLUMNS: the summed-area table of the edge
        /// marks (prefix sums along rows, then columns); DILATE: per tile its dilated CoC;
        /// ENTRIES: per segment the decision of its pixels, the entries.
        HYBRID_PLAN_STEP_TILES: u32 = 0;
        HYBRID_PLAN_STEP_ROWS: u32 = 1;
        HYBRID_PLAN_STEP_COLUMNS: u32 = 2;
        HYBRID_PLAN_STEP_DILATE: u32 = 3;
        HYBRID_PLAN_STEP_ENTRIES: u32 = 4;
        /// hybrid_plan.comp's bindings: the G-buffer images, the per-tile CoC maxima (then the
        /// dilated ones), the
        /// summed-area table of edge marks ((width + 1) x (height + 1) uints), the plan (the
        /// trace pass's TRACE_BINDING_PLAN buffer).
        HYBRID_PLAN_BINDING_NORMAL: u32 = 0;
        HYBRID_PLAN_BINDING_ALBEDO: u32 = 1;
        HYBRID_PLAN_BINDING_VIEW_DEPTH: u32 = 2;
        HYBRID_PLAN_BINDING_TILES: u32 = 3;
        HYBRID_PLAN_BINDING_EDGES: u32 = 4;
        HYBRID_PLAN_BINDING_PLAN: u32 = 5;
        /// The trace pass's TRACE_BINDING_SURFACE_DEPTH, written by the entries step.
        HYBRID_PLAN_BINDING_SURFACE_DEPTH: u32 = 6;
        /// Entries of the software traversal's stack of nodes still to visit; the BVH build
        /// refuses deeper trees (lensray-vulkan/src/scene/bvh.rs).
        BVH_STACK_SIZE: u32 = 64;
        /// probe.comp.
        PROBE_BINDING_QUERIES: u32 = 0;
        PROBE_BINDING_RESULTS: u32 = 1;
        PROBE_BINDING_CAMERA: u32 = 2;
        /// The aperture image's tables, as TRACE_BINDING_APERTURE.
        PROBE_BINDING_APERTURE: u32 = 3;
        /// The real lens, as TRACE_BINDING_LENS.
        PROBE_BINDING_LENS: u32 = 4;
        /// resolve.comp (the preview): the accumulation, the G-buffer images, the display image.
        RESOLVE_GROUP_SIZE: u32 = 8;
        RESOLVE_BINDING_ACCUM: u32 = 0;
        RESOLVE_BINDING_NORMAL: u32 = 1;
        RESOLVE_BINDING_ALBEDO: u32 = 2;
        RESOLVE_BINDING_VIEW_DEPTH: u32 = 3;
        RESOLVE_BINDING_DISPLAY: u32 = 4;
        /// sampler_cost.comp (the benchmark of sample generation alone).
        SAMPLER_COST_BINDING_SUMS: u32 = 0;
    }
    // Every struct here is read back by the layout probe (lensray-vulkan/src/probes/layouts.rs) through
    // the kind of block its layout is for; the one marked `#[layout_probe(push_constant)]`
    // through push constants too.
    structs {
        /// The camera as the shaders see it (shaders/include/camera.glsl); there is no second camera:
        /// the matrices are the Rust camera's.
        Std140 struct GpuCamera as Camera {
            world_from_camera: [f32; 16],
            screen_from_raster: [f32; 16],
            /// PROJECTION_*
            projection: u32,
            near_z: f32,
            aperture_radius: f32,
            focus_distance: f32,
            /// Triangles of the aperture's fan (camera::aperture); 0: a disk.
            aperture_fan_len: u32,
            /// The aperture's height over its width.
            aperture_aspect: f32,
            /// Cells of the aperture image (camera::aperture::image) a row and a column; 0: no
            /// image. Its tables are the storage buffer at APERTURE_TABLE_BINDING.
            aperture_image_columns: u32,
            aperture_image_rows: u32,
            /// (cos, sin) of the aperture's rotation, which turns an image; zw unused.
            aperture_turn: [f32; 4],
            /// The fan's vertices (unit circumscribed radius), two per vec4: (x0, y0, x1, y1).
            aperture_fan: [[f32; 4]; 32],
        }
        /// Where the pinhole ray through a pixel and its neighbours run (camera/footprint.rs).
        Std140 struct GpuFootprint as Footprint {
            /// The eye; w: 1 orthographic, 0 perspective.
            eye: [f32; 4],
            /// The view axis.
            forward: [f32; 4],
            /// One pixel step along raster x and y: on the plane at unit depth (perspective) or
            /// across the parallel rays (orthographic), world space.
            pixel_dx: [f32; 4],
            pixel_dy: [f32; 4],
        }
        /// The uniform block of trace.comp.
        Std140 struct TraceParams as TraceParams {
            camera: GpuCamera,
            background: [f32; 4],
            /// The uniform sky's radiance (`RenderSettings::environment`); w unused.
            environment: [f32; 4],
            width: u32,
            height: u32,
            seed: u32,
            /// SHADING_*
            shading: u32,
            /// SAMPLER_* (`sampler::SamplerKind::id`).
            sampler_kind: u32,
            /// 1: every pixel draws the camera samples of pixel (0, 0)
            /// (`RenderSettings::shared_samples`, sampler.glsl's shared_pixel_sampler).
            shared_samples: u32,
            pad1: u32,
            pad2: u32,
            /// The pinhole's pixel footprint (`Camera::footprint`), for texture filtering.
            footprint: GpuFootprint,
        }
        /// Push constants of one trace.comp dispatch: the blocks of TRACE_GROUP_SIZE rows
        /// block_first + i * block_stride (i < block_count) of the band of band_height rows from
        /// image row band_origin (the accumulation buffer holds that band), samples
        /// sample_begin..sample_end.
        #[layout_probe(push_constant)]
        Std430 struct TracePush as TracePush {
            band_origin: u32,
            band_height: u32,
            block_first: u32,
            block_stride: u32,
            block_count: u32,
            sample_begin: u32,
            sample_end: u32,
            /// TRACE_MODE_*
            mode: u32,
        }
        /// Push constants of the raster path's visibility pass (shaders/passes/visibility.vert).
        Std430 struct VisibilityPush as VisibilityPush {
            /// `Camera::clip_from_world_through_lens` of the pass's camera sample.
            clip_from_world: [f32; 16],
            /// What the keys of the sample's camera rays are made of (`scene::ray_key`), for
            /// BLEND surfaces: the seed, the image width and the sample.
            seed: u32,
            width: u32,
            sample_index: u32,
            /// 1: the pass draws the aperture-centre rays, which cut BLEND surfaces at
            /// AOV_BLEND_THRESHOLD instead.
            aperture_centre: u32,
        }
        /// Push constants of the G-buffer pass.
        Std430 struct RasterPush as RasterPush {
            clip_from_world: [f32; 16],
            eye: [f32; 4],
            /// xyz: the view axis; w: 1 orthographic (viewer direction is the axis), 0 perspective.
            forward: [f32; 4],
        }
        /// What a preview view shows (shaders/include/views.glsl) and the lens data of its circle of
        /// confusion (camera.glsl's coc_radius_pixels mirrors Camera::coc_radius_pixels).
        Std430 struct ViewParams as ViewParams {
            /// VIEW_*
            view: u32,
            /// PROJECTION_*
            projection: u32,
            /// ThinLens::reach: the radius of the circle that holds the aperture's shape.
            lens_reach: f32,
            focus_distance: f32,
            near_z: f32,
            far_z: f32,
            /// Pixels per screen-space unit (height / screen window height).
            pixels_per_screen_unit: f32,
            /// The circle-of-confusion radius, in pixels, shown as white.
            coc_display_max: f32,
        }
        /// Push constants of resolve.comp: the image size and the view.
        Std430 struct ResolvePush as ResolvePush {
            width: u32,
            height: u32,
            pad0: u32,
            pad1: u32,
            shown: ViewParams,
        }
        /// Push constants of the view pass (gbuffer.vert reads the leading RasterPush,
        /// view.frag the view).
        Std430 struct ViewPush as ViewPush {
            raster: RasterPush,
            shown: ViewParams,
        }
        /// Push constants of hybrid_plan.comp: the image, the step, what the plan is for and
        /// the lens data of the circle of confusion (camera.glsl's coc_radius_pixels).
        Std430 struct HybridPlanPush as HybridPlanPush {
            width: u32,
            height: u32,
            tiles_x: u32,
            tiles_y: u32,
            /// HYBRID_PLAN_STEP_*
            step: u32,
            /// SHADING_*
            shading: u32,
            spp: u32,
            /// PROJECTION_*
            projection: u32,
            /// ThinLens::reach: the radius of the circle that holds the aperture's shape.
            lens_reach: f32,
            focus_distance: f32,
            near_z: f32,
            /// Pixels per screen-space unit (Camera::pixels_per_screen_unit).
            pixels_per_screen_unit: f32,
        }
        /// Push constants of sampler_cost.comp.
        Std430 struct SamplerCostPush as SamplerCostPush {
            width: u32,
            height: u32,
            seed: u32,
            /// SAMPLER_*
            sampler_kind: u32,
            spp: u32,
        }
        /// One request of probe.comp (the GLSL mirror check).
        Std430 struct ProbeQuery as ProbeQuery {
            seed: u32,
            pixel_x: u32,
            pixel_y: u32,
            width: u32,
            sample_index: u32,
            dim: u32,
            hash_input: u32,
            /// SAMPLER_*
            sampler_kind: u32,
        }
        /// What probe.comp computed for a query.
        Std430 struct ProbeResult as ProbeResult {
            /// hash_u32(hash_input)
            hash: u32,
            /// sample_key(seed, pixel_y * width + pixel_x, sample_index)
            key: u32,
            /// bits of sample_1d(key, dim)
            sample_bits: u32,
            /// lens_index(hash_input)
            lens: u32,
            /// owen_scramble_reversed(hash_input, seed)
            scrambled: u32,
            /// shuffle_index(hash_input, seed)
            shuffled: u32,
            /// sobol_reversed(dim % 2, hash_input)
            sobol: u32,
            /// bits of sample_dimension(sampler_kind, seed, pixel index, sample_index, dim)
            dimension_bits: u32,
            /// film.xy, lens.xy of camera_sample(sampler_kind, seed, pixel, width, sample_index)
            camera_sample: [f32; 4],
            /// first_order_ray(camera, film, lens): origin (w = 1)
            origin: [f32; 4],
            /// ... and direction (w = 0)
            direction: [f32; 4],
            /// lens_point(camera, lens).xy, then 0, 0
            lens_point: [f32; 4],
            /// generate_ray(camera, film, lens): origin, w the weight (-1: the
            /// real lens blocks the ray)
            through_lens_origin: [f32; 4],
            /// ... and direction (w = 0)
            through_lens_direction: [f32; 4],
        }
        /// A real lens as the shaders read it (camera::real_lens; shaders/include/real_lens.glsl),
        /// focused and stopped down, for one image size; `surface_count` 0: the thin lens.
        Std430 struct GpuLens as Lens {
            surface_count: u32,
            /// The stop's row, and its opening's circumscribed radius (mm).
            stop: u32,
            stop_radius: f32,
            /// Lens-space z of the film and of the entrance pupil (camera space's origin).
            film_z: f32,
            entrance_pupil_z: f32,
            /// Film mm per pixel, and the image's centre in raster coordinates.
            film_mm_per_pixel: f32,
            raster_centre_x: f32,
            raster_centre_y: f32,
            /// The exit pupil's regions: the rear plane's z, the film's half diagonal (the last
            /// bin's outer edge), and 1 / the centre's integral of T cos^4.
            rear_z: f32,
            film_radius: f32,
            inverse_centre_integral: f32,
            /// Where the aperture image's cell transmissions start in the aperture table
            /// (after its cumulative tables); the stop reads them.
            aperture_transmission_start: u32,
            /// Per surface (LENS_MAX_SURFACES): vertex z, radius (0: the stop), clear-aperture
            /// radius, 0.
            surface_shape: [[f32; 4]; 32],
            /// Per surface: the index before it and after it, 0, 0.
            surface_media: [[f32; 4]; 32],
            /// Per bin (LENS_PUPIL_BINS): the region at its inner film radius (centre xy, half
            /// sides zw), and at its outer.
            pupil_inner: [[f32; 4]; 64],
            pupil_outer: [[f32; 4]; 64],
        }
        /// A light of the scene's storage buffer (`scene::Light`).
        Std430 struct GpuLight as Light {
            position: [f32; 4],
            /// The direction the light travels (spot, directional).
            direction: [f32; 4],
            /// W/sr (point, spot) or W/m^2 (directional) per channel.
            intensity: [f32; 4],
            /// LIGHT_*
            kind: u32,
            /// 0: unlimited.
            range: f32,
            /// Spot: cosines of the inner and outer half-angles.
            cos_inner: f32,
            cos_outer: f32,
        }
        /// A texture of the scene (scene::texture): its levels, size and encoding.
        Std430 struct GpuTexture as Texture {
            /// Each level's first texel in the texel buffer, four per uvec4.
            level_first: [[u32; 4]; 4],
            width: u32,
            height: u32,
            levels: u32,
            /// 1: RGB is sRGB-encoded; 0: linear.
            srgb: u32,
        }
        /// A material's texture slot (`scene::TextureRef`).
        Std430 struct GpuTextureRef as TextureRef {
            /// uv = (dot(transform_u.xy, texcoord) + transform_u.z, the same with transform_v).
            transform_u: [f32; 4],
            transform_v: [f32; 4],
            /// TEXTURE_NONE: no texture.
            texture: u32,
            /// WRAP_*
            wrap_u: u32,
            wrap_v: u32,
            pad: u32,
        }
        /// A material of the scene's storage buffer (`scene::Material`).
        Std430 struct GpuMaterial as Material {
            /// Kd; w: alpha
            diffuse: [f32; 4],
            /// Ke; w: the alpha cutoff of ALPHA_MASK
            emission: [f32; 4],
            diffuse_texture: GpuTextureRef,
            emission_texture: GpuTextureRef,
            alpha_texture: GpuTextureRef,
            /// ALPHA_*
            alpha_mode: u32,
            pad0: u32,
            pad1: u32,
            pad2: u32,
        }
        /// An inner node of the software traversal's BVH (lensray-vulkan/src/scene/bvh.rs): the boxes of both
        /// children, so one node fetch tests two boxes (Aila and Laine's layout). A child is
        /// another node (count 0: `link` indexes the node array) or a leaf (count > 0: `count`
        /// triangles from `link` in the leaf-ordered triangle array).
        Std430 struct GpuBvhNode as BvhNode {
            /// Child a: min x, max x, min y, max y.
            a_xy: [f32; 4],
            /// Child b: min x, max x, min y, max y.
            b_xy: [f32; 4],
            /// min z, max z of child a, then of child b.
            ab_z: [f32; 4],
            /// Link of a, link of b, triangle count of a, of b.
            children: [u32; 4],
        }
        /// A triangle of the software traversal, in BVH leaf order: its vertices, and in
        /// `v0[3]` the global triangle index as a float (exact: indices stay below 2^24).
        Std430 struct GpuBvhTriangle as BvhTriangle {
            v0: [f32; 4],
            v1: [f32; 4],
            v2: [f32; 4],
        }
    }
}
