#version 460
// G-buffer pass, fragment stage: shading normal facing the viewer, albedo (textured), linear view
// depth; fragments an alpha test removes from the aperture-centre ray are discarded.
#include "set_gbuffer.glsl"
#include "raster_surface.glsl"
#include "surface_varyings.glsl"

layout(push_constant) uniform PushBlock { RasterPush pc; };

layout(location = 0) out vec4 out_normal;  // w = 1: covered
layout(location = 1) out vec4 out_albedo;
layout(location = 2) out float out_depth;

void main() {
    // The footprint before the discard: its derivatives need the whole quad.
    vec4 dx = vec4(0.0);
    vec4 dy = vec4(0.0);
    if (SURFACES_TEXTURED) {
        fragment_footprint(pc.clip_from_world, v_world, v_triangle, dx, dy);
    }
    if (SURFACES_ALPHA_TESTED
        && !fragment_stops_ray(v_triangle, v_texcoords, aperture_centre_cut())) {
        discard;
    }
    out_normal = vec4(viewer_facing_normal(pc, v_normal, v_world), 1.0);
    vec3 albedo = SURFACES_TEXTURED ? fragment_albedo(v_triangle, v_texcoords, dx, dy, v_world) : v_albedo;
    out_albedo = vec4(albedo, 1.0);
    out_depth = v_view_depth;
}
