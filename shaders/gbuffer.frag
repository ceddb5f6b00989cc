#version 460
// G-buffer pass, fragment stage: shading normal facing the viewer, albedo, linear view depth.

#include "interface.glsl"

layout(push_constant) uniform PushBlock { RasterPush pc; };

layout(location = 0) in vec3 in_normal;
layout(location = 1) in float in_view_depth;
layout(location = 2) in vec3 in_world;
layout(location = 3) flat in vec3 in_albedo;

layout(location = 0) out vec4 out_normal;  // w = 1: covered
layout(location = 1) out vec4 out_albedo;
layout(location = 2) out float out_depth;

void main() {
    // The viewing direction: along the axis (orthographic) or from the eye (perspective).
    vec3 d = pc.forward.w > 0.5 ? pc.forward.xyz : in_world - pc.eye.xyz;
    vec3 ns = normalize(in_normal);
    if (dot(ns, d) > 0.0) {
        ns = -ns;
    }
    out_normal = vec4(ns, 1.0);
    out_albedo = vec4(in_albedo, 1.0);
    out_depth = in_view_depth;
}
