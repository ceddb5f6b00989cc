#version 460
// The preview's display: per pixel, the thin-lens accumulation (sum / samples, exposed, tone
// mapped and sRGB-encoded: tonemap.glsl, as a PNG's pixels) or a G-buffer view, written to an 8-bit image that is then copied to the window. Pixels the
// accumulation has not reached yet show the G-buffer's albedo (the pinhole view) meanwhile.
// The encodings are views.glsl's.

#include "set_resolve.glsl"
#include "views.glsl"
#include "tonemap.glsl"

layout(local_size_x = RESOLVE_GROUP_SIZE, local_size_y = RESOLVE_GROUP_SIZE) in;

layout(push_constant) uniform PushBlock { ResolvePush pc; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.width || p.y >= pc.height) {
        return;
    }
    ivec2 q = ivec2(p);
    // Each view loads only the images it needs (lavapipe pays for every load).
    vec3 shown;
    if (pc.shown.view == VIEW_FINAL) {
        vec4 a = accum[p.y * pc.width + p.x];
        // Pixels the accumulation has not reached yet show the pinhole albedo meanwhile (a
        // reflectance: not exposed, as a PNG of the albedo view).
        vec3 linear = a.xyz / a.w;
        if (pc.flare != 0u) {
            linear += flare[p.y * pc.width + p.x].xyz;
        }
        shown = encode_srgb(a.w > 0.0 ? display_mapped(linear, pc.exposure, pc.tonemap)
                                      : imageLoad(g_albedo, q).xyz);
    } else if (pc.shown.view == VIEW_ALBEDO) {
        shown = encode_srgb(imageLoad(g_albedo, q).xyz);
    } else if (pc.shown.view == VIEW_NORMAL) {
        shown = normal_shown(imageLoad(g_normal, q));
    } else if (pc.shown.view == VIEW_DEPTH) {
        shown = depth_shown(pc.shown, imageLoad(g_depth, q).x);
    } else {
        shown = coc_shown(pc.shown, vec2(p) + 0.5, imageLoad(g_depth, q).x);
    }
    imageStore(display, q, display_value(shown));
}
