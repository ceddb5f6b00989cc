#version 460
// Mirror check of shaders/include/tonemap.glsl: for each linear colour its Khronos PBR Neutral
// and its AgX, so that tests can compare them with lensray-core/src/film/tonemap.rs.
#include "set_tonemap_probe.glsl"
#include "tonemap.glsl"

layout(local_size_x = PROBE_GROUP_SIZE) in;

layout(push_constant) uniform Push { uint count; } pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) {
        return;
    }
    vec3 c = queries[i].xyz;
    results[2u * i] = vec4(pbr_neutral(c), 0.0);
    results[2u * i + 1u] = vec4(agx(c), 0.0);
}
