// The emissive triangles as lights, mirroring lensray-core's scene/emitters.rs (the distribution,
// uploaded by lensray-vulkan's upload/emitters.rs) and reference/emitters.rs function by
// function. Include after the set's header, scene.glsl and texture.glsl.
#ifndef LENSRAY_EMITTERS_GLSL
#define LENSRAY_EMITTERS_GLSL

// reference/integrator.rs: trace_paths' `!self.emitters.is_empty()` (a scene without
// emitters holds one cdf of 0).
bool emitters_light() {
    return emitter_cdf[emitter_cdf.length() - 1] > 0.0;
}

// scene/emitters.rs: EmitterDistribution::pick and pick: the triangle u.x draws (the first cdf
// entry above it) and u with its x rescaled to [0, 1) within that entry's share.
uint emitter_pick(vec2 u, out vec2 rescaled) {
    uint n = uint(emitter_cdf.length());
    uint low_index = 0u;
    uint high_index = n;
    while (low_index < high_index) {
        uint mid = (low_index + high_index) / 2u;
        if (emitter_cdf[mid] <= u.x) {
            low_index = mid + 1u;
        } else {
            high_index = mid;
        }
    }
    uint i = min(low_index, n - 1u);
    float low = i == 0u ? 0.0 : emitter_cdf[i - 1u];
    float width = emitter_cdf[i] - low;
    float x = width > 0.0 ? (u.x - low) / width : 0.0;
    // 1 - f32::EPSILON
    rescaled = vec2(clamp(x, 0.0, 0.99999988), u.y);
    return emitter_triangles[i];
}

// scene/emitters.rs: uniform_barycentric
vec2 uniform_barycentric(vec2 u) {
    float s = sqrt(u.x);
    return vec2(1.0 - s, u.y * s);
}

// scene/emitters.rs: uniform_point (the position; `b` its barycentrics)
vec3 uniform_point(uint tri, vec2 u, out vec2 b) {
    b = uniform_barycentric(u);
    vec3 v0 = positions[indices[3u * tri]].xyz;
    vec3 v1 = positions[indices[3u * tri + 1u]].xyz;
    vec3 v2 = positions[indices[3u * tri + 2u]].xyz;
    return (1.0 - b.x - b.y) * v0 + b.x * v1 + b.y * v2;
}

// reference/emitters.rs: Renderer::emitter_pdf (scene/emitters.rs: EmitterDistribution::pdf)
float emitter_pdf(uint tri, vec3 d, float distance) {
    float area_pdf = tri < uint(emitter_area_pdf.length()) ? emitter_area_pdf[tri] : 0.0;
    float cosine = abs(dot(triangle_geometric_normal(tri), d));
    if (area_pdf == 0.0 || cosine == 0.0) {
        return 0.0;
    }
    return area_pdf * distance * distance / cosine;
}

// reference/emitters.rs: Renderer::emission_towards
vec3 emission_towards(uint tri, vec2 b, vec3 d) {
    if (triangle_single_sided(tri) && dot(d, triangle_geometric_normal(tri)) > 0.0) {
        return vec3(0.0);
    }
    Material mat = materials[triangle_material(tri)];
    if (SURFACES_TEXTURED && material_is_textured(mat)) {
        // No footprint: the finest level, which a trilinear read without one takes.
        vec4 texcoords = triangle_texcoords(tri, b);
        return material_emission_textured(mat)
            ? material_emission_with(mat, texture_sample_finest(mat.emission_texture, texcoords))
            : mat.emission.xyz;
    }
    return mat.emission.xyz;
}

#endif
