#version 460
// Thin-lens compute pass: spp camera samples per pixel, each traced and shaded as specified for
// every renderer (shading.glsl; lensray-core/src/settings/render.rs, the CPU reference). build.rs compiles it
// once per closest-hit implementation: TRAVERSAL_RAY_QUERY (ray queries against the TLAS,
// hit_rayquery.glsl), TRAVERSAL_SOFTWARE (the project's own BVH, hit_software.glsl, no
// ray-tracing extension) and TRAVERSAL_RT_PIPELINE (the ray generation stage of a ray-tracing
// pipeline, traceRayEXT against the TLAS, hit_rtpipeline.glsl: the same pixels and samples, a
// launch of TRACE_GROUP_SIZE rows per block standing for the workgroups). One dispatch covers some rows (strided) and a range of samples; sums
// accumulate in `accum` (xyz: the sum, w: how many samples), which holds a band of rows of the
// image (bounded by the device's storage-buffer range).
// The hybrid path (src/estimators.rs, docs/hybrid.md) runs it in TRACE_MODE_HYBRID: a plan
// per pixel says how many samples to trace, or that the pixel takes a shortcut value, checked
// by tracing a sample with probability 1 / HYBRID_CHECK_INVERSE (unbiased); TRACE_MODE_SHORTCUT
// (lit) first shades the aperture-centre ray of each pixel into the plan, before its steps.
// The raster path (lensray/src/paths/gpu.rs, docs/raster.md) runs it in TRACE_MODE_RASTER after each
// of its raster passes: one camera sample shared by all pixels, whose first hit the pass drew.
#if defined(TRAVERSAL_RAY_QUERY)
#extension GL_EXT_ray_query : require
#elif defined(TRAVERSAL_RT_PIPELINE)
#extension GL_EXT_ray_tracing : require
#elif !defined(TRAVERSAL_SOFTWARE)
#error "define TRAVERSAL_RAY_QUERY, TRAVERSAL_SOFTWARE or TRAVERSAL_RT_PIPELINE"
#endif

#if defined(TRAVERSAL_RAY_QUERY)
#include "set_trace_rayquery.glsl"
#elif defined(TRAVERSAL_RT_PIPELINE)
#include "set_trace_rtpipeline.glsl"
#else
#include "set_trace_software.glsl"
#endif
#include "camera.glsl"
#include "sampler.glsl"
#include "spectral.glsl"
#include "scene.glsl"
#include "texture.glsl"

#if defined(TRAVERSAL_RT_PIPELINE)
// The pixel and its block of rows: launch (x, y) is the compute pass's invocation (x, y).
#define PIXEL_X gl_LaunchIDEXT.x
#define BLOCK (gl_LaunchIDEXT.y / TRACE_GROUP_SIZE)
#define BLOCK_ROWS TRACE_GROUP_SIZE
#define ROW_IN_BLOCK (gl_LaunchIDEXT.y % TRACE_GROUP_SIZE)
#else
layout(local_size_x = TRACE_GROUP_SIZE, local_size_y = TRACE_GROUP_SIZE) in;
#define PIXEL_X gl_GlobalInvocationID.x
#define BLOCK gl_WorkGroupID.y
#define BLOCK_ROWS gl_WorkGroupSize.y
#define ROW_IN_BLOCK gl_LocalInvocationID.y
#endif

layout(push_constant) uniform PushBlock { TracePush pc; };

// What the hit implementations return: the global triangle index (as `instance custom index +
// primitive index` names it), the distance, and the barycentric weights of v1 and v2.
struct Hit {
    uint triangle;
    float t;
    vec2 barycentrics;
};

#if defined(TRAVERSAL_RAY_QUERY)
#include "hit_rayquery.glsl"
#elif defined(TRAVERSAL_RT_PIPELINE)
#include "hit_rtpipeline.glsl"
#else
#include "hit_software.glsl"
#endif
#include "shading.glsl"

// The camera samples of pixel (x, y): its own, or with shared samples those of pixel (0, 0)
// offset to it (sampler.glsl, lensray-core/src/sampler). Made once per pixel, outside the sample loops.
PixelSampler samples_of(uint x, uint y) {
    return params.shared_samples != 0u
        ? shared_pixel_sampler(params.sampler_kind, params.seed, uvec2(x, y))
        : pixel_sampler(params.sampler_kind, params.seed, uvec2(x, y), params.width);
}

// The lit shortcut value of a camera sample of pixel (x, y): where the sample's lens ray meets
// the plane at the pixel's surface depth, seen through the lens centre, the pre-pass's values
// (plan xyz: each pixel's surface shaded along its aperture-centre ray) interpolated there. On
// a diffuse surface with no edge or shadow boundary within the circle of confusion (the plan's
// rule for a shortcut) this follows the traced sample closely, where the pixel's own value
// alone misses the shading's change across the pixel and the aperture: the checks add
// (traced - this) * HYBRID_CHECK_INVERSE, so the closer, the less noise. Unbiased either way.
struct Reprojection {
    float depth;  // camera-space depth of the pixel's surface; 0: none (the pixel's own value)
    mat2 raster_from_screen;
    vec2 screen_origin;
};

Reprojection reprojection(uint pixel_index) {
    Reprojection r;
    r.depth = surface_depth[pixel_index];
    mat4 m = params.camera.screen_from_raster;
    r.raster_from_screen = inverse(mat2(m[0].xy, m[1].xy));
    r.screen_origin = m[3].xy;
    return r;
}

vec3 reprojected_shortcut(Reprojection r, uint pixel_index, CameraSample cs) {
    if (r.depth <= 0.0) {
        return plan[pixel_index].xyz;
    }
    Ray c = generate_ray(params.camera, pinhole_ray(params.camera, cs.film), cs.lens);
    vec3 p = ray_at(c, (r.depth - c.origin.z) / c.direction.z);
    vec2 screen = params.camera.projection == PROJECTION_PERSPECTIVE ? p.xy / p.z : p.xy;
    // Bilinear between pixel centres, clamped to the image.
    vec2 q = r.raster_from_screen * (screen - r.screen_origin) - 0.5;
    vec2 base = floor(q);
    vec2 f = q - base;
    uint w = params.width;
    ivec2 hi = ivec2(w, params.height) - 1;
    ivec2 a = clamp(ivec2(base), ivec2(0), hi);
    ivec2 b = clamp(ivec2(base) + 1, ivec2(0), hi);
    vec3 v00 = plan[uint(a.y) * w + uint(a.x)].xyz;
    vec3 v10 = plan[uint(a.y) * w + uint(b.x)].xyz;
    vec3 v01 = plan[uint(b.y) * w + uint(a.x)].xyz;
    vec3 v11 = plan[uint(b.y) * w + uint(b.x)].xyz;
    return mix(mix(v00, v10, f.x), mix(v01, v11, f.x), f.y);
}

// The radiance along `ray`, which cuts BLEND surfaces with `draw.cut`; where `rasterized`, the
// visibility pass drew its first hit at `pixel_index` (the raster path's sample, the hybrid's lit
// pre-pass) and no traversal finds it. A lit path shades params.bounces surfaces
// (reference/integrator.rs): at each its lights, the emitters and the sky (shading.glsl:
// direct_light; a bounce's emission weighed against the emitters' draw), and
// from each but the last it goes on along its BRDF's draw, weighed by f cos / pdf. `rays` counts
// the rays, `shadowed` says which lights the first surface's shadow rays found blocked. Every
// mode shades through this one call and the path has one closest-hit call site: each inlined
// copy of the traversal and the shading multiplies lavapipe's pipeline compile time.
vec3 shade_sample(Ray ray, LightDraw draw, bool rasterized, uint pixel_index, inout uint rays,
                  out uint shadowed) {
    shadowed = 0u;
    vec3 value = vec3(0.0);
    vec3 throughput = vec3(1.0);
    BlendCut cut = draw.cut;
    LitSurface previous;
    BrdfSample went;
    for (uint vertex = 0u; vertex < MAX_BOUNCES; ++vertex) {
        rays += 1u;
        Hit hit;
        bool found;
        if (rasterized && vertex == 0u) {
            uint seen = visibility[pixel_index];
            found = seen != 0u;
            if (found) {
                hit = triangle_plane_hit(ray, seen - 1u);
            }
        } else {
            found = closest_hit(ray.origin, ray.direction, T_MAX, cut, hit);
        }
        if (!found) {
            if (vertex == 0u) {
                return params.environment_map == ENVIRONMENT_MAP_SEEN
                    ? env_radiance(normalize(ray.direction)) : params.background.xyz;
            }
            if (sky_lights()) {
                value += throughput * sky_along(previous, went);
            }
            break;
        }
        LitSurface s;
        vec3 emission;
        bool lit = surface_at(ray, hit, vertex == 0u, s, emission);
        if (vertex > 0u) {
            throughput *= went.weight;
            // reference/integrator.rs: volume_transmittance
            if (lit) {
                throughput *= exp(-s.attenuation * (hit.t * length(ray.direction)));
            }
            // reference/integrator.rs: emission_weight
            if (emitters_light()) {
                float pdf = emitter_pdf(hit.triangle, normalize(ray.direction),
                                        hit.t * length(ray.direction));
                emission *= power_heuristic(went.pdf, pdf);
            }
        }
        value += throughput * emission;
        if (!lit) {
            break;
        }
        bool last = vertex + 1u >= params.bounces;
        // A path's last surface under no sky draws nothing (the default render): no sampler
        // dimensions, no BRDF draw (reference/integrator.rs: trace_paths).
        bool draws = !last || sky_lights();
        vec4 u = draws ? vertex_points(draw, vertex) : vec4(0.0);
        BrdfSample next;
        float choice = draws ? fresnel_point(draw, vertex) : 0.0;
        bool drawn = draws && brdf_sample(s.brdf, s.ns, s.v, vec3(u.zw, choice), next)
            && leaves(s, next.direction);
        uint blocked;
        cut = shadow_cut(draw.cut);
        // The last surface's BRDF draw meets no emitter: the emitters' draw counts whole.
        vec2 e = emitters_light() ? emitter_point(draw, vertex) : vec2(0.0);
        vec3 sky_point = vec3(u.xy, draws ? sky_pick_point(draw, vertex) : 0.0);
        vec3 reflected = direct_light(s, e, !last, sky_point, last && drawn, next, cut, rays,
                                      blocked);
        if (vertex == 0u) {
            shadowed = blocked;
        }
        value += throughput * reflected;
        if (last || !drawn) {
            break;
        }
        previous = s;
        went = next;
        ray = Ray(origin_towards(s, next.direction), next.direction);
    }
    return value;
}

// What sample `s` of pixel `pixel_index` draws besides its camera ray (reference/render.rs,
// add_pixel_samples): its ray's BLEND cut (scene::ray_key) and the points of its path.
LightDraw sample_draw(PixelSampler state, uint pixel_index, uint s) {
    LightDraw draw;
    draw.cut = ray_cut(sample_key(params.seed, pixel_index, s) ^ BLEND_CAMERA_SALT);
    draw.state = state;
    draw.sample_index = s;
    draw.centred = false;
    return draw;
}

// The pixel's work for this dispatch; returns the rays it traced (0 outside the band). Every mode
// runs the same loop over its samples and shades through one shade_sample call:
// - TRACE_MODE_ALL traces samples sample_begin..sample_end (through the real lens when there is
//   one: a blocked ray adds nothing but counts as a sample; real_lens.glsl).
// - TRACE_MODE_RASTER shades the one sample, shared by every pixel, whose first hit the raster
//   pass drew.
// - TRACE_MODE_SHORTCUT (the hybrid's lit pre-pass) shades the aperture-centre ray at the pixel
//   centre (concentric_sample_disk(0.5, 0.5) is the lens centre), which the visibility pass
//   rasterized through the lens centre just before, into the plan: the shortcut value and which
//   lights were blocked (the plan's edge test compares it between neighbours: a shadow boundary
//   is an edge). Its path draws every point at (0.5, 0.5): the shortcut only steers the checks,
//   which keep the estimate unbiased.
// - TRACE_MODE_HYBRID: the plan's entry says how many samples to trace (w >= 1), or that the
//   pixel takes the shortcut value (w = HYBRID_SHORTCUT), checked by tracing with probability
//   1 / HYBRID_CHECK_INVERSE: the value plus (traced - value) * HYBRID_CHECK_INVERSE, unbiased.
//   The choice hashes the 8x8 tile and the sample, so that the pixels of a workgroup (run in
//   lockstep) check alike. Lit, the value is reprojected per sample (above); unlit the albedo is
//   the value of every lens ray of a uniform neighbourhood.
// - TRACE_MODE_ADAPTIVE (adaptive sampling's rounds, decided on the host: film/adaptive.rs):
//   TRACE_MODE_ALL from the pixel's own count (plan w) on, or nothing (w = ADAPTIVE_IDLE); its
//   class A samples (film/adaptive.rs is_class_a) add to its class A sum, plan xyz.
uint trace_pixel() {
    uint x = PIXEL_X;
    uint block = BLOCK;
    uint band_row = (pc.block_first + block * pc.block_stride) * BLOCK_ROWS + ROW_IN_BLOCK;
    uint y = pc.band_origin + band_row;
    if (x >= params.width || block >= pc.block_count || band_row >= pc.band_height) {
        return 0u;
    }
    uint slot = band_row * params.width + x;
    uint pixel_index = y * params.width + x;
    uint rays = 0u;
    bool pre_pass = pc.mode == TRACE_MODE_SHORTCUT;
    bool adaptive = pc.mode == TRACE_MODE_ADAPTIVE;
    bool every_sample = pc.mode == TRACE_MODE_ALL || adaptive;
    bool rasterized = pre_pass || pc.mode == TRACE_MODE_RASTER;
    bool lit = params.shading == SHADING_LIT;
    PixelSampler sampler_state = samples_of(x, y);
    uint begin = pc.sample_begin;
    uint end = rasterized ? begin + 1u : pc.sample_end;
    bool shortcut = false;
    vec3 shortcut_value = vec3(0.0);
    Reprojection r;
    if (pc.mode == TRACE_MODE_HYBRID) {
        vec4 entry = plan[pixel_index];
        shortcut = entry.w == HYBRID_SHORTCUT;
        shortcut_value = entry.xyz;
        // Samples i < entry.w are traced; the pixel's count stops there.
        end = shortcut ? end : min(end, uint(entry.w));
        r = reprojection(pixel_index);
    }
    vec3 class_a = vec3(0.0);
    if (adaptive) {
        vec4 entry = plan[pixel_index];
        if (entry.w == ADAPTIVE_IDLE) {
            return 0u;
        }
        begin = max(begin, uint(entry.w));
        class_a = entry.xyz;
    }
    uint tile = (y / TRACE_GROUP_SIZE) * ((params.width + TRACE_GROUP_SIZE - 1u) / TRACE_GROUP_SIZE)
              + x / TRACE_GROUP_SIZE;
    vec4 before = pre_pass ? vec4(0.0) : accum[slot];
    vec3 sum = before.xyz;
    for (uint s = begin; s < end; ++s) {
        bool trace = !shortcut
            || hash_u32(sample_key(params.seed ^ HYBRID_CHECK_SALT, tile, s)) % HYBRID_CHECK_INVERSE == 0u;
        CameraSample cs;
        if (trace || lit) {
            cs = pixel_camera_sample(sampler_state, s);
            // projective.rs: Camera::sample_time.
            if (params.camera.motion_steps != 0u) {
                cs.time = pixel_dimension(sampler_state, s, DIM_TIME);
            }
            trace_moment = sample_moment(params.camera, cs);
        }
        // What the sample adds untraced: a shortcut's value.
        vec3 value = !shortcut ? vec3(0.0) : lit ? reprojected_shortcut(r, pixel_index, cs) : shortcut_value;
        // Through a dispersive lens the sample traces the d line, and where it checks it, its
        // wavelength too (nm; 0: it does not): spectral.glsl's d_line_value, checked_value
        // (reference/render.rs: add_pixel_samples, reference/rays.rs: generate_rays).
        float checked = 0.0;
        uint passes = 1u;
        if (every_sample && lens.dispersive != 0u
            && checks_dispersion(pixel_dimension(sampler_state, s, DIM_DISPERSION_CHECK))) {
            checked = sample_wavelength(pixel_dimension(sampler_state, s, DIM_WAVELENGTH));
            passes = 2u;
        }
        for (uint pass = 0u; pass < passes; ++pass) {
            Ray ray;
            float weight = 1.0;
            bool traced_now = trace;
            if (pre_pass) {
                ray = first_order_ray(params.camera, CameraSample(vec2(x, y) + 0.5, vec2(0.5), CAMERA_SAMPLE_MIDDLE));
            } else if (every_sample) {
                traced_now = generate_ray(params.camera, cs, pass == 1u ? checked : 0.0, ray, weight);
            } else if (trace) {
                ray = first_order_ray(params.camera, cs);
            }
            if (!traced_now) {
                continue;
            }
            LightDraw draw = sample_draw(sampler_state, pixel_index, s);
            if (pre_pass) {
                draw.cut = aperture_centre_cut();
                draw.centred = true;
            }
            uint shadowed;
            vec3 shaded = shade_sample(ray, draw, rasterized, pixel_index, rays, shadowed);
            shaded = pass == 1u ? checked_value(checked, shaded) : d_line_value(checked, shaded);
            vec3 traced = weight * shaded;
            if (pre_pass) {
                plan[pixel_index] = vec4(traced, float(shadowed));
                return rays;
            }
            // Without a shortcut `value` starts at 0: the sum of the sample's passes.
            value = shortcut ? value + (traced - value) * float(HYBRID_CHECK_INVERSE) : value + traced;
        }
        sum += value;
        // The parity of the index's odd bits, as film/adaptive.rs's is_class_a.
        if (adaptive && (bitCount(s & 0xaaaaaaaau) & 1) == 1) {
            class_a += value;
        }
    }
    if (adaptive) {
        plan[pixel_index].xyz = class_a;
    }
    // w counts the samples added (exact in float up to 2^24): the preview divides by it.
    uint added = end > begin ? end - begin : 0u;
    accum[slot] = vec4(sum, before.w + float(added));
    return rays;
}

// Adds to the 64-bit count (two words): the add that wraps the low word carries into the high
// one, exactly once per wrap.
void count_rays(uint rays) {
    uint before = atomicAdd(rays_traced, rays);
    if (before > 0xFFFFFFFFu - rays) {
        atomicAdd(rays_traced_high, 1u);
    }
}

#if defined(TRAVERSAL_RT_PIPELINE)
// A ray generation stage has no workgroup to sum the rays in: each invocation adds its own.
void main() {
    uint rays = trace_pixel();
    if (rays != 0u) {
        count_rays(rays);
    }
}
#else
// Rays are summed per workgroup in shared memory and added to the global counter once per
// workgroup: a global atomic per invocation serializes on one address across the whole GPU.
shared uint group_rays;

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        group_rays = 0u;
    }
    memoryBarrierShared();
    barrier();
    uint rays = trace_pixel();
    if (rays != 0u) {
        atomicAdd(group_rays, rays);
    }
    memoryBarrierShared();
    barrier();
    if (gl_LocalInvocationIndex == 0u && group_rays != 0u) {
        count_rays(group_rays);
    }
}
#endif
