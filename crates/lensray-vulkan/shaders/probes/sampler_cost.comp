#version 460
// The cost of sample generation alone: trace.comp's per-pixel sample loop with the ray
// generation and tracing left out. The sums are written so that nothing is optimised away.
#include "set_sampler_cost.glsl"
#include "sampler.glsl"

layout(local_size_x = TRACE_GROUP_SIZE, local_size_y = TRACE_GROUP_SIZE) in;

layout(push_constant) uniform PushBlock { SamplerCostPush pc; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= pc.width || pixel.y >= pc.height) {
        return;
    }
    vec4 sum = vec4(0.0);
    for (uint s = 0u; s < pc.spp; ++s) {
        CameraSample cs = camera_sample(pc.sampler_kind, pc.seed, pixel, pc.width, s);
        sum += vec4(cs.film, cs.lens);
    }
    sums[pixel.y * pc.width + pixel.x] = sum;
}
