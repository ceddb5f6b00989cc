// Mirror of lensray-core/src/reference/sheen.rs and clearcoat.rs, function by function: the
// layers glTF's extensions put over brdf.glsl's metallic-roughness base, KHR_materials_sheen's
// sheen under KHR_materials_clearcoat's coat (about its own normal), and the draws from them.
// The layered BRDF's functions overload the base's names; brdf_reflected is f times each
// layer's own cosine.
#ifndef LENSRAY_LAYERS_GLSL
#define LENSRAY_LAYERS_GLSL

#include "brdf.glsl"

// clearcoat.rs: Clearcoat
struct Clearcoat {
    float weight;
    float roughness;
    vec3 normal;
};

// sheen.rs: Sheen
struct Sheen {
    vec3 colour;
    float roughness;
};

// Where SHEEN_ALBEDO is read: the trace pass (GROUP_LENS) from Lens.sheen_albedo, since a
// constant array indexed by a variable costs lavapipe a copy per invocation (spectral.glsl);
// others from the constant. The values are the same floats.
#ifdef GROUP_LENS
#define SHEEN_ALBEDO_AT(i) lens.sheen_albedo[(i) >> 2u][(i) & 3u]
#else
#define SHEEN_ALBEDO_AT(i) SHEEN_ALBEDO[i]
#endif

// sheen.rs: Sheen::alpha
float sheen_alpha(Sheen s) {
    float r = clamp(s.roughness, MIN_ROUGHNESS, 1.0);
    return r * r;
}

// sheen.rs: charlie_distribution
float charlie_distribution(float n_dot_h, float alpha) {
    float inverse = 1.0 / alpha;
    float sin2 = max(1.0 - n_dot_h * n_dot_h, 0.0);
    return (2.0 + inverse) * pow(sin2, 0.5 * inverse) / (2.0 * PI);
}

// sheen.rs: charlie_fit
float charlie_fit(float x, float alpha) {
    float t = (1.0 - alpha) * (1.0 - alpha);
    float a = 21.5473 + (25.3245 - 21.5473) * t;
    float b = 3.82987 + (3.32435 - 3.82987) * t;
    float c = 0.19823 + (0.16801 - 0.19823) * t;
    float d = -1.97760 + (-1.27393 - -1.97760) * t;
    float e = -4.32054 + (-4.85967 - -4.32054) * t;
    return a / (1.0 + b * pow(x, c)) + d * x + e;
}

// sheen.rs: charlie_lambda
float charlie_lambda(float cos_theta, float alpha) {
    if (cos_theta < 0.5) {
        return exp(charlie_fit(cos_theta, alpha));
    }
    return exp(2.0 * charlie_fit(0.5, alpha) - charlie_fit(1.0 - cos_theta, alpha));
}

// sheen.rs: charlie_visibility
float charlie_visibility(float n_dot_l, float n_dot_v, float alpha) {
    float lambda = charlie_lambda(n_dot_v, alpha) + charlie_lambda(n_dot_l, alpha);
    return clamp(1.0 / ((1.0 + lambda) * (4.0 * n_dot_v * n_dot_l)), 0.0, 1.0);
}

// sheen.rs: directional_albedo
float sheen_directional_albedo(float mu, float roughness) {
    float size = float(SHEEN_ALBEDO_SIZE);
    float x = clamp(clamp(mu, 0.0, 1.0) * size - 0.5, 0.0, size - 1.0);
    float y = clamp(clamp(roughness, 0.0, 1.0) * size - 0.5, 0.0, size - 1.0);
    uint i = min(uint(x), SHEEN_ALBEDO_SIZE - 2u);
    uint j = min(uint(y), SHEEN_ALBEDO_SIZE - 2u);
    float fx = x - float(i);
    float fy = y - float(j);
    uint k = j * SHEEN_ALBEDO_SIZE + i;
    float a00 = SHEEN_ALBEDO_AT(k);
    float a10 = SHEEN_ALBEDO_AT(k + 1u);
    float a01 = SHEEN_ALBEDO_AT(k + SHEEN_ALBEDO_SIZE);
    float a11 = SHEEN_ALBEDO_AT(k + SHEEN_ALBEDO_SIZE + 1u);
    float low = a00 + (a10 - a00) * fx;
    float high = a01 + (a11 - a01) * fx;
    return low + (high - low) * fy;
}

// sheen.rs: Sheen::lobe
float sheen_lobe(Sheen s, float n_dot_l, float n_dot_v, float n_dot_h) {
    if (n_dot_l <= 0.0 || n_dot_v <= 0.0) {
        return 0.0;
    }
    float alpha = sheen_alpha(s);
    return charlie_distribution(n_dot_h, alpha) * charlie_visibility(n_dot_l, n_dot_v, alpha);
}

// sheen.rs: Sheen::albedo_scaling
float sheen_albedo_scaling(Sheen s, float n_dot_l, float n_dot_v) {
    float strength = max(max(s.colour.x, s.colour.y), s.colour.z);
    float e_v = sheen_directional_albedo(n_dot_v, s.roughness);
    float e_l = sheen_directional_albedo(n_dot_l, s.roughness);
    return max(min(1.0 - strength * e_v, 1.0 - strength * e_l), 0.0);
}

// sheen.rs: Sheen::probability
float sheen_probability(Sheen s, float n_dot_v) {
    float strength = max(max(s.colour.x, s.colour.y), s.colour.z);
    if (strength <= 0.0 || n_dot_v <= 0.0) {
        return 0.0;
    }
    return clamp(strength * sheen_directional_albedo(n_dot_v, s.roughness), 0.0, 1.0);
}

// sheen.rs: uniform_direction
vec3 uniform_direction(vec3 n, vec2 u) {
    vec3 t;
    vec3 b;
    orthonormal_frame(n, t, b);
    float z = u.x;
    float r = sqrt(max(1.0 - z * z, 0.0));
    float phi = 2.0 * PI * u.y;
    return t * (r * cos(phi)) + b * (r * sin(phi)) + n * z;
}

// clearcoat.rs: LayeredBrdf
struct LayeredBrdf {
    MetallicRoughness base;
    Clearcoat clearcoat;
    Sheen sheen;
};

// sheen.rs: LayeredBrdf::beneath_evaluate
vec3 beneath_evaluate(LayeredBrdf s, vec3 n, vec3 l, vec3 v) {
    vec3 base = brdf_evaluate(s.base, n, l, v);
    if (max(max(s.sheen.colour.x, s.sheen.colour.y), s.sheen.colour.z) <= 0.0) {
        return base;
    }
    float n_dot_l = dot(n, l);
    float n_dot_v = dot(n, v);
    vec3 h = normalize(l + v);
    float lobe = sheen_lobe(s.sheen, n_dot_l, n_dot_v, dot(n, h));
    return base * sheen_albedo_scaling(s.sheen, abs(n_dot_l), n_dot_v) + s.sheen.colour * lobe;
}

// sheen.rs: LayeredBrdf::beneath_pdf
float beneath_pdf(LayeredBrdf s, vec3 n, vec3 l, vec3 v) {
    float base = brdf_pdf(s.base, n, l, v);
    float n_dot_l = dot(n, l);
    float p = sheen_probability(s.sheen, dot(n, v));
    if (p <= 0.0) {
        return base;
    }
    float sheen = n_dot_l > 0.0 ? 0.5 / PI : 0.0;
    return p * sheen + (1.0 - p) * base;
}

// sheen.rs: LayeredBrdf::beneath_sample; false where the draw carries no light.
bool beneath_sample(LayeredBrdf s, vec3 n, vec3 v, vec3 u, out BrdfSample draw) {
    float p = sheen_probability(s.sheen, dot(n, v));
    if (p <= 0.0) {
        return brdf_sample(s.base, n, v, u, draw);
    }
    vec3 direction;
    if (u.x < p) {
        direction = uniform_direction(n, vec2(u.x / p, u.y));
    } else {
        BrdfSample base_draw;
        if (!brdf_sample(s.base, n, v, vec3((u.x - p) / (1.0 - p), u.y, u.z), base_draw)) {
            return false;
        }
        direction = base_draw.direction;
    }
    float pdf = beneath_pdf(s, n, direction, v);
    return finish_draw(n, direction, pdf, beneath_evaluate(s, n, direction, v), draw);
}

// clearcoat.rs: Clearcoat::alpha
float clearcoat_alpha(Clearcoat c) {
    float r = clamp(c.roughness, MIN_ROUGHNESS, 1.0);
    return r * r;
}

// clearcoat.rs: Clearcoat::blend
float clearcoat_blend(Clearcoat c, float n_dot_v) {
    float m = clamp(1.0 - abs(n_dot_v), 0.0, 1.0);
    float m2 = m * m;
    return c.weight * (CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * (m2 * m2 * m));
}

// clearcoat.rs: Clearcoat::lobe
float clearcoat_lobe(Clearcoat c, float n_dot_l, float n_dot_v, float n_dot_h) {
    if (n_dot_l <= 0.0 || n_dot_v <= 0.0) {
        return 0.0;
    }
    float alpha = clearcoat_alpha(c);
    return ggx_distribution(n_dot_h, alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
}

// clearcoat.rs: Clearcoat::probability
float clearcoat_probability(Clearcoat c, float n_dot_v) {
    if (c.weight <= 0.0 || n_dot_v <= 0.0) {
        return 0.0;
    }
    float fresnel = clearcoat_blend(c, n_dot_v) / c.weight;
    return clamp(c.weight * (0.2 + 0.8 * fresnel), 0.0, 1.0);
}

// clearcoat.rs: LayeredBrdf::transmits
bool brdf_transmits(LayeredBrdf s) {
    return brdf_transmits(s.base);
}

// clearcoat.rs: LayeredBrdf::coat_reflects
bool coat_reflects(LayeredBrdf s, vec3 n, vec3 l) {
    return s.clearcoat.weight > 0.0 && dot(s.clearcoat.normal, l) > 0.0
        && (dot(n, l) > 0.0 || !brdf_transmits(s));
}

// clearcoat.rs: LayeredBrdf::reflected
vec3 brdf_reflected(LayeredBrdf s, vec3 n, vec3 l, vec3 v) {
    vec3 base = beneath_evaluate(s, n, l, v) * abs(dot(n, l));
    if (s.clearcoat.weight <= 0.0) {
        return base;
    }
    vec3 nc = s.clearcoat.normal;
    float n_dot_v = dot(nc, v);
    float blend = clearcoat_blend(s.clearcoat, n_dot_v);
    float coat = 0.0;
    if (coat_reflects(s, n, l)) {
        vec3 h = normalize(l + v);
        float n_dot_l = dot(nc, l);
        coat = clearcoat_lobe(s.clearcoat, n_dot_l, n_dot_v, dot(nc, h)) * n_dot_l;
    }
    return base * (1.0 - blend) + vec3(blend * coat);
}

// clearcoat.rs: LayeredBrdf::pdf
float brdf_pdf(LayeredBrdf s, vec3 n, vec3 l, vec3 v) {
    float base = beneath_pdf(s, n, l, v);
    vec3 nc = s.clearcoat.normal;
    float n_dot_v = dot(nc, v);
    float p = clearcoat_probability(s.clearcoat, n_dot_v);
    if (p <= 0.0) {
        return base;
    }
    float coat = 0.0;
    if (coat_reflects(s, n, l)) {
        vec3 h = normalize(l + v);
        coat = visible_normal_pdf(n_dot_v, dot(nc, h), clearcoat_alpha(s.clearcoat));
    }
    return p * coat + (1.0 - p) * base;
}

// clearcoat.rs: LayeredBrdf::sample; false where the draw carries no light.
bool brdf_sample(LayeredBrdf s, vec3 n, vec3 v, vec3 u, out BrdfSample draw) {
    vec3 nc = s.clearcoat.normal;
    float p = clearcoat_probability(s.clearcoat, dot(nc, v));
    if (p <= 0.0) {
        return beneath_sample(s, n, v, u, draw);
    }
    vec3 direction;
    if (u.x < p) {
        vec3 h = visible_normal_around(nc, v, clearcoat_alpha(s.clearcoat), vec2(u.x / p, u.y));
        direction = 2.0 * dot(v, h) * h - v;
        // The lobe's density counts only what it reflects.
        if (!coat_reflects(s, n, direction)) {
            return false;
        }
    } else {
        BrdfSample base_draw;
        if (!beneath_sample(s, n, v, vec3((u.x - p) / (1.0 - p), u.y, u.z), base_draw)) {
            return false;
        }
        direction = base_draw.direction;
    }
    float pdf = brdf_pdf(s, n, direction, v);
    if (!(pdf > 0.0) || isinf(pdf)) {
        return false;
    }
    draw.direction = direction;
    draw.pdf = pdf;
    draw.weight = brdf_reflected(s, n, direction, v) / pdf;
    return true;
}

#endif
