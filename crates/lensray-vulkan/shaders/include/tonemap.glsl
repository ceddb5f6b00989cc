// The tone maps of the preview's final view: the GLSL mirror of lensray-core/src/film/tonemap.rs
// (the reference; tests/tonemap.rs compares the two on the device), statement by statement,
// with the constants of lensray-interface (TONEMAP_*, NEUTRAL_*, AGX_*).
#ifndef LENSRAY_TONEMAP_GLSL
#define LENSRAY_TONEMAP_GLSL

#include "interface.glsl"

// tonemap.rs: non_negative (NaN reads as 0 there; GLSL's max leaves NaN to the driver).
vec3 tonemap_non_negative(vec3 c) {
    return vec3(isnan(c.x) ? 0.0 : max(c.x, 0.0), isnan(c.y) ? 0.0 : max(c.y, 0.0),
                isnan(c.z) ? 0.0 : max(c.z, 0.0));
}

// tonemap.rs: pbr_neutral. Khronos PBR Neutral (github.com/KhronosGroup/ToneMapping,
// PBR_Neutral/pbrNeutral.glsl, PBRNeutralToneMapping).
vec3 pbr_neutral(vec3 color) {
    color = tonemap_non_negative(color);
    const float start_compression = NEUTRAL_START_COMPRESSION;
    const float desaturation = NEUTRAL_DESATURATION;

    float x = min(color.r, min(color.g, color.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color -= offset;

    float peak = max(color.r, max(color.g, color.b));
    if (peak < start_compression) {
        return color;
    }

    const float d = 1.0 - start_compression;
    float new_peak = 1.0 - d * d / (peak + d - start_compression);
    color *= new_peak / peak;

    float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(color, vec3(new_peak), g);
}

// A mat3 of nine floats, column by column.
mat3 tonemap_mat3(const float m[9]) {
    return mat3(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8]);
}

// tonemap.rs: agx_sigmoid (three.js's agxDefaultContrastApprox).
vec3 agx_sigmoid(vec3 x) {
    vec3 x2 = x * x;
    vec3 x4 = x2 * x2;
    return AGX_SIGMOID[0] * x4 * x2 + AGX_SIGMOID[1] * x4 * x + AGX_SIGMOID[2] * x4
        + AGX_SIGMOID[3] * x2 * x + AGX_SIGMOID[4] * x2 + AGX_SIGMOID[5] * x + AGX_SIGMOID[6];
}

// tonemap.rs: agx. AgX as three.js writes it (tonemapping_pars_fragment.glsl.js, AgXToneMapping).
vec3 agx(vec3 color) {
    color = tonemap_mat3(AGX_SRGB_TO_REC2020) * tonemap_non_negative(color);
    color = tonemap_mat3(AGX_INSET) * color;
    color = max(color, vec3(1e-10));
    color = log2(color);
    color = (color - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
    color = clamp(color, 0.0, 1.0);
    color = agx_sigmoid(color);
    color = tonemap_mat3(AGX_OUTSET) * color;
    color = max(color, vec3(0.0));
    color = pow(color, vec3(2.2));
    color = tonemap_mat3(AGX_REC2020_TO_SRGB) * color;
    return clamp(color, 0.0, 1.0);
}

// tonemap.rs: ToneMap::apply; `tonemap` is TONEMAP_*.
vec3 tone_map(vec3 c, uint tonemap) {
    if (tonemap == TONEMAP_NEUTRAL) {
        return pbr_neutral(c);
    } else if (tonemap == TONEMAP_AGX) {
        return agx(c);
    }
    return c;
}

// tonemap.rs: Display::map.
vec3 display_mapped(vec3 c, float exposure, uint tonemap) {
    return tone_map(c * exposure, tonemap);
}

#endif
