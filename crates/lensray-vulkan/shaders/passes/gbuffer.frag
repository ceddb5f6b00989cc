#version 460
// G-buffer pass, fragment stage: shading normal facing the viewer, albedo (textured), linear view
// depth; fragments an alpha test removes from the aperture-centre ray are discarded.
#include "set_gbuffer.glsl"
#include "raster_surface.glsl"

layout(push_constant) uniform PushBlock { RasterPush pc; };

layout(location = 0) in vec3 in_normal;
layout(location = 1) in float in_view_depth;
layout(location = 2) in vec3 in_world;
layout(location = 3) flat in uint in_triangle;
layout(location = 4) in vec2 in_texcoord;
layout(location = 5) flat in vec3 in_albedo;  // the material's untextured diffuse colour

layout(location = 0) out vec4 out_normal;  // w = 1: covered
layout(location = 1) out vec4 out_albedo;
layout(location = 2) out float out_depth;

void main() {
    // The footprint before the discard: its derivatives need the whole quad.
    vec2 dx = vec2(0.0);
    vec2 dy = vec2(0.0);
    if (SURFACES_TEXTURED) {
        fragment_footprint(pc.clip_from_world, in_world, in_triangle, dx, dy);
    }
    if (SURFACES_ALPHA_TESTED
        && !fragment_stops_ray(in_triangle, in_texcoord, aperture_centre_cut())) {
        discard;
    }
    out_normal = vec4(viewer_facing_normal(pc, in_normal, in_world), 1.0);
    vec3 albedo = SURFACES_TEXTURED ? fragment_albedo(in_triangle, in_texcoord, dx, dy) : in_albedo;
    out_albedo = vec4(albedo, 1.0);
    out_depth = in_view_depth;
}
