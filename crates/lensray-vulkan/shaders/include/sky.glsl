// Mirror of lensray-core/src/reference/sky.rs, function by function: the environment as a
// light, a uniform sky (params.environment) or the scene's map (environment.glsl, where
// params.environment_map says it lights), drawn from and weighed against the BRDF's draws by
// the power heuristic. Include after environment.glsl, lights.glsl and brdf.glsl.
#ifndef LENSRAY_SKY_GLSL
#define LENSRAY_SKY_GLSL

// sky.rs: power_heuristic
float power_heuristic(float a, float b) {
    float a2 = a * a;
    float b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

// sky.rs: Sky::of (whether anything lights from afar).
bool sky_lights() {
    return params.environment_map != ENVIRONMENT_MAP_NONE ? environment.total > 0.0
                                                          : params.environment.xyz != vec3(0.0);
}

bool sky_is_map() {
    return params.environment_map != ENVIRONMENT_MAP_NONE;
}

// sky.rs: Sky::radiance
vec3 sky_radiance(vec3 d) {
    return sky_is_map() ? env_radiance(d) : params.environment.xyz;
}

// sky.rs: Sky::pdf
float sky_pdf(vec3 n, vec3 d) {
    return sky_is_map() ? env_pdf(d) : max(dot(n, d), 0.0) * (1.0 / PI);
}

// sky.rs: Sky::sample; false where none is drawn.
bool sky_sample(vec3 n, vec2 u, out vec3 direction, out float pdf, out vec3 radiance) {
    if (sky_is_map()) {
        uvec2 texel;
        if (!env_sample(u, direction, pdf, texel)) {
            return false;
        }
        radiance = env_texel(texel);
        return true;
    }
    direction = cosine_direction(n, u);
    pdf = max(dot(n, direction), 0.0) * (1.0 / PI);
    radiance = params.environment.xyz;
    return pdf > 0.0;
}

// environment/mod.rs: luminance (`precise`: as the CPU rounds it, since it picks a candidate)
float luminance(vec3 c) {
    precise float l = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
    return l;
}

// sky.rs: candidate_point. `precise`: no fused multiply-add, Rust's roundings, so that a
// candidate lands in the texel the CPU's does.
vec2 candidate_point(vec2 u, uint k) {
    float kf = float(k);
    precise float x = u.x + SKY_CANDIDATE_STEP[0] * kf;
    precise float y = u.y + SKY_CANDIDATE_STEP[1] * kf;
    return vec2(fract(x), fract(y));
}

#endif
