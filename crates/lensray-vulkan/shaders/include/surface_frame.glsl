// Mirror of lensray-core/src/reference/surface_frame.rs, operation for operation: vertex colours,
// which multiply the base colour, the tangent frame in which a normal map tilts the shading
// normal, and the shading normal made safe for reflection. A triangle without colours or
// tangents costs the test of its flag (TRI_HAS_*). Include after texture.glsl.
#ifndef LENSRAY_SURFACE_FRAME_GLSL
#define LENSRAY_SURFACE_FRAME_GLSL

#include "scene.glsl"
#include "texture.glsl"

bool triangle_has_colours(uint tri) { return (tri_info[tri] & TRI_HAS_COLOURS) != 0u; }
bool triangle_has_tangents(uint tri) { return (tri_info[tri] & TRI_HAS_TANGENTS) != 0u; }

// surface.rs: interpolate, for vec4 corners.
vec4 interpolate4(vec4 a, vec4 b, vec4 c, vec2 w) {
    precise vec4 v = (1.0 - w.x - w.y) * a + w.x * b + w.y * c;
    return v;
}

// surface_frame.rs: vertex_coloured with SurfaceData::colour; `b`: the weights of v1, v2.
vec3 vertex_coloured(vec3 base, uint tri, vec2 b) {
    if (!triangle_has_colours(tri)) {
        return base;
    }
    vec4 c = interpolate4(colours[indices[3u * tri]], colours[indices[3u * tri + 1u]],
                          colours[indices[3u * tri + 2u]], b);
    return base * c.xyz;
}

// The weights of v1, v2 of the point `p` of triangle `tri`'s plane (the raster stages: the
// barycentrics of the fragment's world point).
vec2 triangle_barycentrics_at(uint tri, vec3 p) {
    vec3 v0 = positions[indices[3u * tri]].xyz;
    vec3 e1 = positions[indices[3u * tri + 1u]].xyz - v0;
    vec3 e2 = positions[indices[3u * tri + 2u]].xyz - v0;
    vec3 d = p - v0;
    float g11 = dot(e1, e1);
    float g12 = dot(e1, e2);
    float g22 = dot(e2, e2);
    float r1 = dot(d, e1);
    float r2 = dot(d, e2);
    float det = g11 * g22 - g12 * g12;
    return det == 0.0 ? vec2(0.0) : vec2(g22 * r1 - g12 * r2, g11 * r2 - g12 * r1) / det;
}

// surface_frame.rs: SurfaceData::normal_mapped, the `texel` of the map `map` (the base's or
// the clear coat's, read as colours() reads it) at its `scale`.
vec3 normal_mapped(TextureRef map, float scale, uint tri, vec2 b, vec3 ns, vec4 texel) {
    if (!has_texture(map) || !triangle_has_tangents(tri)) {
        return ns;
    }
    uint i0 = indices[3u * tri];
    uint i1 = indices[3u * tri + 1u];
    uint i2 = indices[3u * tri + 2u];
    vec3 n0;
    if (triangle_has_normals(tri)) {
        n0 = interpolate4(vertex_normal(i0), vertex_normal(i1), vertex_normal(i2), b).xyz;
    } else {
        vec3 v0 = vertex_position(i0);
        n0 = cross(vertex_position(i1) - v0, vertex_position(i2) - v0);
    }
    float s = dot(ns, n0) < 0.0 ? -1.0 : 1.0;
    vec4 t4 = interpolate4(vertex_tangent(i0), vertex_tangent(i1), vertex_tangent(i2), b);
    precise vec3 t = t4.xyz - ns * dot(ns, t4.xyz);
    precise float length_squared = dot(t, t);
    if (!(length_squared > 0.0) || isinf(length_squared)) {
        return ns;
    }
    t = t / sqrt(length_squared);
    float w = t4.w < 0.0 ? -1.0 : 1.0;
    vec3 bitangent = cross(ns, t) * w;
    vec3 v = texel.xyz * 2.0 - vec3(1.0);
    precise vec3 n = t * (s * v.x * scale) + bitangent * (v.y * scale) + ns * v.z;
    length_squared = dot(n, n);
    if (!(length_squared > 0.0) || isinf(length_squared)) {
        return ns;
    }
    return n / sqrt(length_squared);
}

// surface_frame.rs: reflection_safe_normal. `ng` faces the viewer, `v` points to it.
vec3 reflection_safe_normal(vec3 ng, vec3 v, vec3 n) {
    float v_z = dot(v, ng);
    float t = min(0.9 * v_z, REFLECTION_MIN_COSINE);
    float reflected_height = 2.0 * dot(n, v) * dot(n, ng) - v_z;
    if (reflected_height >= t || v_z <= 0.0) {
        return n;
    }
    vec3 across = n - ng * dot(n, ng);
    float length_squared = dot(across, across);
    if (!(length_squared > 0.0) || isinf(length_squared)) {
        return ng;
    }
    vec3 x_axis = across / sqrt(length_squared);
    float v_x = dot(v, x_axis);
    float a = v_x * v_x + v_z * v_z;
    float b = a + v_z * t;
    float c = (v_z + t) * (v_z + t);
    float root = sqrt(max(b * b - a * c, 0.0));
    float inv_2a = 0.5 / a;
    float s1 = clamp((b + root) * inv_2a, 0.0, 1.0);
    float s2 = clamp((b - root) * inv_2a, 0.0, 1.0);
    float z1 = sqrt(s1);
    float x1 = sqrt(1.0 - s1);
    float z2 = sqrt(s2);
    float x2 = sqrt(1.0 - s2);
    float r1 = abs(2.0 * x1 * z1 * v_x - (t + v_z * (1.0 - 2.0 * s1)));
    float r2 = abs(2.0 * x2 * z2 * v_x - (t + v_z * (1.0 - 2.0 * s2)));
    return r1 <= r2 ? x_axis * x1 + ng * z1 : x_axis * x2 + ng * z2;
}

#endif
