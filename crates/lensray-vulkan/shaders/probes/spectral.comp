#version 460
// Mirror check of shaders/include/spectral.glsl: for each query (u, a wavelength) the wavelength
// of u, the weight at that wavelength and the weight at the given one, so that tests can compare
// them with lensray-core/src/film/spectral.rs bit for bit.
#include "set_spectral_probe.glsl"
#include "spectral.glsl"

layout(local_size_x = PROBE_GROUP_SIZE) in;

layout(push_constant) uniform Push { uint count; } pc;

void write_matrix(uint at, mat3 m) {
    for (uint c = 0u; c < 3u; ++c) {
        for (uint r = 0u; r < 3u; ++r) {
            results[at + 3u * c + r] = m[c][r];
        }
    }
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) {
        return;
    }
    vec2 q = queries[i];
    uint at = i * SPECTRAL_PROBE_RESULT_FLOATS;
    float lambda = sample_wavelength(q.x);
    results[at] = lambda;
    results[at + 1u] = float(wavelength_interval(q.x));
    write_matrix(at + 2u, rgb_weights(lambda));
    write_matrix(at + 11u, rgb_weights(q.y));
}
