// The scene as the shaders see it (lensray-vulkan/src/core/conv.rs builds these arrays): every mesh
// concatenated, global vertex indices, one info word per triangle, materials.
// Declare SCENE_SET before including; bindings SCENE_BINDING_* of that set.
#ifndef LENSRAY_SCENE_GLSL
#define LENSRAY_SCENE_GLSL

#include "interface.glsl"

layout(std430, set = SCENE_SET, binding = SCENE_BINDING_POSITIONS) readonly buffer Positions {
    vec4 positions[];
};
layout(std430, set = SCENE_SET, binding = SCENE_BINDING_NORMALS) readonly buffer Normals {
    vec4 normals[];
};
layout(std430, set = SCENE_SET, binding = SCENE_BINDING_INDICES) readonly buffer Indices {
    uint indices[];
};
layout(std430, set = SCENE_SET, binding = SCENE_BINDING_TRI_INFO) readonly buffer TriInfo {
    uint tri_info[];
};
layout(std430, set = SCENE_SET, binding = SCENE_BINDING_MATERIALS) readonly buffer Materials {
    Material materials[];
};

uint triangle_material(uint tri) { return tri_info[tri] & ~TRI_HAS_NORMALS; }
bool triangle_has_normals(uint tri) { return (tri_info[tri] & TRI_HAS_NORMALS) != 0u; }

// Geometric normal: normalize(cross(v1 - v0, v2 - v0)).
vec3 triangle_geometric_normal(uint tri) {
    vec3 v0 = positions[indices[3u * tri]].xyz;
    vec3 v1 = positions[indices[3u * tri + 1u]].xyz;
    vec3 v2 = positions[indices[3u * tri + 2u]].xyz;
    return normalize(cross(v1 - v0, v2 - v0));
}

#endif
