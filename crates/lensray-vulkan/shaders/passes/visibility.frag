#version 460
// Raster path, visibility pass: the triangle seen at the pixel centre, + 1 (0: nothing). The
// shading pass (trace.comp, TRACE_MODE_RASTER) shades it along the sample's lens ray.

layout(location = 0) flat in uint in_triangle;
layout(location = 0) out uint out_triangle;

void main() {
    out_triangle = in_triangle + 1u;
}
