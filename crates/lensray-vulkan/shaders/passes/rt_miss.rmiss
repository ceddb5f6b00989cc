#version 460
// The ray-tracing pipeline's miss stage of the closest-hit ray and, with SHADOW_RAY, of the
// shadow ray (include/hit_rtpipeline.glsl): nothing stops the ray.
#extension GL_EXT_ray_tracing : require

#include "set_trace_rtpipeline.glsl"
#include "scene.glsl"
#include "texture.glsl"
#include "rt_payloads.glsl"

#if defined(SHADOW_RAY)
layout(location = RT_RAY_SHADOW) rayPayloadInEXT ShadowPayload payload;
#else
layout(location = RT_RAY_CLOSEST) rayPayloadInEXT ClosestPayload payload;
#endif

void main() {
#if defined(SHADOW_RAY)
    payload.occluded = false;
#else
    payload.found = false;
#endif
}
