// Mirror of src/sampler.rs, function by function. 32-bit integer arithmetic only, so every value
// equals the CPU's bit for bit.
#ifndef LENSRAY_SAMPLER_GLSL
#define LENSRAY_SAMPLER_GLSL

const uint DIM_FILM_X = 0u;
const uint DIM_FILM_Y = 1u;
const uint DIM_LENS_X = 2u;
const uint DIM_LENS_Y = 3u;
const uint DIM_FIRST_FREE = 4u;

uint hash_u32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

uint sample_key(uint seed, uint pixel_index, uint sample_index) {
    return hash_u32(hash_u32(hash_u32(seed) ^ pixel_index) ^ sample_index);
}

float unit_float(uint bits) {
    return float(bits >> 8) * (1.0 / 16777216.0);
}

float sample_1d(uint key, uint dim) {
    return unit_float(hash_u32(key ^ (dim * 0x9e3779b9u)));
}

struct CameraSample {
    vec2 film;
    vec2 lens;
};

CameraSample camera_sample(uint seed, uvec2 pixel, uint width, uint sample_index) {
    uint key = sample_key(seed, pixel.y * width + pixel.x, sample_index);
    CameraSample s;
    s.film = vec2(float(pixel.x) + sample_1d(key, DIM_FILM_X),
                  float(pixel.y) + sample_1d(key, DIM_FILM_Y));
    s.lens = vec2(sample_1d(key, DIM_LENS_X), sample_1d(key, DIM_LENS_Y));
    return s;
}

#endif
