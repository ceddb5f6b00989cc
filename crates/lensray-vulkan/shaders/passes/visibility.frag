#version 460
// Raster path, visibility pass: the triangle seen at the pixel centre, + 1 (0: nothing). The
// shading pass (trace.comp, TRACE_MODE_RASTER) shades it along the sample's lens ray. Fragments
// the alpha test removes from the sample's camera ray (the key its traced twin has) are
// discarded, so the depth test keeps the nearest surface that stops the ray.
#include "set_visibility.glsl"
#include "raster_surface.glsl"

layout(push_constant) uniform PushBlock { VisibilityPush pc; };

layout(location = 0) flat in uint in_triangle;
#ifdef PLAIN_SURFACES
const vec4 in_texcoords = vec4(0.0);  // read by alpha tests only (raster_surface.glsl)
#else
layout(location = 1) in vec4 in_texcoords;
#endif
layout(location = 0) out uint out_triangle;

void main() {
    if (SURFACES_ALPHA_TESTED) {
        uint pixel_index = uint(gl_FragCoord.y) * pc.width + uint(gl_FragCoord.x);
        BlendCut cut = pc.aperture_centre != 0u
            ? aperture_centre_cut()
            : ray_cut(sample_key(pc.seed, pixel_index, pc.sample_index) ^ BLEND_CAMERA_SALT);
        if (!fragment_stops_ray(in_triangle, in_texcoords, cut)) {
            discard;
        }
    }
    out_triangle = in_triangle + 1u;
}
