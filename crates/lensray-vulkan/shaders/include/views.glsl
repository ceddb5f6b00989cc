// What the preview shows of a surface, one function per view: the encodings of lensray-core/src/film/colour.rs
// (PNG): sRGB colours, 0.5 n + 0.5 normals, depth scaled by the far plane, and the circle of
// confusion from the thin-lens formula. resolve.comp applies them to the G-buffer's images,
// view.frag to a fragment's values, so both routes show the same bytes.
#ifndef LENSRAY_VIEWS_GLSL
#define LENSRAY_VIEWS_GLSL

#include "camera.glsl"

// output.rs: linear_to_srgb
float linear_to_srgb(float c) {
    if (isnan(c) || c <= 0.0) {
        return 0.0;
    } else if (c <= 0.0031308) {
        return 12.92 * c;
    }
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

vec3 encode_srgb(vec3 c) {
    return vec3(linear_to_srgb(c.x), linear_to_srgb(c.y), linear_to_srgb(c.z));
}

// normal.w = 1 where a surface covers the pixel.
vec3 normal_shown(vec4 normal) {
    return normal.w > 0.5 ? 0.5 * normal.xyz + 0.5 : vec3(0.0);
}

vec3 depth_shown(ViewParams v, float depth) {
    return vec3(depth / v.far_z);
}

// Grey from 0 (sharp) to white at COC_DISPLAY_MAX pixels, pixels sharper than half a pixel in
// green (what the plane of focus cuts). Depth 0: no surface. `p_raster`: the pixel's centre.
vec3 coc_shown(ViewParams v, vec2 p_raster, float depth) {
    if (depth <= 0.0) {
        return vec3(0.0);
    }
    float coc = coc_radius_pixels(v.coc, p_raster, depth);
    return coc < 0.5 ? vec3(0.1, 0.8, 0.2) : vec3(clamp(coc / COC_DISPLAY_MAX, 0.0, 1.0));
}

// What an 8-bit target stores.
vec4 display_value(vec3 shown) {
    return vec4(clamp(shown, 0.0, 1.0), 1.0);
}

#endif
