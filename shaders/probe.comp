#version 460
// Mirror check: evaluates shaders/sampler.glsl and shaders/camera.glsl for a list of queries so
// tests can compare them with src/sampler.rs and src/camera bit for bit.
#include "camera.glsl"
#include "sampler.glsl"

layout(local_size_x = 64) in;

struct Query {
    uint seed;
    uint pixel_x;
    uint pixel_y;
    uint width;
    uint sample_index;
    uint dim;
    uint hash_input;
    uint sampler_kind;
};

struct Result {
    uint hash;          // hash_u32(hash_input)
    uint key;           // sample_key(seed, pixel_y * width + pixel_x, sample_index)
    uint sample_bits;   // floatBitsToUint(sample_1d(key, dim))
    uint lens;          // lens_index(hash_input)
    uint scrambled;     // owen_scramble_reversed(hash_input, seed)
    uint shuffled;      // shuffle_index(hash_input, seed)
    uint sobol;         // sobol_reversed(dim % 2, hash_input)
    uint dimension_bits; // floatBitsToUint(sample_dimension(sampler_kind, seed, pixel index, sample_index, dim))
    vec4 camera_sample; // film.xy, lens.xy of camera_sample(sampler_kind, seed, pixel, width, sample_index)
    vec4 origin;        // generate_ray(cam, film, lens)
    vec4 direction;
};

layout(std430, set = 0, binding = 0) readonly buffer Queries { Query queries[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Results { Result results[]; };
layout(std140, set = 0, binding = 2) uniform CameraBlock { Camera cam; };
layout(push_constant) uniform Push { uint count; } pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) {
        return;
    }
    Query q = queries[i];
    Result r;
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
    Ray ray = generate_ray(cam, cs.film, cs.lens);
    r.origin = vec4(ray.origin, 1.0);
    r.direction = vec4(ray.direction, 0.0);
    results[i] = r;
}
