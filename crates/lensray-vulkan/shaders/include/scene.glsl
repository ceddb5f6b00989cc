// The scene as the shaders see it (lensray-vulkan/src/core/conv.rs builds these arrays): every mesh
// concatenated, global vertex indices, one info word per triangle, materials.
// Include after the set's header (set_*.glsl), which declares the arrays (SceneGroup).
#ifndef LENSRAY_SCENE_GLSL
#define LENSRAY_SCENE_GLSL

#include "interface.glsl"

// The moment in the shutter's span of the sample being traced (camera.glsl's sample_moment,
// set by trace.comp for each sample): every ray of its path meets what moves where it is then,
// as the CPU reference's rays carry their sample's moment (reference/lighting.rs: LightDraw).
float trace_moment = 0.5;

// Moving vertex row `row`'s attribute `which` (0 position, 1 normal, 2 tangent) at
// trace_moment: linearly between the two steps around it (reference/steps.rs: between; the
// upload's layout: lensray-vulkan/src/upload/motion.rs).
vec4 moving_attribute(uint row, uint which) {
    float s = clamp(trace_moment, 0.0, 1.0) * float(MOTION_STEPS - 1u);
    uint k = min(uint(s), MOTION_STEPS - 2u);
    float f = s - float(k);
    uint first = (3u * row + which) * MOTION_STEPS + k;
    return motion_vertices[first] * (1.0 - f) + motion_vertices[first + 1u] * f;
}

// The row of vertex `i` among the moving ones (its position's w is -(row + 1)), or -1 where
// it stands still (w is 1).
int vertex_motion_row(uint i) {
    float w = positions[i].w;
    return w < 0.0 ? int(-w) - 1 : -1;
}

// Vertex `i`'s position, normal (w 0) and tangent, where trace_moment has them.
vec3 vertex_position(uint i) {
    int row = vertex_motion_row(i);
    return row < 0 ? positions[i].xyz : moving_attribute(uint(row), 0u).xyz;
}
vec4 vertex_normal(uint i) {
    int row = vertex_motion_row(i);
    return row < 0 ? normals[i] : moving_attribute(uint(row), 1u);
}
vec4 vertex_tangent(uint i) {
    int row = vertex_motion_row(i);
    return row < 0 ? tangents[i] : moving_attribute(uint(row), 2u);
}

uint triangle_material(uint tri) { return tri_info[tri] & TRI_MATERIAL_MASK; }
bool triangle_has_normals(uint tri) { return (tri_info[tri] & TRI_HAS_NORMALS) != 0u; }
bool triangle_single_sided(uint tri) { return (tri_info[tri] & TRI_SINGLE_SIDED) != 0u; }

// Geometric normal: normalize(cross(v1 - v0, v2 - v0)).
vec3 triangle_geometric_normal(uint tri) {
    vec3 v0 = vertex_position(indices[3u * tri]);
    vec3 v1 = vertex_position(indices[3u * tri + 1u]);
    vec3 v2 = vertex_position(indices[3u * tri + 2u]);
    return normalize(cross(v1 - v0, v2 - v0));
}

#endif
