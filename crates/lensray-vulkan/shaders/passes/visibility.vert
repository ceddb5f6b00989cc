#version 460
// Raster path, visibility pass (lensray-vulkan/src/passes/visibility.rs): pulls triangle corners from the scene
// arrays (non-indexed draw of 3 vertices per triangle) and projects them through one lens point
// with Camera::clip_from_world_through_lens. The triangle index goes to the fragment stage as a
// flat varying (gl_PrimitiveID there would need the geometry-shader feature). Its PLAIN_SURFACES
// build passes no texture coordinates (raster_surface.glsl).
#include "set_visibility.glsl"
#include "scene.glsl"
#include "texture.glsl"

layout(push_constant) uniform PushBlock { VisibilityPush pc; };

layout(location = 0) flat out uint out_triangle;
#ifndef PLAIN_SURFACES
layout(location = 1) out vec4 out_texcoords;  // xy: set 0, zw: set 1
#endif

void main() {
    uint tri = uint(gl_VertexIndex) / 3u;
    uint corner = uint(gl_VertexIndex) % 3u;
    uint index = indices[3u * tri + corner];
    vec3 p = positions[index].xyz;
    out_triangle = tri;
#ifndef PLAIN_SURFACES
    out_texcoords = vertex_texcoords(index);
#endif
    gl_Position = pc.clip_from_world * vec4(p, 1.0);
}
