#version 460
// Thin-lens compute pass: spp camera samples per pixel, each traced and shaded as specified for
// every renderer (shading.glsl; lensray-core/src/settings/render.rs, the CPU reference). build.rs compiles it
// once per closest-hit implementation: TRAVERSAL_RAY_QUERY (ray queries against the TLAS,
// hit_rayquery.glsl) and TRAVERSAL_SOFTWARE (the project's own BVH, hit_software.glsl, no
// ray-tracing extension). One dispatch covers some rows (strided) and a range of samples; sums
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
#elif !defined(TRAVERSAL_SOFTWARE)
#error "define TRAVERSAL_RAY_QUERY or TRAVERSAL_SOFTWARE"
#endif

#define APERTURE_TABLE_BINDING TRACE_BINDING_APERTURE
#define LENS_BINDING TRACE_BINDING_LENS
#include "camera.glsl"
#include "sampler.glsl"
#define SCENE_SET 0
#include "scene.glsl"
#include "texture.glsl"

layout(local_size_x = TRACE_GROUP_SIZE, local_size_y = TRACE_GROUP_SIZE) in;

layout(std430, set = 0, binding = TRACE_BINDING_ACCUM) buffer Accum { vec4 accum[]; };
layout(std430, set = 0, binding = TRACE_BINDING_COUNTERS) buffer Counters { uint rays_traced; };
layout(std140, set = 0, binding = TRACE_BINDING_PARAMS) uniform ParamsBlock { TraceParams params; };
layout(std430, set = 0, binding = TRACE_BINDING_PLAN) buffer Plan { vec4 plan[]; };
layout(std430, set = 0, binding = TRACE_BINDING_VISIBILITY) readonly buffer Visibility {
    uint visibility[];
};
layout(std430, set = 0, binding = TRACE_BINDING_SURFACE_DEPTH) readonly buffer SurfaceDepth {
    float surface_depth[];
};
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
    Ray c = lens_ray(params.camera, pinhole_ray_camera(params.camera, cs.film), cs.lens);
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

// The radiance along `ray`, whose first hit the visibility pass drew at `pixel_index` (the
// raster path's sample, the hybrid's lit pre-pass); `shadowed` as shade_hit_shadowed says.
vec3 shade_rasterized(Ray ray, uint pixel_index, LightDraw draw, inout uint rays,
                      out uint shadowed) {
    uint seen = visibility[pixel_index];
    rays += 1u;  // the camera ray, resolved by the rasterizer instead of a traversal
    shadowed = 0u;
    if (seen == 0u) {
        return params.background.xyz;
    }
    return shade_hit_shadowed(ray, triangle_plane_hit(ray, seen - 1u), draw, rays, shadowed);
}

// What sample `s` of pixel `pixel_index` draws besides its camera ray (reference/render.rs,
// add_pixel_samples): its ray's BLEND cut (scene::ray_key) and its environment direction.
LightDraw sample_draw(PixelSampler state, uint pixel_index, uint s) {
    LightDraw draw;
    draw.cut = ray_cut(sample_key(params.seed, pixel_index, s) ^ BLEND_CAMERA_SALT);
    draw.environment = params.environment.xyz == vec3(0.0)
        ? vec2(0.0)
        : vec2(pixel_dimension(state, s, DIM_ENVIRONMENT_X),
               pixel_dimension(state, s, DIM_ENVIRONMENT_Y));
    return draw;
}

// The pixel's work for this dispatch; returns the rays it traced (0 outside the band).
uint trace_pixel() {
    uint x = gl_GlobalInvocationID.x;
    uint block = gl_WorkGroupID.y;
    uint band_row = (pc.block_first + block * pc.block_stride) * gl_WorkGroupSize.y
                  + gl_LocalInvocationID.y;
    uint y = pc.band_origin + band_row;
    if (x >= params.width || block >= pc.block_count || band_row >= pc.band_height) {
        return 0u;
    }
    uint slot = band_row * params.width + x;
    uint pixel_index = y * params.width + x;
    uint rays = 0u;
    if (pc.mode == TRACE_MODE_SHORTCUT) {
        // The lit pre-pass of the hybrid's plan: the surface seen along the aperture-centre
        // ray at the pixel centre (concentric_sample_disk(0.5, 0.5) is the lens centre), which
        // the visibility pass rasterized through the lens centre just before (as the raster
        // path does: no traversal for it), shaded with one shadow ray (the shortcut value),
        // and which lights were blocked (the plan's edge test compares it between neighbours:
        // a shadow boundary is an edge). Its environment ray runs along the normal (the disk's
        // centre): the shortcut only steers the checks, which keep the estimate unbiased.
        Ray ray = first_order_ray(params.camera, vec2(x, y) + 0.5, vec2(0.5));
        LightDraw draw;
        draw.cut = aperture_centre_cut();
        draw.environment = vec2(0.5);
        uint shadowed;
        vec3 value = shade_rasterized(ray, pixel_index, draw, rays, shadowed);
        plan[pixel_index] = vec4(value, float(shadowed));
        return rays;
    }
    PixelSampler sampler_state = samples_of(x, y);
    vec4 before = accum[slot];
    vec3 sum = before.xyz;
    uint added = 0u;
    if (pc.mode == TRACE_MODE_HYBRID) {
        vec4 entry = plan[pixel_index];
        if (entry.w == HYBRID_SHORTCUT) {
            // Sample s: the shortcut value, plus (traced - shortcut) * HYBRID_CHECK_INVERSE with
            // probability 1 / HYBRID_CHECK_INVERSE: unbiased. The choice hashes the 8x8 tile
            // and the sample, so that the pixels of a workgroup (run in lockstep) check alike.
            vec3 shortcut = entry.xyz;
            uint tile = (y / TRACE_GROUP_SIZE) * ((params.width + TRACE_GROUP_SIZE - 1u) / TRACE_GROUP_SIZE)
                      + x / TRACE_GROUP_SIZE;
            // Lit, per sample: reprojected (above); unlit the albedo is the value of every
            // lens ray of a uniform neighbourhood.
            bool lit = params.shading == SHADING_LIT;
            Reprojection r = reprojection(pixel_index);
            for (uint s = pc.sample_begin; s < pc.sample_end; ++s) {
                uint key = sample_key(params.seed ^ HYBRID_CHECK_SALT, tile, s);
                bool check = hash_u32(key) % HYBRID_CHECK_INVERSE == 0u;
                CameraSample cs;
                if (lit || check) {
                    cs = pixel_camera_sample(sampler_state, s);
                }
                vec3 value = lit ? reprojected_shortcut(r, pixel_index, cs) : shortcut;
                if (check) {
                    Ray ray = first_order_ray(params.camera, cs.film, cs.lens);
                    vec3 traced = shade(ray, sample_draw(sampler_state, pixel_index, s), rays);
                    value += (traced - value) * float(HYBRID_CHECK_INVERSE);
                }
                sum += value;
            }
            added = pc.sample_end - pc.sample_begin;
        } else {
            // Samples i < entry.w are traced; the pixel's count stops there.
            uint end = min(pc.sample_end, uint(entry.w));
            for (uint s = pc.sample_begin; s < end; ++s) {
                CameraSample cs = pixel_camera_sample(sampler_state, s);
                Ray ray = first_order_ray(params.camera, cs.film, cs.lens);
                sum += shade(ray, sample_draw(sampler_state, pixel_index, s), rays);
            }
            added = end > pc.sample_begin ? end - pc.sample_begin : 0u;
        }
    } else if (pc.mode == TRACE_MODE_RASTER) {
        // One sample, shared by every pixel: the raster pass drew what its lens ray sees first.
        uint s = pc.sample_begin;
        CameraSample cs = pixel_camera_sample(sampler_state, s);
        Ray ray = first_order_ray(params.camera, cs.film, cs.lens);
        uint shadowed;
        LightDraw draw = sample_draw(sampler_state, pixel_index, s);
        sum += shade_rasterized(ray, pixel_index, draw, rays, shadowed);
        added = 1u;
    } else {
        // Through the real lens when there is one (blocked rays add nothing but count as
        // samples; real_lens.glsl), else the thin lens with weight 1.
        for (uint s = pc.sample_begin; s < pc.sample_end; ++s) {
            CameraSample cs = pixel_camera_sample(sampler_state, s);
            Ray ray;
            float weight;
            if (generate_ray(params.camera, cs.film, cs.lens, ray, weight)) {
                sum += weight * shade(ray, sample_draw(sampler_state, pixel_index, s), rays);
            }
        }
        added = pc.sample_end - pc.sample_begin;
    }
    // w counts the samples added (exact in float up to 2^24): the preview divides by it.
    accum[slot] = vec4(sum, before.w + float(added));
    return rays;
}

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
        atomicAdd(rays_traced, group_rays);
    }
}
