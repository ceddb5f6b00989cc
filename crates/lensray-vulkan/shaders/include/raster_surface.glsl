// The surface a raster fragment sees, shared by the G-buffer pass, the view pass and the
// visibility pass. Include after the set's header (set_*.glsl).
#ifndef LENSRAY_RASTER_SURFACE_GLSL
#define LENSRAY_RASTER_SURFACE_GLSL

#include "interface.glsl"
#include "sampler.glsl"
#include "scene.glsl"
#include "texture.glsl"
#include "surface_frame.glsl"

// SURFACES (texture.glsl) holds what every triangle of the draw may have: the raster passes
// draw each run of triangles with the pipeline specialized for its surfaces (passes/draw.rs).
// The runs with none of the pass's bits take the stages' PLAIN_SURFACES build (build.rs), which
// passes between them only what those surfaces read: no texture coordinates, and no triangle
// index where only textures and alpha tests read it (surface_varyings.glsl, visibility.frag).

// The interpolated shading normal turned to face the viewer: the viewing direction runs along
// the axis (orthographic) or from the eye (perspective).
vec3 viewer_facing_normal(RasterPush raster, vec3 normal, vec3 world) {
    vec3 d = raster.forward.w > 0.5 ? raster.forward.xyz : world - raster.eye.xyz;
    vec3 ns = normalize(normal);
    return dot(ns, d) > 0.0 ? -ns : ns;
}

// Whether the fragment of triangle `tri` at `texcoords` (both sets) is there for a ray cutting
// BLEND surfaces with `cut` (the alpha test; a fragment that is not is discarded).
bool fragment_stops_ray(uint tri, vec4 texcoords, BlendCut cut) {
    uint material = triangle_material(tri);
    return materials[material].alpha_mode == ALPHA_OPAQUE
        || material_stops_ray(material, tri, texcoords, cut);
}

// The point where the ray through clip-space point (x, y) (any depth) meets the plane through
// `p` with normal `n`.
vec3 plane_point_at(mat4 world_from_clip, vec2 xy, vec3 p, vec3 n) {
    vec4 a = world_from_clip * vec4(xy, 0.0, 1.0);
    vec4 b = world_from_clip * vec4(xy, 0.5, 1.0);
    vec3 origin = a.xyz / a.w;
    vec3 direction = b.xyz / b.w - origin;
    return origin + direction * (dot(n, p - origin) / dot(n, direction));
}

// The pinhole's pixel footprint at the fragment of triangle `tri` at world point `p`, in
// texture coordinates: the camera footprint (camera/footprint.rs) found from the pass's matrix,
// as where the rays through the neighbouring pixels meet the triangle's plane. The pixel step in
// clip space is the derivative of the fragment's own clip position, which is linear in the pixel
// (hardware derivatives of the texture coordinates would not be: they differ from pixel to pixel
// of a quad where the footprint grows fast).
void fragment_footprint(mat4 clip_from_world, vec3 p, uint tri, out vec4 dx, out vec4 dy) {
    vec4 c = clip_from_world * vec4(p, 1.0);
    vec2 xy = c.xy / c.w;
    vec2 step = vec2(dFdx(xy.x), dFdy(xy.y));
    mat4 world_from_clip = inverse(clip_from_world);
    vec3 n = triangle_geometric_normal(tri);
    vec3 dpdx = plane_point_at(world_from_clip, xy + vec2(step.x, 0.0), p, n) - p;
    vec3 dpdy = plane_point_at(world_from_clip, xy + vec2(0.0, step.y), p, n) - p;
    triangle_texcoord_footprint(tri, dpdx, dpdy, dx, dy);
}

// The diffuse colour of triangle `tri` at `texcoords` (both sets), filtered over the footprints
// (dx, dy), times the vertex colour at world point `p`.
vec3 fragment_albedo(uint tri, vec4 texcoords, vec4 dx, vec4 dy, vec3 p) {
    vec3 diffuse = material_diffuse(materials[triangle_material(tri)], texcoords, dx, dy);
    if (!triangle_has_colours(tri)) {
        return diffuse;
    }
    return vertex_coloured(diffuse, tri, triangle_barycentrics_at(tri, p));
}

#endif
