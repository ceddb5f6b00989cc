// What the G-buffer's vertex stage (passes/gbuffer.vert) passes to the fragment stages of the
// G-buffer pass (passes/gbuffer.frag) and the view pass (present/view.frag): each value only in
// the builds whose fragment stage reads it, since lavapipe interpolates every input a fragment
// stage declares, read or not, and validation warns of an output that no stage reads. A value
// left out is a constant in the fragment stage (nothing reads it there) and a variable the
// compiler drops in the vertex stage. Both stages of a pipeline are built with the same macros
// (build.rs):
//   SHOWN_ALBEDO, SHOWN_NORMAL, SHOWN_DEPTH, SHOWN_COC: the view pass's view (none: the G-buffer
//     pass, which stores every value);
//   PLAIN_SURFACES: surfaces without a texture or an alpha test (raster_surface.glsl): no
//     triangle index or texture coordinates.
// Define VERTEX_STAGE in the vertex stage before including.
#ifndef LENSRAY_SURFACE_VARYINGS_GLSL
#define LENSRAY_SURFACE_VARYINGS_GLSL

#if !defined(SHOWN_ALBEDO) && !defined(SHOWN_NORMAL) && !defined(SHOWN_DEPTH) && !defined(SHOWN_COC)
#define STORES_ALL
#endif
#if defined(STORES_ALL) || defined(SHOWN_NORMAL)
#define READS_NORMAL
#endif
#if defined(STORES_ALL) || defined(SHOWN_DEPTH) || defined(SHOWN_COC)
#define READS_VIEW_DEPTH
#endif
// The normal faces the viewer from the world point; a texture's footprint is found there too.
#if defined(STORES_ALL) || defined(SHOWN_NORMAL) || (defined(SHOWN_ALBEDO) && !defined(PLAIN_SURFACES))
#define READS_WORLD
#endif
#if !defined(PLAIN_SURFACES)
#define READS_SURFACE
#endif
#if defined(STORES_ALL) || defined(SHOWN_ALBEDO)
#define READS_ALBEDO
#endif

#ifdef VERTEX_STAGE
#define VARYING out
#define LEFT_OUT(type, name) type name
#else
#define VARYING in
#define LEFT_OUT(type, name) const type name = type(0)
#endif

#ifdef READS_NORMAL
layout(location = 0) VARYING vec3 v_normal;  // vertex normal (or ng), interpolated
#else
LEFT_OUT(vec3, v_normal);
#endif
#ifdef READS_VIEW_DEPTH
layout(location = 1) VARYING float v_view_depth;  // camera-space z, perspective-correct
#else
LEFT_OUT(float, v_view_depth);
#endif
#ifdef READS_WORLD
layout(location = 2) VARYING vec3 v_world;
#else
LEFT_OUT(vec3, v_world);
#endif
#ifdef READS_SURFACE
layout(location = 3) flat VARYING uint v_triangle;
layout(location = 4) VARYING vec4 v_texcoords;  // xy: set 0, zw: set 1
#else
LEFT_OUT(uint, v_triangle);
LEFT_OUT(vec4, v_texcoords);
#endif
#ifdef READS_ALBEDO
layout(location = 5) flat VARYING vec3 v_albedo;  // the material's untextured diffuse colour
#else
LEFT_OUT(vec3, v_albedo);
#endif

#endif
