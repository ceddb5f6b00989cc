#version 460
// The ray-tracing pipeline's closest-hit stage (include/hit_rtpipeline.glsl): the hit as a ray
// query commits it, the global triangle index being `instance custom index + primitive index`.
#extension GL_EXT_ray_tracing : require

#include "set_trace_rtpipeline.glsl"
#include "scene.glsl"
#include "texture.glsl"
#include "rt_payloads.glsl"

layout(location = RT_RAY_CLOSEST) rayPayloadInEXT ClosestPayload payload;
hitAttributeEXT vec2 barycentrics;

void main() {
    payload.found = true;
    payload.triangle = uint(gl_InstanceCustomIndexEXT) + uint(gl_PrimitiveID);
    payload.t = gl_HitTEXT;
    payload.barycentrics = barycentrics;
}
