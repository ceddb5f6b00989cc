#version 460
// Layout probe: reads every scalar of every shared struct through the kind of block the real
// shaders read it through (std140 uniform, std430 storage buffer, push constants) and stores it,
// in declaration order, so tests can check that each field is read where Rust wrote it
// (lensray-vulkan/src/probes/layouts.rs). The blocks, the store functions and layout_probe_all() are
// generated into interface.glsl from the list of shared structs (lensray-core/src/interface/shared.rs).
#define LENSRAY_LAYOUT_PROBE

layout(local_size_x = 1) in;

#include "interface.glsl"

void main() {
    layout_probe_all();
}
