#version 460
#include "sampler.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) buffer Keys { uint v[]; } keys;
void main() { keys.v[gl_GlobalInvocationID.x] = hash_u32(keys.v[gl_GlobalInvocationID.x]); }
