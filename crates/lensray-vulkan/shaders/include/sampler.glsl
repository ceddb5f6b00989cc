// Mirror of lensray-core/src/sampler/ (mod.rs, hash.rs, independent.rs, owen.rs, sobol.rs,
// scrambled_sobol.rs), function by function. 32-bit integer arithmetic only, so every value
// equals the CPU's bit for bit. The generator matrices of sobol.rs are not needed here: the
// sampler uses the closed forms of the first two Sobol' dimensions (and quality.rs is analysis).
#ifndef LENSRAY_SAMPLER_GLSL
#define LENSRAY_SAMPLER_GLSL

// DIM_*, SAMPLER_* and LENS_INDEX_COLUMNS come from the generated interface.
#include "interface.glsl"

// hash.rs

uint hash_u32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

float unit_float(uint bits) {
    return float(bits >> 8) * (1.0 / 16777216.0);
}

// mod.rs

uint pixel_key(uint seed, uint pixel_index) {
    return hash_u32(hash_u32(seed) ^ pixel_index);
}

// independent.rs

uint sample_key(uint seed, uint pixel_index, uint sample_index) {
    return hash_u32(pixel_key(seed, pixel_index) ^ sample_index);
}

float sample_1d(uint key, uint dim) {
    return unit_float(hash_u32(key ^ (dim * 0x9e3779b9u)));
}

vec4 independent_sample(uint key, uint sample_index) {
    uint s = hash_u32(key ^ sample_index);
    return vec4(sample_1d(s, DIM_FILM_X), sample_1d(s, DIM_FILM_Y),
                sample_1d(s, DIM_LENS_X), sample_1d(s, DIM_LENS_Y));
}

// owen.rs

uint laine_karras_permutation(uint x, uint seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

uint owen_scramble_reversed(uint reversed, uint seed) {
    return bitfieldReverse(laine_karras_permutation(reversed, seed));
}

uint shuffle_index(uint index, uint seed) {
    return bitfieldReverse(laine_karras_permutation(bitfieldReverse(index), seed));
}

// sobol.rs

uint sobol_reversed(uint dim, uint index) {
    uint x = index;
    if (dim == 1u) {
        x ^= (x >> 1) & 0x55555555u;
        x ^= (x >> 2) & 0x33333333u;
        x ^= (x >> 4) & 0x0f0f0f0fu;
        x ^= (x >> 8) & 0x00ff00ffu;
        x ^= x >> 16;
    }
    return x;
}

uint lens_index(uint index) {
    uint lens = index & 0xffff0000u;
    for (uint bit = 0u; bit < 16u; ++bit) {
        lens ^= LENS_INDEX_COLUMNS[bit] & (0u - ((index >> bit) & 1u));
    }
    return lens;
}

// scrambled_sobol.rs

uint scramble_seed(uint pixel_key, uint dim) {
    return hash_u32(pixel_key ^ (dim * 0x9e3779b9u));
}

uint shuffle_seed(uint pixel_key, uint pair) {
    return hash_u32(scramble_seed(pixel_key, 2u * pair));
}

float sobol_1d(uint pixel_key, uint sample_index, uint dim) {
    uint pair = dim / 2u;
    uint index = pair == 0u ? sample_index
               : pair == 1u ? lens_index(sample_index)
                            : shuffle_index(sample_index, shuffle_seed(pixel_key, pair));
    return unit_float(owen_scramble_reversed(sobol_reversed(dim % 2u, index),
                                             scramble_seed(pixel_key, dim)));
}

struct SobolPixel {
    uint film_x;
    uint film_y;
    uint lens_x;
    uint lens_y;
};

SobolPixel sobol_pixel(uint pixel_key) {
    SobolPixel p;
    p.film_x = scramble_seed(pixel_key, DIM_FILM_X);
    p.film_y = scramble_seed(pixel_key, DIM_FILM_Y);
    p.lens_x = scramble_seed(pixel_key, DIM_LENS_X);
    p.lens_y = scramble_seed(pixel_key, DIM_LENS_Y);
    return p;
}

vec4 sobol_sample(SobolPixel pixel, uint sample_index) {
    uint lens = lens_index(sample_index);
    return vec4(unit_float(owen_scramble_reversed(sobol_reversed(0u, sample_index), pixel.film_x)),
                unit_float(owen_scramble_reversed(sobol_reversed(1u, sample_index), pixel.film_y)),
                unit_float(owen_scramble_reversed(sobol_reversed(0u, lens), pixel.lens_x)),
                unit_float(owen_scramble_reversed(sobol_reversed(1u, lens), pixel.lens_y)));
}

// mod.rs

float sample_dimension(uint kind, uint seed, uint pixel_index, uint sample_index, uint dim) {
    if (kind == SAMPLER_INDEPENDENT) {
        return sample_1d(sample_key(seed, pixel_index, sample_index), dim);
    }
    return sobol_1d(pixel_key(seed, pixel_index), sample_index, dim);
}

struct CameraSample {
    vec2 film;
    vec2 lens;
    // mod.rs: CameraSample::time (CAMERA_SAMPLE_MIDDLE while the camera is still).
    float time;
};

const float CAMERA_SAMPLE_MIDDLE = 0.5;

struct PixelSampler {
    uint kind;
    uvec2 pixel;
    uint key;
    SobolPixel sobol;
};

PixelSampler pixel_sampler(uint kind, uint seed, uvec2 pixel, uint width) {
    PixelSampler s;
    s.kind = kind;
    s.pixel = pixel;
    s.key = pixel_key(seed, pixel.y * width + pixel.x);
    s.sobol = kind == SAMPLER_SOBOL ? sobol_pixel(s.key) : SobolPixel(0u, 0u, 0u, 0u);
    return s;
}

// mod.rs: shared_pixel_sampler
PixelSampler shared_pixel_sampler(uint kind, uint seed, uvec2 pixel) {
    PixelSampler s = pixel_sampler(kind, seed, uvec2(0u), 1u);
    s.pixel = pixel;
    return s;
}

// mod.rs: pixel_dimension
float pixel_dimension(PixelSampler state, uint sample_index, uint dim) {
    if (state.kind == SAMPLER_INDEPENDENT) {
        return sample_1d(hash_u32(state.key ^ sample_index), dim);
    }
    return sobol_1d(state.key, sample_index, dim);
}

// mod.rs: vertex_dimensions
uvec4 vertex_dimensions(uint vertex) {
    if (vertex == 0u) {
        return uvec4(DIM_ENVIRONMENT_X, DIM_ENVIRONMENT_Y, DIM_BRDF_X, DIM_BRDF_Y);
    }
    uint first = DIM_BOUNCES + DIMS_PER_BOUNCE * (vertex - 1u);
    return uvec4(first, first + 1u, first + 2u, first + 3u);
}

// mod.rs: fresnel_dimension
uint fresnel_dimension(uint vertex) {
    return DIM_FRESNEL + vertex;
}

// mod.rs: sky_pick_dimension
uint sky_pick_dimension(uint vertex) {
    return DIM_SKY_PICK + vertex;
}

// mod.rs: emitter_dimensions
uvec2 emitter_dimensions(uint vertex) {
    uint first = DIM_EMITTERS + 2u * vertex;
    return uvec2(first, first + 1u);
}

CameraSample pixel_camera_sample(PixelSampler state, uint sample_index) {
    vec4 u = state.kind == SAMPLER_INDEPENDENT ? independent_sample(state.key, sample_index)
                                               : sobol_sample(state.sobol, sample_index);
    CameraSample s;
    s.film = vec2(float(state.pixel.x) + u.x, float(state.pixel.y) + u.y);
    s.lens = u.zw;
    s.time = CAMERA_SAMPLE_MIDDLE;
    return s;
}

CameraSample camera_sample(uint kind, uint seed, uvec2 pixel, uint width, uint sample_index) {
    return pixel_camera_sample(pixel_sampler(kind, seed, pixel, width), sample_index);
}

#endif
