// Mirror of lensray-core/src/film/spectral.rs, function by function: one wavelength per sample
// and the 3x3 weight that turns a ray's linear sRGB radiance into what that sample adds to the
// film (the module documentation has the definition). The tables (SPECTRAL_*) come from the
// generated interface.glsl, the same numbers as Rust's. `precise` wherever Rust does
// arithmetic: no fused multiply-adds, the same roundings, so the results agree bit for bit.
#ifndef LENSRAY_SPECTRAL_GLSL
#define LENSRAY_SPECTRAL_GLSL

#include "interface.glsl"

// spectral.rs: SEARCH_FIRST_STEP
const uint SPECTRAL_SEARCH_FIRST_STEP = 64u;

// Where the tables are read: a shader with the lens buffer (GROUP_LENS: the trace pass) reads
// them from Lens.spectral_table, since a constant array indexed by a variable costs lavapipe a
// copy per invocation (interface::SPECTRAL_AT_*); others (the probe) from the constants. The
// values are the same floats.
#ifdef GROUP_LENS
#define SPECTRAL_TABLE_AT(i) lens.spectral_table[(i) >> 2u][(i) & 3u]
#define SPECTRAL_CDF_AT(k) SPECTRAL_TABLE_AT(SPECTRAL_AT_CDF + (k))
#define SPECTRAL_INV_PROBABILITY_AT(k) SPECTRAL_TABLE_AT(SPECTRAL_AT_INV_PROBABILITY + (k))
#define SPECTRAL_INV_DENSITY_AT(k) SPECTRAL_TABLE_AT(SPECTRAL_AT_INV_DENSITY + (k))
#define SPECTRAL_WEIGHTS_AT(i) SPECTRAL_TABLE_AT(SPECTRAL_AT_WEIGHTS + (i))
#else
#define SPECTRAL_CDF_AT(k) SPECTRAL_CDF[k]
#define SPECTRAL_INV_PROBABILITY_AT(k) SPECTRAL_INV_PROBABILITY[k]
#define SPECTRAL_INV_DENSITY_AT(k) SPECTRAL_INV_DENSITY[k]
#define SPECTRAL_WEIGHTS_AT(i) SPECTRAL_WEIGHTS[i]
#endif

// spectral.rs: wavelength_interval
uint wavelength_interval(float u) {
    uint k = 0u;
    for (uint step = SPECTRAL_SEARCH_FIRST_STEP; step > 0u; step >>= 1u) {
        uint next = k + step;
        if (next < SPECTRAL_INTERVALS && SPECTRAL_CDF_AT(next) <= u) {
            k = next;
        }
    }
    return k;
}

// spectral.rs: sample_wavelength
float sample_wavelength(float u) {
    uint k = wavelength_interval(u);
    precise float fraction = (u - SPECTRAL_CDF_AT(k)) * SPECTRAL_INV_PROBABILITY_AT(k);
    fraction = clamp(fraction, 0.0, 1.0);
    precise float node = float(k) * SPECTRAL_STEP_NM + SPECTRAL_MIN_NM;
    precise float lambda = node + SPECTRAL_STEP_NM * fraction;
    return lambda;
}

// spectral.rs: rgb_weights
mat3 rgb_weights(float lambda_nm) {
    uint last = SPECTRAL_INTERVALS - 1u;
    precise float x = (lambda_nm - SPECTRAL_MIN_NM) * SPECTRAL_INV_STEP_NM;
    x = clamp(x, 0.0, float(SPECTRAL_INTERVALS));
    uint k = min(uint(x), last);
    precise float t = x - float(k);
    precise float s = 1.0 - t;
    float inv_density = SPECTRAL_INV_DENSITY_AT(k);
    uint a = 9u * k;
    uint b = a + 9u;
    precise float w[9];
    for (uint j = 0u; j < 9u; ++j) {
        w[j] = (SPECTRAL_WEIGHTS_AT(a + j) * s + SPECTRAL_WEIGHTS_AT(b + j) * t) * inv_density;
    }
    return mat3(w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7], w[8]);
}

// spectral.rs: checks_dispersion
bool checks_dispersion(float u) {
    return u * float(DISPERSION_CHECK_INVERSE) < 1.0;
}

// spectral.rs: d_line_value (`checked` > 0: the sample checks the d line at that wavelength).
vec3 d_line_value(float checked, vec3 l_d) {
    if (checked > 0.0) {
        return l_d - rgb_weights(checked) * l_d * float(DISPERSION_CHECK_INVERSE);
    }
    return l_d;
}

// spectral.rs: checked_value
vec3 checked_value(float lambda_nm, vec3 l) {
    return rgb_weights(lambda_nm) * l * float(DISPERSION_CHECK_INVERSE);
}

#endif
