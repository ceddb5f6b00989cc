#version 460
// Thin-lens compute pass: spp camera samples per pixel, each traced and shaded as specified for
// every renderer (shading.glsl; src/render/settings.rs, the CPU reference). build.rs compiles it
// once per closest-hit implementation: TRAVERSAL_RAY_QUERY (ray queries against the TLAS,
// hit_rayquery.glsl) and TRAVERSAL_SOFTWARE (the project's own BVH, hit_software.glsl, no
// ray-tracing extension). One dispatch covers some rows (strided) and a range of samples; sums
// accumulate in `accum` (xyz: the sum, w: how many samples), which holds a band of rows of the
// image (bounded by the device's storage-buffer range).
#if defined(TRAVERSAL_RAY_QUERY)
#extension GL_EXT_ray_query : require
#elif !defined(TRAVERSAL_SOFTWARE)
#error "define TRAVERSAL_RAY_QUERY or TRAVERSAL_SOFTWARE"
#endif

#include "camera.glsl"
#include "sampler.glsl"
#define SCENE_SET 0
#include "scene.glsl"

layout(local_size_x = TRACE_GROUP_SIZE, local_size_y = TRACE_GROUP_SIZE) in;

layout(std430, set = 0, binding = TRACE_BINDING_ACCUM) buffer Accum { vec4 accum[]; };
layout(std430, set = 0, binding = TRACE_BINDING_COUNTERS) buffer Counters { uint rays_traced; };
layout(std140, set = 0, binding = TRACE_BINDING_PARAMS) uniform ParamsBlock { TraceParams params; };
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

void main() {
    uint x = gl_GlobalInvocationID.x;
    uint block = gl_WorkGroupID.y;
    uint band_row = (pc.block_first + block * pc.block_stride) * gl_WorkGroupSize.y
                  + gl_LocalInvocationID.y;
    uint y = pc.band_origin + band_row;
    if (x >= params.width || block >= pc.block_count || band_row >= pc.band_height) {
        return;
    }
    uint slot = band_row * params.width + x;
    vec4 before = accum[slot];
    vec3 sum = before.xyz;
    uint rays = 0u;
    for (uint s = pc.sample_begin; s < pc.sample_end; ++s) {
        CameraSample cs = camera_sample(params.sampler_kind, params.seed, uvec2(x, y), params.width, s);
        Ray ray = generate_ray(params.camera, cs.film, cs.lens);
        sum += shade(ray, rays);
    }
    // w counts the samples added (exact in float up to 2^24): the preview divides by it.
    accum[slot] = vec4(sum, before.w + float(pc.sample_end - pc.sample_begin));
    atomicAdd(rays_traced, rays);
}
