// Mirror of lensray-core/src/scene/texture/mod.rs (lookups), scene/material.rs (colours and
// alpha) and camera/footprint.rs (the pinhole's pixel footprint), function by function: the
// texels are a storage buffer read with the CPU's arithmetic, so every path filters as the CPU
// reference does. `precise` keeps the compiler from fusing what Rust rounds twice. Include after
// scene.glsl (the set's header declares the arrays).
#ifndef LENSRAY_TEXTURE_GLSL
#define LENSRAY_TEXTURE_GLSL

#include "sampler.glsl"
#include "scene.glsl"

// Texture reads sit in loops marked [[dont_unroll]]: lavapipe inlines every call and compiles
// each copy of the filtering and decoding with LLVM, which made the textured trace variants
// take minutes (docs/testing.md, "Where CI's time goes").
#extension GL_EXT_control_flow_attributes : require

// The SURFACE_* bits any surface the shader meets may have. A pass specialized without one
// (SPEC_SURFACES) compiles out its texture or alpha code, which CPU drivers would otherwise run
// for every fragment or hit: they run both sides of a branch that may differ between
// invocations. Unspecialized: all. The raster stages' PLAIN_SURFACES build (build.rs) draws
// surfaces with none of them (raster_surface.glsl).
#ifdef PLAIN_SURFACES
const uint SURFACES = 0u;
#else
layout(constant_id = SPEC_SURFACES) const uint SURFACES =
    SURFACE_TEXTURED | SURFACE_ALPHA_TESTED | SURFACE_SINGLE_SIDED;
#endif
const bool SURFACES_TEXTURED = (SURFACES & SURFACE_TEXTURED) != 0u;
const bool SURFACES_ALPHA_TESTED = (SURFACES & SURFACE_ALPHA_TESTED) != 0u;
const bool SURFACES_SINGLE_SIDED = (SURFACES & SURFACE_SINGLE_SIDED) != 0u;

// texture/mod.rs: srgb_to_linear
float srgb_to_linear(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

// texture/mod.rs: decode_texel
vec4 decode_texel(uint texel, bool srgb) {
    vec4 v = vec4(float(texel & 0xffu), float((texel >> 8u) & 0xffu),
                  float((texel >> 16u) & 0xffu), float(texel >> 24u)) / 255.0;
    if (srgb) {
        v.xyz = vec3(srgb_to_linear(v.x), srgb_to_linear(v.y), srgb_to_linear(v.z));
    }
    return v;
}

// texture/mod.rs: wrap_texel, for the coordinates reduce_coordinate leaves: -1 ..= 2 size.
int wrap_texel(int i, int size, uint wrap) {
    if (wrap == WRAP_CLAMP_TO_EDGE) {
        return clamp(i, 0, size - 1);
    }
    int period = wrap == WRAP_REPEAT ? size : 2 * size;
    int m = i < 0 ? i + period : (i >= period ? i - period : i);
    return (wrap == WRAP_REPEAT || m < size) ? m : 2 * size - 1 - m;
}

// texture/mod.rs: reduce
float reduce_coordinate(float c, uint wrap) {
    if (isnan(c)) {
        return 0.0;
    }
    if (wrap == WRAP_REPEAT) {
        return c - floor(c);
    }
    if (wrap == WRAP_MIRRORED_REPEAT) {
        precise float twice = 2.0 * floor(0.5 * c);
        return c - twice;
    }
    return clamp(c, -1.0, 2.0);
}

// glam's lerp: a (1 - f) + b f.
vec4 lerp4(vec4 a, vec4 b, float f) {
    precise vec4 v = a * (1.0 - f) + b * f;
    return v;
}

vec4 level_texel(Texture t, uint level, int width, int x, int y) {
    uint first = t.level_first[level / 4u][level % 4u];
    return decode_texel(texels[first + uint(y) * uint(width) + uint(x)], t.srgb != 0u);
}

// texture/mod.rs: Texture::bilinear
vec4 texture_bilinear(Texture t, uint level, vec2 uv, uint wrap_u, uint wrap_v) {
    int w = int(max(t.width >> level, 1u));
    int h = int(max(t.height >> level, 1u));
    precise float x = reduce_coordinate(uv.x, wrap_u) * float(w) - 0.5;
    precise float y = reduce_coordinate(uv.y, wrap_v) * float(h) - 0.5;
    float x0 = floor(x);
    float y0 = floor(y);
    precise float fx = x - x0;
    precise float fy = y - y0;
    int xa = wrap_texel(int(x0), w, wrap_u);
    int xb = wrap_texel(int(x0) + 1, w, wrap_u);
    int ya = wrap_texel(int(y0), h, wrap_v);
    int yb = wrap_texel(int(y0) + 1, h, wrap_v);
    // The four texels in one loop the compiler keeps: one copy of the decoding (below).
    vec4 c[4];
    [[dont_unroll]] for (uint k = 0u; k < 4u; ++k) {
        c[k] = level_texel(t, level, w, (k & 1u) == 0u ? xa : xb, (k & 2u) == 0u ? ya : yb);
    }
    vec4 top = lerp4(c[0], c[1], fx);
    vec4 bottom = lerp4(c[2], c[3], fx);
    return lerp4(top, bottom, fy);
}

// texture/mod.rs: Texture::level_of_detail
float texture_level_of_detail(Texture t, vec2 duv_dx, vec2 duv_dy) {
    vec2 size = vec2(float(t.width), float(t.height));
    precise vec2 x = duv_dx * size;
    precise vec2 y = duv_dy * size;
    precise float longest = max(x.x * x.x + x.y * x.y, y.x * y.x + y.y * y.y);
    // No footprint (a surface met after a bounce): the finest level, as Rust's log2(0) = -inf
    // clamps to; GLSL leaves log2(0) undefined.
    return longest > 0.0 ? 0.5 * log2(longest) : 0.0;
}

// texture/mod.rs: Texture::trilinear
vec4 texture_trilinear(Texture t, vec2 uv, float lod, uint wrap_u, uint wrap_v) {
    float last = float(t.levels - 1u);
    lod = isnan(lod) ? 0.0 : clamp(lod, 0.0, last);
    float l0 = floor(lod);
    precise float f = lod - l0;
    // Both levels in one loop the compiler keeps (below).
    uint levels = f == 0.0 ? 1u : 2u;
    vec4 v[2];
    [[dont_unroll]] for (uint k = 0u; k < levels; ++k) {
        v[k] = texture_bilinear(t, uint(l0) + k, uv, wrap_u, wrap_v);
    }
    return levels == 1u ? v[0] : lerp4(v[0], v[1], f);
}

// A point's texture coordinate sets (texture/mod.rs: TexcoordSets) travel as one vec4: xy set 0,
// zw set 1; so do their footprints (FootprintSets).

// texture/mod.rs: TextureRef::texcoord
vec2 texture_texcoord(TextureRef r, vec4 texcoords) {
    return r.texcoord_set == 1u ? texcoords.zw : texcoords.xy;
}

// Both sets of vertex `index`; (0, 0) in set 1 past its array's end (no mesh has the set).
vec4 vertex_texcoords(uint index) {
    vec2 second = index < uint(texcoords1.length()) ? texcoords1[index] : vec2(0.0);
    return vec4(texcoords[index], second);
}

// Affine2::transform_point2 and its matrix alone.
vec2 texture_uv(TextureRef r, vec2 texcoord) {
    precise vec2 uv = vec2(r.transform_u.x * texcoord.x + r.transform_u.y * texcoord.y + r.transform_u.z,
                           r.transform_v.x * texcoord.x + r.transform_v.y * texcoord.y + r.transform_v.z);
    return uv;
}
vec2 texture_duv(TextureRef r, vec2 d) {
    precise vec2 duv = vec2(r.transform_u.x * d.x + r.transform_u.y * d.y,
                            r.transform_v.x * d.x + r.transform_v.y * d.y);
    return duv;
}

// texture/mod.rs: sample
vec4 texture_sample(TextureRef r, vec4 texcoords, vec4 dx, vec4 dy) {
    Texture t = textures[r.texture];
    vec2 set_dx = texture_texcoord(r, dx);
    vec2 set_dy = texture_texcoord(r, dy);
    float lod = texture_level_of_detail(t, texture_duv(r, set_dx), texture_duv(r, set_dy));
    vec2 uv = texture_uv(r, texture_texcoord(r, texcoords));
    return texture_trilinear(t, uv, lod, r.wrap_u, r.wrap_v);
}

// texture/mod.rs: sample_finest
vec4 texture_sample_finest(TextureRef r, vec4 texcoords) {
    vec2 uv = texture_uv(r, texture_texcoord(r, texcoords));
    return texture_bilinear(textures[r.texture], 0u, uv, r.wrap_u, r.wrap_v);
}

// footprint.rs: Footprint::dp_along
const float FOOTPRINT_EDGE_ON = 1e30;
vec3 footprint_dp_along(Footprint f, vec3 p, vec3 n, vec3 step) {
    vec3 forward = f.forward.xyz;
    if (f.eye.w > 0.5) {
        precise float t = -dot(n, step) / dot(n, forward);
        precise vec3 dp = step + t * forward;
        return (any(isnan(dp)) || any(isinf(dp))) ? vec3(FOOTPRINT_EDGE_ON) : dp;
    }
    precise vec3 to_p = p - f.eye.xyz;
    precise vec3 d = to_p / dot(to_p, forward) + step;
    precise float t = dot(n, to_p) / dot(n, d);
    return (t > 0.0 && !isinf(t)) ? t * d - to_p : vec3(FOOTPRINT_EDGE_ON);
}

// surface.rs: SurfaceData::texcoord_footprints, each set's TexcoordFootprint::on_triangle
// (texture/mod.rs); out: the footprints along x and along y.
void triangle_texcoord_footprint(uint tri, vec3 dpdx, vec3 dpdy, out vec4 dx, out vec4 dy) {
    uint i0 = indices[3u * tri];
    uint i1 = indices[3u * tri + 1u];
    uint i2 = indices[3u * tri + 2u];
    vec3 e1 = vertex_position(i1) - vertex_position(i0);
    vec3 e2 = vertex_position(i2) - vertex_position(i0);
    vec4 c0 = vertex_texcoords(i0);
    vec4 t1 = vertex_texcoords(i1) - c0;
    vec4 t2 = vertex_texcoords(i2) - c0;
    float g11 = dot(e1, e1);
    float g12 = dot(e1, e2);
    float g22 = dot(e2, e2);
    precise float det = g11 * g22 - g12 * g12;
    if (det == 0.0 || isinf(det) || isnan(det)) {
        dx = vec4(0.0);
        dy = vec4(0.0);
        return;
    }
    float r1 = dot(e1, dpdx);
    float r2 = dot(e2, dpdx);
    dx = (g22 * r1 - g12 * r2) / det * t1 + (g11 * r2 - g12 * r1) / det * t2;
    r1 = dot(e1, dpdy);
    r2 = dot(e2, dpdy);
    dy = (g22 * r1 - g12 * r2) / det * t1 + (g11 * r2 - g12 * r1) / det * t2;
}

// surface.rs: SurfaceData::texcoords
vec4 triangle_texcoords(uint tri, vec2 b) {
    vec4 t0 = vertex_texcoords(indices[3u * tri]);
    vec4 t1 = vertex_texcoords(indices[3u * tri + 1u]);
    vec4 t2 = vertex_texcoords(indices[3u * tri + 2u]);
    precise vec4 t = (1.0 - b.x - b.y) * t0 + b.x * t1 + b.y * t2;
    return t;
}

bool has_texture(TextureRef r) { return r.texture != TEXTURE_NONE; }

// The textures of a material that shading reads, one slot each (material_texels). Each
// material_*_with below combines a slot's texel (vec4(1.0) where the material has no texture)
// with the material's factors, as material.rs does.
const uint TEXEL_DIFFUSE = 0u;
const uint TEXEL_METALLIC_ROUGHNESS = 1u;
const uint TEXEL_CLEARCOAT = 2u;
const uint TEXEL_CLEARCOAT_ROUGHNESS = 3u;
const uint TEXEL_TRANSMISSION = 4u;
const uint TEXEL_SHEEN_COLOUR = 5u;
const uint TEXEL_SHEEN_ROUGHNESS = 6u;
const uint TEXEL_EMISSION = 7u;
const uint TEXEL_OCCLUSION = 8u;
const uint TEXEL_CLEARCOAT_NORMAL = 9u;
const uint TEXEL_NORMAL = 10u;
const uint MATERIAL_TEXEL_SLOTS = 11u;

// The texture of `m` in `slot` (TEXEL_*).
TextureRef material_texture(Material m, uint slot) {
    switch (slot) {
    case TEXEL_DIFFUSE: return m.diffuse_texture;
    case TEXEL_METALLIC_ROUGHNESS: return m.metallic_roughness_texture;
    case TEXEL_CLEARCOAT: return m.clearcoat_texture;
    case TEXEL_CLEARCOAT_ROUGHNESS: return m.clearcoat_roughness_texture;
    case TEXEL_TRANSMISSION: return m.transmission_texture;
    case TEXEL_SHEEN_COLOUR: return m.sheen_colour_texture;
    case TEXEL_SHEEN_ROUGHNESS: return m.sheen_roughness_texture;
    case TEXEL_EMISSION: return m.emission_texture;
    case TEXEL_OCCLUSION: return m.occlusion_texture;
    case TEXEL_CLEARCOAT_NORMAL: return m.clearcoat_normal_texture;
    default: return m.normal_texture;
    }
}

// material.rs: Material::diffuse_at
vec3 material_diffuse_with(Material m, vec4 texel) {
    return has_texture(m.diffuse_texture) ? m.diffuse.xyz * texel.xyz : m.diffuse.xyz;
}
vec3 material_diffuse(Material m, vec4 texcoords, vec4 dx, vec4 dy) {
    if (!has_texture(m.diffuse_texture)) {
        return m.diffuse.xyz;
    }
    return material_diffuse_with(m, texture_sample(m.diffuse_texture, texcoords, dx, dy));
}

// material.rs: Material::emission_at
bool material_emission_textured(Material m) {
    return has_texture(m.emission_texture) && m.emission.xyz != vec3(0.0);
}
vec3 material_emission_with(Material m, vec4 texel) {
    return material_emission_textured(m) ? m.emission.xyz * texel.xyz : m.emission.xyz;
}

// material.rs: Material::metallic_roughness_at; x: metallic, y: roughness.
vec2 material_metallic_roughness_with(Material m, vec4 texel) {
    vec2 factors = vec2(m.metallic, m.roughness);
    return has_texture(m.metallic_roughness_texture) ? factors * texel.zy : factors;
}

// material.rs: Material::occlusion_at
float material_occlusion_with(Material m, vec4 texel) {
    return has_texture(m.occlusion_texture) ? 1.0 + m.occlusion_strength * (texel.x - 1.0) : 1.0;
}

// material.rs: Material::clearcoat_at; `weight`, `roughness`: the slots' texels.
vec2 material_clearcoat_with(Material m, vec4 weight_texel, vec4 roughness_texel) {
    float weight = m.clearcoat;
    if (has_texture(m.clearcoat_texture) && m.clearcoat > 0.0) {
        weight = m.clearcoat * weight_texel.x;
    }
    float roughness = m.clearcoat_roughness;
    if (has_texture(m.clearcoat_roughness_texture) && weight > 0.0) {
        roughness = m.clearcoat_roughness * roughness_texel.y;
    }
    return vec2(weight, roughness);
}

// material.rs: Material::transmission_at
float material_transmission_with(Material m, vec4 texel) {
    if (has_texture(m.transmission_texture) && m.transmission > 0.0) {
        return m.transmission * texel.x;
    }
    return m.transmission;
}

// material.rs: Material::sheen_at; xyz: the colour, w: the roughness.
vec4 material_sheen_with(Material m, vec4 colour_texel, vec4 roughness_texel) {
    vec3 colour = m.sheen_colour.xyz;
    if (has_texture(m.sheen_colour_texture) && max(max(colour.x, colour.y), colour.z) > 0.0) {
        colour = m.sheen_colour.xyz * colour_texel.xyz;
    }
    float roughness = m.sheen_colour.w;
    if (has_texture(m.sheen_roughness_texture) && max(max(colour.x, colour.y), colour.z) > 0.0) {
        roughness = m.sheen_colour.w * roughness_texel.w;
    }
    return vec4(colour, roughness);
}

// material.rs: Material::is_textured
bool material_is_textured(Material m) {
    return has_texture(m.diffuse_texture) || has_texture(m.emission_texture)
        || has_texture(m.metallic_roughness_texture) || has_texture(m.occlusion_texture)
        || has_texture(m.normal_texture) || has_texture(m.clearcoat_texture)
        || has_texture(m.clearcoat_roughness_texture) || has_texture(m.sheen_colour_texture)
        || has_texture(m.sheen_roughness_texture) || has_texture(m.transmission_texture)
        || has_texture(m.clearcoat_normal_texture);
}

// material.rs: Material::alpha_at
float material_alpha(Material m, vec4 texcoords) {
    if (!has_texture(m.alpha_texture)) {
        return m.diffuse.w;
    }
    return m.diffuse.w * texture_sample_finest(m.alpha_texture, texcoords).w;
}

// How a ray cuts BLEND surfaces: a draw per surface from its key (`scene::ray_key`), or, for
// the aperture-centre ray of the AOVs, the fixed AOV_BLEND_THRESHOLD.
struct BlendCut {
    uint key;
    bool fixed_threshold;
};

BlendCut ray_cut(uint key) { return BlendCut(key, false); }
BlendCut aperture_centre_cut() { return BlendCut(0u, true); }
// The shadow ray's cut of a camera ray's (reference/render.rs: the shadow key).
BlendCut shadow_cut(BlendCut camera) {
    return BlendCut(camera.key ^ BLEND_CAMERA_SALT ^ BLEND_SHADOW_SALT, camera.fixed_threshold);
}

// material.rs: blend_threshold
float blend_threshold(uint key, uint tri) { return unit_float(hash_u32(key ^ hash_u32(tri))); }

// material.rs: Material::stops_ray, for a surface of alpha-tested `material` (the global
// triangle `tri`) at `texcoords`.
bool material_stops_ray(uint material, uint tri, vec4 texcoords, BlendCut cut) {
    Material m = materials[material];
    float alpha = material_alpha(m, texcoords);
    if (m.alpha_mode == ALPHA_MASK) {
        return alpha >= m.emission.w;
    }
    float threshold = cut.fixed_threshold ? AOV_BLEND_THRESHOLD : blend_threshold(cut.key, tri);
    return alpha > threshold;
}

// Whether global triangle `tri` stops the ray at barycentrics `b` (reference/render.rs: stops).
bool triangle_stops_ray(uint tri, vec2 b, BlendCut cut) {
    uint material = triangle_material(tri);
    if (materials[material].alpha_mode == ALPHA_OPAQUE) {
        return true;
    }
    return material_stops_ray(material, tri, triangle_texcoords(tri, b), cut);
}

#endif
