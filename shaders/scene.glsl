// The scene as the shaders see it (src/gpu/conv.rs builds these arrays): every mesh
// concatenated, global vertex indices, one info word per triangle, materials.
// Declare SCENE_SET before including; bindings 0..4 of that set.
#ifndef LENSRAY_SCENE_GLSL
#define LENSRAY_SCENE_GLSL

// Bit 31 of a triangle's info word: its mesh has vertex normals. Bits 0..30: material.
const uint TRI_HAS_NORMALS = 0x80000000u;

struct Material {
    vec4 diffuse;   // Kd
    vec4 emission;  // Ke
};

layout(std430, set = SCENE_SET, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, set = SCENE_SET, binding = 1) readonly buffer Normals { vec4 normals[]; };
layout(std430, set = SCENE_SET, binding = 2) readonly buffer Indices { uint indices[]; };
layout(std430, set = SCENE_SET, binding = 3) readonly buffer TriInfo { uint tri_info[]; };
layout(std430, set = SCENE_SET, binding = 4) readonly buffer Materials { Material materials[]; };

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
