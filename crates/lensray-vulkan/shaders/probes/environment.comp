#version 460
// Mirror check of shaders/include/environment.glsl: for each query a sample drawn by its point
// and a lookup of its direction, so that tests can compare them with
// lensray-core/src/scene/environment.
#include "set_environment_probe.glsl"
#include "environment.glsl"

layout(local_size_x = PROBE_GROUP_SIZE) in;

layout(push_constant) uniform Push { uint count; } pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) {
        return;
    }
    vec2 u = env_queries[2u * i].xy;
    vec3 d = env_queries[2u * i + 1u].xyz;
    uint at = i * ENVIRONMENT_PROBE_RESULT_FLOATS;
    vec3 direction = vec3(0.0);
    float pdf = 0.0;
    uvec2 texel = uvec2(0u);
    bool drawn = env_sample(u, direction, pdf, texel);
    vec3 radiance = drawn ? env_texel(texel) : vec3(0.0);
    env_results[at] = direction.x;
    env_results[at + 1u] = direction.y;
    env_results[at + 2u] = direction.z;
    env_results[at + 3u] = drawn ? pdf : 0.0;
    env_results[at + 4u] = radiance.x;
    env_results[at + 5u] = radiance.y;
    env_results[at + 6u] = radiance.z;
    env_results[at + 7u] = drawn ? float(texel.x + texel.y * environment.width) : -1.0;
    vec2 uv = env_uv_from_world(d);
    vec3 looked_up = env_radiance(d);
    env_results[at + 8u] = env_pdf(d);
    env_results[at + 9u] = looked_up.x;
    env_results[at + 10u] = looked_up.y;
    env_results[at + 11u] = looked_up.z;
    env_results[at + 12u] = uv.x;
    env_results[at + 13u] = uv.y;
    env_results[at + 14u] = 0.0;
    env_results[at + 15u] = 0.0;
}
