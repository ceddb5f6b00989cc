// The hit interface (see shading.glsl) answered by traceRayEXT against the scene's TLAS
// (lensray-vulkan/src/scene/accel.rs: one BLAS per mesh, instance custom index = the mesh's
// first triangle), the same structures and alpha test as hit_rayquery.glsl: the closest-hit
// ray's hit group (rt_hit.rchit, rt_hit.rahit) returns the hit, its miss stage (rt_miss.rmiss)
// that there is none; the shadow ray's (rt_shadow.rahit, rt_shadow.rmiss) whether anything stops
// it. The including shader is the ray generation stage: it enables GL_EXT_ray_tracing and
// declares the trace set's bindings.
#ifndef LENSRAY_HIT_RTPIPELINE_GLSL
#define LENSRAY_HIT_RTPIPELINE_GLSL

#include "rt_payloads.glsl"

layout(location = RT_RAY_CLOSEST) rayPayloadEXT ClosestPayload closest_payload;
layout(location = RT_RAY_SHADOW) rayPayloadEXT ShadowPayload shadow_payload;

// Without alpha-tested surfaces every hit is opaque: the traversal need not run any-hit stages.
// With single-sided surfaces the rays cull back faces: only single-sided meshes' instances
// let them (the others are marked TRIANGLE_FACING_CULL_DISABLE, scene/accel.rs), so a ray that
// meets a single-sided triangle from behind passes through it, as on the CPU reference.
uint surfaces_ray_flags() {
    uint cull = SURFACES_SINGLE_SIDED ? gl_RayFlagsCullBackFacingTrianglesEXT : gl_RayFlagsNoneEXT;
    return cull | (SURFACES_ALPHA_TESTED ? gl_RayFlagsNoneEXT : gl_RayFlagsOpaqueEXT);
}

// The closest hit with t in (0, t_max) that stops a ray cutting BLEND surfaces with `cut`: the
// global triangle index, t and the weights of v1, v2. Every geometry of a kind of ray takes the
// same record (stride 0).
bool closest_hit(vec3 origin, vec3 direction, float t_max, BlendCut cut, out Hit hit) {
    closest_payload.cut = cut;
    closest_payload.found = false;
    traceRayEXT(tlas, surfaces_ray_flags(), 0xFFu, RT_RAY_CLOSEST, 0u, RT_RAY_CLOSEST, origin,
                0.0, direction, t_max, int(RT_RAY_CLOSEST));
    if (!closest_payload.found) {
        return false;
    }
    hit.triangle = closest_payload.triangle;
    hit.t = closest_payload.t;
    hit.barycentrics = closest_payload.barycentrics;
    return true;
}

// Whether a surface that stops the ray lies along it with t in (0, t_max); the first ends the
// traversal, and no closest-hit stage runs.
bool occluded(vec3 origin, vec3 direction, float t_max, BlendCut cut) {
    shadow_payload.cut = cut;
    shadow_payload.occluded = true;
    uint flags = surfaces_ray_flags() | gl_RayFlagsTerminateOnFirstHitEXT
               | gl_RayFlagsSkipClosestHitShaderEXT;
    traceRayEXT(tlas, flags, 0xFFu, RT_RAY_SHADOW, 0u, RT_RAY_SHADOW, origin, 0.0, direction,
                t_max, int(RT_RAY_SHADOW));
    return shadow_payload.occluded;
}

#endif
