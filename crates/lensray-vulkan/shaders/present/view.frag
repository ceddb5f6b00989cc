#version 460
// View pass, fragment stage: the preview's non-final views (albedo, normal, depth, circle of
// confusion) drawn straight into the window image, one 8-bit target instead of the G-buffer's
// three float targets and the resolve pass. The vertex stage is the G-buffer's (gbuffer.vert),
// so each fragment has the values the G-buffer would store and shows what resolve.comp would
// show for them (views.glsl). One build per view (SHOWN_*, build.rs), each with only the inputs
// that view reads (surface_varyings.glsl): what a CPU driver spends on a fragment grows with the
// inputs it declares, not with the code a view leaves out.

#include "set_view.glsl"
#include "raster_surface.glsl"
#include "surface_varyings.glsl"
#include "views.glsl"

layout(push_constant) uniform PushBlock { ViewPush pc; };

#if defined(SHOWN_ALBEDO)
const uint VIEW = VIEW_ALBEDO;
#elif defined(SHOWN_NORMAL)
const uint VIEW = VIEW_NORMAL;
#elif defined(SHOWN_DEPTH)
const uint VIEW = VIEW_DEPTH;
#elif defined(SHOWN_COC)
const uint VIEW = VIEW_COC;
#else
#error "view.frag is built once per view: define SHOWN_ALBEDO, SHOWN_NORMAL, SHOWN_DEPTH or SHOWN_COC"
#endif

layout(location = 0) out vec4 out_shown;

void main() {
    // As gbuffer.frag; the footprint only where a texture is shown.
    bool textured = SURFACES_TEXTURED && VIEW == VIEW_ALBEDO;
    vec4 dx = vec4(0.0);
    vec4 dy = vec4(0.0);
    if (textured) {
        fragment_footprint(pc.raster.clip_from_world, v_world, v_triangle, dx, dy);
    }
    if (SURFACES_ALPHA_TESTED
        && !fragment_stops_ray(v_triangle, v_texcoords, aperture_centre_cut())) {
        discard;
    }
    vec3 shown;
    if (VIEW == VIEW_ALBEDO) {
        vec3 albedo = textured ? fragment_albedo(v_triangle, v_texcoords, dx, dy, v_world) : v_albedo;
        shown = encode_srgb(albedo);
    } else if (VIEW == VIEW_NORMAL) {
        shown = normal_shown(vec4(viewer_facing_normal(pc.raster, v_normal, v_world), 1.0));
    } else if (VIEW == VIEW_DEPTH) {
        shown = depth_shown(pc.shown, v_view_depth);
    } else {
        shown = coc_shown(pc.shown, gl_FragCoord.xy, v_view_depth);
    }
    out_shown = display_value(shown);
}
