#version 460
// G-buffer pass, vertex stage: pulls triangle corners from the scene arrays (non-indexed draw of
// 3 vertices per triangle) and projects them with the Rust camera's clip_from_world().
#include "set_gbuffer.glsl"
#include "scene.glsl"
#include "texture.glsl"

layout(push_constant) uniform PushBlock { RasterPush pc; };

layout(location = 0) out vec3 out_normal;       // vertex normal (or ng), interpolated
layout(location = 1) out float out_view_depth;  // camera-space z, perspective-correct
layout(location = 2) out vec3 out_world;
layout(location = 3) flat out uint out_triangle;
layout(location = 4) out vec2 out_texcoord;
layout(location = 5) flat out vec3 out_albedo;  // untextured: the fragments' albedo

void main() {
    uint tri = uint(gl_VertexIndex) / 3u;
    uint corner = uint(gl_VertexIndex) % 3u;
    uint index = indices[3u * tri + corner];
    vec3 p = positions[index].xyz;
    vec3 ng = triangle_geometric_normal(tri);
    out_normal = triangle_has_normals(tri) ? normals[index].xyz : ng;
    out_triangle = tri;
    out_albedo = materials[triangle_material(tri)].diffuse.xyz;
    out_texcoord = texcoords[index];
    out_view_depth = dot(p - pc.eye.xyz, pc.forward.xyz);
    out_world = p;
    gl_Position = pc.clip_from_world * vec4(p, 1.0);
}
