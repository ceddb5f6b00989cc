// What the ray-tracing pipeline's rays carry between the ray generation (trace.comp,
// hit_rtpipeline.glsl) and the hit and miss stages (passes/rt_hit.*, passes/rt_miss.rmiss): the
// closest-hit ray's answer as the ray-query hit function gives it, and the shadow ray's. Both
// carry the ray's BLEND cut to the any-hit stage's alpha test. The including shader enables
// GL_EXT_ray_tracing and includes texture.glsl (BlendCut).
#ifndef LENSRAY_RT_PAYLOADS_GLSL
#define LENSRAY_RT_PAYLOADS_GLSL

// Location RT_RAY_CLOSEST.
struct ClosestPayload {
    BlendCut cut;
    bool found;
    // Where found: the global triangle index, t and the weights of v1, v2.
    uint triangle;
    float t;
    vec2 barycentrics;
};

// Location RT_RAY_SHADOW.
struct ShadowPayload {
    BlendCut cut;
    // Set before the trace; its miss stage clears it.
    bool occluded;
};

#endif
