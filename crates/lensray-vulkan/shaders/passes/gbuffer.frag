#version 460
// G-buffer pass, fragment stage: shading normal facing the viewer, albedo, linear view depth.

#include "raster_surface.glsl"

layout(push_constant) uniform PushBlock { RasterPush pc; };

layout(location = 0) in vec3 in_normal;
layout(location = 1) in float in_view_depth;
layout(location = 2) in vec3 in_world;
layout(location = 3) flat in vec3 in_albedo;

layout(location = 0) out vec4 out_normal;  // w = 1: covered
layout(location = 1) out vec4 out_albedo;
layout(location = 2) out float out_depth;

void main() {
    out_normal = vec4(viewer_facing_normal(pc, in_normal, in_world), 1.0);
    out_albedo = vec4(in_albedo, 1.0);
    out_depth = in_view_depth;
}
