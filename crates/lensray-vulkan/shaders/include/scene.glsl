// The scene as the shaders see it (lensray-vulkan/src/core/conv.rs builds these arrays): every mesh
// concatenated, global vertex indices, one info word per triangle, materials.
// Include after the set's header (set_*.glsl), which declares the arrays (SceneGroup).
#ifndef LENSRAY_SCENE_GLSL
#define LENSRAY_SCENE_GLSL

#include "interface.glsl"

uint triangle_material(uint tri) { return tri_info[tri] & TRI_MATERIAL_MASK; }
bool triangle_has_normals(uint tri) { return (tri_info[tri] & TRI_HAS_NORMALS) != 0u; }
bool triangle_single_sided(uint tri) { return (tri_info[tri] & TRI_SINGLE_SIDED) != 0u; }

// Geometric normal: normalize(cross(v1 - v0, v2 - v0)).
vec3 triangle_geometric_normal(uint tri) {
    vec3 v0 = positions[indices[3u * tri]].xyz;
    vec3 v1 = positions[indices[3u * tri + 1u]].xyz;
    vec3 v2 = positions[indices[3u * tri + 2u]].xyz;
    return normalize(cross(v1 - v0, v2 - v0));
}

#endif
