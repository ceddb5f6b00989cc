// The surface a raster fragment sees, shared by the G-buffer pass, the view pass and the
// visibility pass. Declare SCENE_SET before including.
#ifndef LENSRAY_RASTER_SURFACE_GLSL
#define LENSRAY_RASTER_SURFACE_GLSL

#include "interface.glsl"
#include "sampler.glsl"
#include "scene.glsl"
#include "texture.glsl"

// The interpolated shading normal turned to face the viewer: the viewing direction runs along
// the axis (orthographic) or from the eye (perspective).
vec3 viewer_facing_normal(RasterPush raster, vec3 normal, vec3 world) {
    vec3 d = raster.forward.w > 0.5 ? raster.forward.xyz : world - raster.eye.xyz;
    vec3 ns = normalize(normal);
    return dot(ns, d) > 0.0 ? -ns : ns;
}

// Whether the fragment of triangle `tri` at `texcoord` is there for a ray cutting BLEND
// surfaces with `cut` (the alpha test; a fragment that is not is discarded).
bool fragment_stops_ray(uint tri, vec2 texcoord, BlendCut cut) {
    uint material = triangle_material(tri);
    return materials[material].alpha_mode == ALPHA_OPAQUE
        || material_stops_ray(material, tri, texcoord, cut);
}

// The diffuse colour of triangle `tri` at `texcoord`, filtered over the fragment's footprint:
// the G-buffer is the pinhole's image, so its derivatives are the pinhole's pixel footprint
// (the traced paths compute the same footprint from the camera, texture.glsl).
vec3 fragment_albedo(uint tri, vec2 texcoord, vec2 dx, vec2 dy) {
    return material_diffuse(materials[triangle_material(tri)], texcoord, dx, dy);
}

#endif
