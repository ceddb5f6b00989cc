#version 460
// Mirror check: evaluates shaders/include/sampler.glsl and shaders/include/camera.glsl for a list of queries so
// tests can compare them with lensray-core/src/sampler.rs and lensray-core/src/camera bit for bit.
#include "interface.glsl"
#include "set_mirror_probe.glsl"
#include "camera.glsl"
#include "sampler.glsl"

layout(local_size_x = PROBE_GROUP_SIZE) in;

// struct ProbeQuery and ProbeResult: the generated interface.glsl.

layout(push_constant) uniform Push { uint count; } pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) {
        return;
    }
    ProbeQuery q = queries[i];
    ProbeResult r;
    r.hash = hash_u32(q.hash_input);
    r.key = sample_key(q.seed, q.pixel_y * q.width + q.pixel_x, q.sample_index);
    r.sample_bits = floatBitsToUint(sample_1d(r.key, q.dim));
    r.lens = lens_index(q.hash_input);
    r.scrambled = owen_scramble_reversed(q.hash_input, q.seed);
    r.shuffled = shuffle_index(q.hash_input, q.seed);
    r.sobol = sobol_reversed(q.dim % 2u, q.hash_input);
    uint pixel_index = q.pixel_y * q.width + q.pixel_x;
    r.dimension_bits = floatBitsToUint(
        sample_dimension(q.sampler_kind, q.seed, pixel_index, q.sample_index, q.dim));
    CameraSample cs = camera_sample(q.sampler_kind, q.seed, uvec2(q.pixel_x, q.pixel_y), q.width,
                                    q.sample_index);
    r.camera_sample = vec4(cs.film, cs.lens);
    Ray ray = first_order_ray(cam, cs);
    r.origin = vec4(ray.origin, 1.0);
    r.direction = vec4(ray.direction, 0.0);
    r.lens_point = vec4(lens_point(cam, cs.lens), 0.0, 0.0);
    Ray through;
    float weight;
    bool passed = generate_ray(cam, cs, q.wavelength_nm, through, weight);
    r.through_lens_origin = vec4(through.origin, passed ? weight : -1.0);
    r.through_lens_direction = vec4(through.direction, 0.0);
    results[i] = r;
}
