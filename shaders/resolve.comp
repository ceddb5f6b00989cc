#version 460
// The preview's display: per pixel, the thin-lens accumulation (sum / samples, sRGB-encoded) or
// a G-buffer view, written to an 8-bit image that is then copied to the window. Pixels the
// accumulation has not reached yet show the G-buffer's albedo (the pinhole view) meanwhile.
// The encodings are those of src/output.rs (PNG): sRGB colours, 0.5 n + 0.5 normals, depth
// scaled by the far plane.

#include "camera.glsl"

layout(local_size_x = RESOLVE_GROUP_SIZE, local_size_y = RESOLVE_GROUP_SIZE) in;

layout(std430, set = 0, binding = RESOLVE_BINDING_ACCUM) readonly buffer Accum { vec4 accum[]; };
layout(set = 0, binding = RESOLVE_BINDING_NORMAL, rgba32f) readonly uniform image2D g_normal;
layout(set = 0, binding = RESOLVE_BINDING_ALBEDO, rgba32f) readonly uniform image2D g_albedo;
layout(set = 0, binding = RESOLVE_BINDING_VIEW_DEPTH, r32f) readonly uniform image2D g_depth;
layout(set = 0, binding = RESOLVE_BINDING_DISPLAY, rgba8) writeonly uniform image2D display;
layout(push_constant) uniform PushBlock { ResolvePush pc; };

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

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.width || p.y >= pc.height) {
        return;
    }
    ivec2 q = ivec2(p);
    // Each view loads only the images it needs (lavapipe pays for every load).
    vec3 shown;
    if (pc.view == VIEW_FINAL) {
        vec4 a = accum[p.y * pc.width + p.x];
        // Pixels the accumulation has not reached yet show the pinhole albedo meanwhile.
        shown = encode_srgb(a.w > 0.0 ? a.xyz / a.w : imageLoad(g_albedo, q).xyz);
    } else if (pc.view == VIEW_ALBEDO) {
        shown = encode_srgb(imageLoad(g_albedo, q).xyz);
    } else if (pc.view == VIEW_NORMAL) {
        vec4 normal = imageLoad(g_normal, q);  // w = 1 where a surface covers the pixel
        shown = normal.w > 0.5 ? 0.5 * normal.xyz + 0.5 : vec3(0.0);
    } else if (pc.view == VIEW_DEPTH) {
        shown = vec3(imageLoad(g_depth, q).x / pc.far_z);
    } else {
        // Circle of confusion: grey from 0 (sharp) to white at coc_display_max pixels, pixels
        // sharper than half a pixel in green (what the focus plane cuts). Depth 0: no surface.
        float depth = imageLoad(g_depth, q).x;
        if (depth <= 0.0) {
            shown = vec3(0.0);
        } else {
            float coc = coc_radius_pixels(pc.projection, pc.aperture_radius, pc.focus_distance,
                                          pc.near_z, pc.pixels_per_screen_unit, depth);
            shown = coc < 0.5 ? vec3(0.1, 0.8, 0.2)
                              : vec3(clamp(coc / pc.coc_display_max, 0.0, 1.0));
        }
    }
    imageStore(display, q, vec4(clamp(shown, 0.0, 1.0), 1.0));
}
