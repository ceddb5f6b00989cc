#version 460
// View pass, fragment stage: the preview's non-final views (albedo, normal, depth, circle of
// confusion) drawn straight into the window image, one 8-bit target instead of the G-buffer's
// three float targets and the resolve pass. The vertex stage is the G-buffer's (gbuffer.vert),
// so each fragment has the values the G-buffer would store and shows what resolve.comp would
// show for them (views.glsl).

#include "set_view.glsl"
#include "raster_surface.glsl"
#include "views.glsl"

layout(push_constant) uniform PushBlock { ViewPush pc; };

layout(location = 0) in vec3 in_normal;
layout(location = 1) in float in_view_depth;
layout(location = 2) in vec3 in_world;
layout(location = 3) flat in uint in_triangle;
layout(location = 4) in vec2 in_texcoord;
layout(location = 5) flat in vec3 in_albedo;

layout(location = 0) out vec4 out_shown;

void main() {
    // As gbuffer.frag; the footprint only where a texture is shown.
    bool textured = SURFACES_TEXTURED && pc.shown.view == VIEW_ALBEDO;
    vec2 dx = vec2(0.0);
    vec2 dy = vec2(0.0);
    if (textured) {
        fragment_footprint(pc.raster.clip_from_world, in_world, in_triangle, dx, dy);
    }
    if (SURFACES_ALPHA_TESTED
        && !fragment_stops_ray(in_triangle, in_texcoord, aperture_centre_cut())) {
        discard;
    }
    vec3 shown;
    if (pc.shown.view == VIEW_ALBEDO) {
        vec3 albedo = textured ? fragment_albedo(in_triangle, in_texcoord, dx, dy) : in_albedo;
        shown = encode_srgb(albedo);
    } else if (pc.shown.view == VIEW_NORMAL) {
        shown = normal_shown(vec4(viewer_facing_normal(pc.raster, in_normal, in_world), 1.0));
    } else if (pc.shown.view == VIEW_DEPTH) {
        shown = depth_shown(pc.shown, in_view_depth);
    } else {
        shown = coc_shown(pc.shown, gl_FragCoord.xy, in_view_depth);
    }
    out_shown = display_value(shown);
}
