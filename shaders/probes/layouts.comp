#version 460
// Layout probe: reads every scalar of each shared struct through the same kind of block the
// real shaders use (std140 uniform, std430 storage, push constants) and stores it, in
// declaration order, so tests can check that each field is read where Rust wrote it
// (src/gpu/layout_probe.rs). The store functions are generated with the structs.
#define LENSRAY_LAYOUT_PROBE

layout(local_size_x = 1) in;

#include "interface.glsl"

layout(std140, set = 0, binding = LAYOUT_PROBE_BINDING_PARAMS) uniform ParamsBlock {
    TraceParams params;
};
layout(std430, set = 0, binding = LAYOUT_PROBE_BINDING_RASTER) readonly buffer RasterBlock {
    RasterPush raster;
};
// Two materials: the second one's scalars check the array stride.
layout(std430, set = 0, binding = LAYOUT_PROBE_BINDING_MATERIALS) readonly buffer MaterialBlock {
    Material materials[2];
};
layout(std430, set = 0, binding = LAYOUT_PROBE_BINDING_RESOLVE) readonly buffer ResolveBlock {
    ResolvePush resolve;
};
// Two of each: the second one's scalars check the array stride.
layout(std430, set = 0, binding = LAYOUT_PROBE_BINDING_BVH) readonly buffer BvhBlock {
    BvhNode bvh_nodes[2];
    BvhTriangle bvh_triangles[2];
};
layout(push_constant) uniform PushBlock { TracePush pc; };

void main() {
    uint i = 0u;
    i = layout_probe_TraceParams(params, i);
    i = layout_probe_TracePush(pc, i);
    i = layout_probe_RasterPush(raster, i);
    i = layout_probe_Material(materials[0], i);
    i = layout_probe_Material(materials[1], i);
    i = layout_probe_ResolvePush(resolve, i);
    i = layout_probe_BvhNode(bvh_nodes[0], i);
    i = layout_probe_BvhNode(bvh_nodes[1], i);
    i = layout_probe_BvhTriangle(bvh_triangles[0], i);
    i = layout_probe_BvhTriangle(bvh_triangles[1], i);
}
