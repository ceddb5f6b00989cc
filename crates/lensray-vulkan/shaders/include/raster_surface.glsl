// The surface a raster fragment sees, shared by the G-buffer pass and the view pass.
#ifndef LENSRAY_RASTER_SURFACE_GLSL
#define LENSRAY_RASTER_SURFACE_GLSL

#include "interface.glsl"

// The interpolated shading normal turned to face the viewer: the viewing direction runs along
// the axis (orthographic) or from the eye (perspective).
vec3 viewer_facing_normal(RasterPush raster, vec3 normal, vec3 world) {
    vec3 d = raster.forward.w > 0.5 ? raster.forward.xyz : world - raster.eye.xyz;
    vec3 ns = normalize(normal);
    return dot(ns, d) > 0.0 ? -ns : ns;
}

#endif
