// The structs the host and the shaders share: uniform blocks, push constants and storage
// buffers (the constants are constants.rs). lensray-vulkan's build.rs writes `interface.glsl`
// from both; the shaders include that, so a shader that names a field that is gone here fails
// to build.

use super::constants::*;
use super::glsl::*;

shader_interface! {
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
            /// image. Its tables are `ApertureGroup`'s `aperture_table`.
            aperture_image_columns: u32,
            aperture_image_rows: u32,
            /// (cos, sin) of the aperture's rotation, which turns an image; zw unused.
            aperture_turn: [f32; 4],
            /// The plane of focus's slope (ThinLens::focus_tilt); zw unused.
            focus_tilt: [f32; 4],
            /// The fan's vertices (unit circumscribed radius), two per vec4: (x0, y0, x1, y1).
            aperture_fan: [[f32; 4]; 32],
            /// camera::motion's CameraMotion: 0 while the camera is still (every ray through
            /// world_from_camera), else MOTION_STEPS poses.
            motion_steps: u32,
            motion_exposure_share: f32,
            motion_rolling_share: f32,
            /// The image's height in rows, for a row's share of the readout.
            motion_height: f32,
            /// Each pose's eye (w unused) and rotation (a quaternion, xyzw).
            motion_eye: [[f32; 4]; 8],
            motion_rotation: [[f32; 4]; 8],
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
            /// The surfaces a lit path shades (`RenderSettings::bounces`).
            bounces: u32,
            /// ENVIRONMENT_MAP_*: whether the scene's map (EnvironmentGroup) lights, and is
            /// seen where camera rays leave the scene.
            environment_map: u32,
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
        /// A circle of confusion's lens data (camera/coc.rs, `CocLens`; camera.glsl's
        /// coc_radius_pixels mirrors `CocLens::radius_pixels`).
        Std430 struct GpuCocLens as CocLens {
            /// PROJECTION_*
            projection: u32,
            focus_distance: f32,
            /// Pixels of circle per unit of the distance to the plane of focus.
            scale: f32,
            /// The plane's slope dotted with the screen point at raster (0, 0), and its steps
            /// per raster x and y.
            tilt_origin: f32,
            tilt_dx: f32,
            tilt_dy: f32,
        }
        /// What a preview view shows (shaders/include/views.glsl) and the lens data of its
        /// circle of confusion.
        Std430 struct ViewParams as ViewParams {
            /// VIEW_*
            view: u32,
            far_z: f32,
            coc: GpuCocLens,
        }
        /// Push constants of resolve.comp: the image size, how the final view is exposed and
        /// tone mapped, and the view.
        Std430 struct ResolvePush as ResolvePush {
            width: u32,
            height: u32,
            /// The final view's linear scale (film::tonemap::Display::exposure).
            exposure: f32,
            /// TONEMAP_*
            tonemap: u32,
            shown: ViewParams,
            /// 1: the final view adds `flare` (the lens's own light) before exposure.
            flare: u32,
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
            coc: GpuCocLens,
        }
        /// Push constants of ghosts.comp: a distant source `field` off the axis (its sine and
        /// cosine) traced on a `grid` x `grid` grid over the front surface's clear aperture
        /// (`front_radius` mm) along `paths` paths at `wavelengths` wavelengths, drawn into
        /// `columns` x `rows` film bins of `bin_mm`; `step` GHOST_STEP_*.
        Std430 struct GhostPush as GhostPush {
            step: u32,
            paths: u32,
            wavelengths: u32,
            grid: u32,
            columns: u32,
            rows: u32,
            front_radius: f32,
            bin_mm: f32,
            sin_field: f32,
            cos_field: f32,
            /// The share of the light entering the lens one grid cell carries.
            cell_share: f32,
            pad0: u32,
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
            /// The wavelength generate_ray traces the real lens at, nm (0: the d line).
            wavelength_nm: f32,
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
            /// first_order_ray(camera, camera sample): origin (w = 1)
            origin: [f32; 4],
            /// ... and direction (w = 0)
            direction: [f32; 4],
            /// lens_point(camera, lens).xy, then 0, 0
            lens_point: [f32; 4],
            /// generate_ray(camera, camera sample, wavelength_nm): origin, w the weight (-1: the
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
            /// 1: each camera sample draws a wavelength (RealLens::dispersive), 0: the d line.
            dispersive: u32,
            /// Bit i: surface i is an asphere (its terms in surface_shape.w and
            /// surface_asphere_low/high).
            asphere_mask: u32,
            pad0: u32,
            pad1: u32,
            /// The film in lens space (real_lens::FilmFrame): its point on the view axis (w:
            /// the exit pupil's axis_depth), the image's +x and +y, its normal.
            film_origin: [f32; 4],
            film_right: [f32; 4],
            film_up: [f32; 4],
            film_normal: [f32; 4],
            /// Camera space from lens space unflipped (the tilt's turn), column by column.
            camera_from_lens: [[f32; 4]; 3],
            /// Per surface (LENS_MAX_SURFACES): vertex z, radius (0: the stop), clear-aperture
            /// radius, an asphere's conic constant.
            surface_shape: [[f32; 4]; 32],
            /// Per surface: the d-line index before it and after it, and Cauchy's B of the
            /// media before and after (optics::glass: the index at offset k is n + B k).
            surface_media: [[f32; 4]; 32],
            /// Per surface: an asphere's a2, a4, a6, a8 ...
            surface_asphere_low: [[f32; 4]; 32],
            /// ... and a10, a12, a14, a16.
            surface_asphere_high: [[f32; 4]; 32],
            /// The spectral tables, four floats a vec4, at SPECTRAL_AT_* (the trace pass's
            /// spectral.glsl reads them here; upload/camera.rs copies the SPECTRAL_* constants).
            spectral_table: [[f32; 4]; 256],
            /// Per bin (LENS_PUPIL_BINS): the region at its inner film radius (centre xy, half
            /// sides zw), and at its outer.
            pupil_inner: [[f32; 4]; 64],
            pupil_outer: [[f32; 4]; 64],
            /// SHEEN_ALBEDO, four floats a vec4 (brdf.glsl's sheen reads it here in the trace
            /// pass, for the reason spectral_table is here; upload/camera.rs copies it).
            sheen_albedo: [[f32; 4]; 256],
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
        /// An environment map's parameters (`scene::environment`); its texels and sampling
        /// tables are `EnvironmentGroup`'s buffers.
        Std430 struct GpuEnvironment as Environment {
            width: u32,
            height: u32,
            /// The sum of the sampling weights (`EnvironmentSampler`); 0: nothing emits.
            total: f32,
            /// Multiplies every texel.
            intensity: f32,
            /// (cos, sin) of the turn about +Y; zw unused.
            turn: [f32; 4],
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
            /// uv = (dot(transform_u.xy, texcoord) + transform_u.z, the same with transform_v),
            /// texcoord the coordinates of set `texcoord_set`.
            transform_u: [f32; 4],
            transform_v: [f32; 4],
            /// TEXTURE_NONE: no texture.
            texture: u32,
            /// WRAP_*
            wrap_u: u32,
            wrap_v: u32,
            /// The texture coordinate set read: 0 (`texcoords`) or 1 (`texcoords1`).
            texcoord_set: u32,
        }
        /// A material of the scene's storage buffer (`scene::Material`).
        Std430 struct GpuMaterial as Material {
            /// The base colour; w: alpha
            diffuse: [f32; 4],
            /// Ke; w: the alpha cutoff of ALPHA_MASK
            emission: [f32; 4],
            diffuse_texture: GpuTextureRef,
            emission_texture: GpuTextureRef,
            alpha_texture: GpuTextureRef,
            /// ALPHA_*
            alpha_mode: u32,
            metallic: f32,
            roughness: f32,
            specular: f32,
            /// B: metallic, G: roughness (linear).
            metallic_roughness_texture: GpuTextureRef,
            /// R: the environment's occlusion (linear).
            occlusion_texture: GpuTextureRef,
            occlusion_strength: f32,
            /// glTF's `normalTexture.scale`: multiplies the normal map's x and y.
            normal_scale: f32,
            pad0: u32,
            pad1: u32,
            /// A tangent-space normal map (linear; TEXTURE_NONE: none).
            normal_texture: GpuTextureRef,
            /// `KHR_materials_clearcoat`: the coat's weight and roughness (0: no coat).
            clearcoat: f32,
            clearcoat_roughness: f32,
            /// `clearcoatNormalTexture.scale`: multiplies the coat's normal map's x and y.
            clearcoat_normal_scale: f32,
            pad3: u32,
            /// R: multiplies `clearcoat` (linear).
            clearcoat_texture: GpuTextureRef,
            /// G: multiplies `clearcoat_roughness` (linear).
            clearcoat_roughness_texture: GpuTextureRef,
            /// `KHR_materials_sheen`: the sheen's linear colour (black: no sheen); w: its
            /// roughness.
            sheen_colour: [f32; 4],
            /// RGB (sRGB): multiplies the sheen's colour.
            sheen_colour_texture: GpuTextureRef,
            /// A: multiplies the sheen's roughness (linear).
            sheen_roughness_texture: GpuTextureRef,
            /// `KHR_materials_volume`: the extinction per unit length (xyz; 0: clear).
            attenuation: [f32; 4],
            /// `KHR_materials_transmission`: the share of the dielectric's unreflected light
            /// that goes through (0: opaque).
            transmission: f32,
            /// `KHR_materials_ior`: the dielectric's index of refraction.
            ior: f32,
            /// 1: a thin wall; 0: a volume's boundary.
            thin: u32,
            pad4: u32,
            /// R: multiplies `transmission` (linear).
            transmission_texture: GpuTextureRef,
            /// The coat's own tangent-space normal map (linear; TEXTURE_NONE: the coat follows
            /// the interpolated vertex normal).
            clearcoat_normal_texture: GpuTextureRef,
        }
        /// A node of the software traversal's 8-wide BVH (lensray-vulkan/src/scene/bvh.rs), the
        /// compressed layout of Ylitie, Karras and Laine (2017): up to eight children's boxes,
        /// quantized to 8 bits on a grid from `origin` with power-of-two cell sizes, so that one
        /// 80-byte fetch tests eight boxes. A child is another node or a leaf of 1 to 3
        /// triangles; leaves cost no node fetch.
        Std430 struct GpuBvhNode as BvhNode {
            /// The grid's origin (f32 bits of x, y, z), then the cell sizes' biased exponents
            /// (bits 0-23, one byte an axis) and the mask of children that are nodes (bits 24-31).
            header: [u32; 4],
            /// The first child node's index, the first triangle's slot, then one byte a child
            /// (children 0-3, 4-7): 0 for an empty child; for a node 24 + its child index, plus
            /// 0x20; for a leaf its first triangle's offset from the first slot (bits 0-4) and
            /// its triangle count in unary (bits 5-7).
            links: [u32; 4],
            /// Grid coordinates of the children's lower x planes (children 0-3, 4-7), then of
            /// their upper x planes.
            x_planes: [u32; 4],
            /// The same for y.
            y_planes: [u32; 4],
            /// The same for z.
            z_planes: [u32; 4],
        }
        /// A triangle of the software traversal, in BVH leaf order: its vertices, in `v0[3]`
        /// the global triangle index as a float (exact: indices stay below 2^24), and in
        /// `v1[3]` 1 where it moves while the shutter is open (its vertices here are the
        /// frame's; the traversal meets it at the ray's moment: scene.glsl's vertex_position).
        Std430 struct GpuBvhTriangle as BvhTriangle {
            v0: [f32; 4],
            v1: [f32; 4],
            v2: [f32; 4],
        }
    }
}
