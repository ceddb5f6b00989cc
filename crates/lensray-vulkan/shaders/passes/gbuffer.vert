#version 460
// G-buffer pass, vertex stage: pulls triangle corners from the scene arrays (non-indexed draw of
// 3 vertices per triangle) and projects them with the Rust camera's clip_from_world(). The view
// pass draws with it too; each build passes what its fragment stage reads (surface_varyings.glsl).
#include "set_gbuffer.glsl"
#define VERTEX_STAGE
#include "scene.glsl"
#include "texture.glsl"
#include "surface_varyings.glsl"

layout(push_constant) uniform PushBlock { RasterPush pc; };

void main() {
    uint tri = uint(gl_VertexIndex) / 3u;
    uint corner = uint(gl_VertexIndex) % 3u;
    uint index = indices[3u * tri + corner];
    vec3 p = positions[index].xyz;
#ifdef READS_NORMAL
    v_normal = triangle_has_normals(tri) ? normals[index].xyz : triangle_geometric_normal(tri);
#endif
#ifdef READS_SURFACE
    v_triangle = tri;
    v_texcoords = vertex_texcoords(index);
#endif
    v_albedo = materials[triangle_material(tri)].diffuse.xyz;
    v_view_depth = dot(p - pc.eye.xyz, pc.forward.xyz);
    v_world = p;
    gl_Position = pc.clip_from_world * vec4(p, 1.0);
}
