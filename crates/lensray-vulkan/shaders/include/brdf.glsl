// Mirror of lensray-core/src/reference/brdf.rs, brdf_sampling.rs, sheen.rs and clearcoat.rs,
// function by function: glTF's metallic-roughness BRDF (the specification's Appendix B) under
// KHR_materials_sheen's sheen under KHR_materials_clearcoat's coat, and the draws from them. The layered BRDF's functions
// overload the base's names.
// Include after the generated interface (DIELECTRIC_F0, MIN_ROUGHNESS, PI) and lights.glsl
// (orthonormal_frame, cosine_direction).
#ifndef LENSRAY_BRDF_GLSL
#define LENSRAY_BRDF_GLSL

// brdf.rs: MetallicRoughness
struct MetallicRoughness {
    vec3 base_colour;
    float metallic;
    float roughness;
    float specular;
};

// brdf.rs: ggx_distribution
float ggx_distribution(float n_dot_h, float alpha) {
    float a2 = alpha * alpha;
    float c2 = n_dot_h * n_dot_h;
    float d = (1.0 - c2) + c2 * a2;
    return a2 / (PI * d * d);
}

// brdf.rs: smith_visibility
float smith_visibility(float n_dot_l, float n_dot_v, float alpha) {
    float a2 = alpha * alpha;
    float ggx_v = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    float ggx_l = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / (ggx_v + ggx_l);
}

// brdf.rs: schlick_fresnel
vec3 schlick_fresnel(vec3 f0, float f90, float v_dot_h) {
    float m = clamp(1.0 - v_dot_h, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (vec3(f90) - f0) * (m2 * m2 * m);
}

// brdf.rs: MetallicRoughness::evaluate
vec3 brdf_evaluate(MetallicRoughness s, vec3 n, vec3 l, vec3 v) {
    vec3 h = normalize(l + v);
    float n_dot_l = dot(n, l);
    float n_dot_v = max(dot(n, v), 0.0);
    float r = clamp(s.roughness, MIN_ROUGHNESS, 1.0);
    float alpha = r * r;
    vec3 f0 = mix(vec3(DIELECTRIC_F0 * s.specular), s.base_colour, s.metallic);
    float f90 = s.specular + (1.0 - s.specular) * s.metallic;
    vec3 fresnel = schlick_fresnel(f0, f90, abs(dot(v, h)));
    float specular = ggx_distribution(dot(n, h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
    vec3 diffuse_colour = s.base_colour * (1.0 - s.metallic);
    return (vec3(1.0) - fresnel) * diffuse_colour * (1.0 / PI) + fresnel * specular;
}

// brdf.rs: MetallicRoughness::alpha
float brdf_alpha(MetallicRoughness s) {
    float r = clamp(s.roughness, MIN_ROUGHNESS, 1.0);
    return r * r;
}

// brdf_sampling.rs: MetallicRoughness::specular_probability
float specular_probability(MetallicRoughness s, float n_dot_v) {
    if (n_dot_v <= 0.0) {
        return 0.0;
    }
    return clamp(s.metallic + (1.0 - s.metallic) * 0.5 * s.specular, 0.0, 1.0);
}

// brdf_sampling.rs: visible_normal_pdf
float visible_normal_pdf(float n_dot_v, float n_dot_h, float alpha) {
    if (n_dot_v <= 0.0 || n_dot_h <= 0.0) {
        return 0.0;
    }
    float a2 = alpha * alpha;
    float lambda = sqrt(a2 + (1.0 - a2) * n_dot_v * n_dot_v);
    return ggx_distribution(n_dot_h, alpha) / (2.0 * (n_dot_v + lambda));
}

// brdf_sampling.rs: MetallicRoughness::pdf
float brdf_pdf(MetallicRoughness s, vec3 n, vec3 l, vec3 v) {
    float n_dot_l = dot(n, l);
    if (n_dot_l <= 0.0) {
        return 0.0;
    }
    float n_dot_v = dot(n, v);
    float p = specular_probability(s, n_dot_v);
    float diffuse = n_dot_l * (1.0 / PI);
    if (p <= 0.0) {
        return diffuse;
    }
    vec3 h = normalize(l + v);
    float specular = visible_normal_pdf(n_dot_v, dot(n, h), brdf_alpha(s));
    return p * specular + (1.0 - p) * diffuse;
}

// brdf_sampling.rs: visible_normal
vec3 visible_normal(vec3 v, float alpha, vec2 u) {
    vec3 vh = normalize(vec3(alpha * v.x, alpha * v.y, v.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) / sqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    float p1 = r * cos(phi);
    float p2 = r * sin(phi);
    float s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * p2;
    vec3 nh = t1 * p1 + t2 * p2 + vh * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(nh.z, 0.0)));
}

// brdf_sampling.rs: BrdfSample
struct BrdfSample {
    vec3 direction;
    float pdf;
    vec3 weight;
};

// brdf_sampling.rs: finish_draw; false where the draw carries no light. f is evaluated before
// the test (GLSL has no closures); a draw below the surface discards it.
bool finish_draw(vec3 n, vec3 direction, float pdf, vec3 f, out BrdfSample draw) {
    float n_dot_l = dot(n, direction);
    if (n_dot_l <= 0.0 || pdf <= 0.0) {
        return false;
    }
    draw.direction = direction;
    draw.pdf = pdf;
    draw.weight = f * (n_dot_l / pdf);
    return true;
}

// brdf_sampling.rs: MetallicRoughness::sample; false where the draw carries no light.
bool brdf_sample(MetallicRoughness s, vec3 n, vec3 v, vec2 u, out BrdfSample draw) {
    float p = specular_probability(s, dot(n, v));
    vec3 direction;
    if (u.x < p) {
        vec3 t;
        vec3 b;
        orthonormal_frame(n, t, b);
        vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
        vec3 m = visible_normal(v_local, brdf_alpha(s), vec2(u.x / p, u.y));
        vec3 h = t * m.x + b * m.y + n * m.z;
        direction = 2.0 * dot(v, h) * h - v;
    } else {
        direction = cosine_direction(n, vec2((u.x - p) / (1.0 - p), u.y));
    }
    float pdf = brdf_pdf(s, n, direction, v);
    return finish_draw(n, direction, pdf, brdf_evaluate(s, n, direction, v), draw);
}

// clearcoat.rs: Clearcoat
struct Clearcoat {
    float weight;
    float roughness;
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
    return base * sheen_albedo_scaling(s.sheen, n_dot_l, n_dot_v) + s.sheen.colour * lobe;
}

// sheen.rs: LayeredBrdf::beneath_pdf
float beneath_pdf(LayeredBrdf s, vec3 n, vec3 l, vec3 v) {
    float base = brdf_pdf(s.base, n, l, v);
    float n_dot_l = dot(n, l);
    float p = sheen_probability(s.sheen, dot(n, v));
    if (p <= 0.0 || n_dot_l <= 0.0) {
        return base;
    }
    return p * (0.5 / PI) + (1.0 - p) * base;
}

// sheen.rs: LayeredBrdf::beneath_sample; false where the draw carries no light.
bool beneath_sample(LayeredBrdf s, vec3 n, vec3 v, vec2 u, out BrdfSample draw) {
    float p = sheen_probability(s.sheen, dot(n, v));
    if (p <= 0.0) {
        return brdf_sample(s.base, n, v, u, draw);
    }
    vec3 direction;
    if (u.x < p) {
        direction = uniform_direction(n, vec2(u.x / p, u.y));
    } else {
        BrdfSample base_draw;
        if (!brdf_sample(s.base, n, v, vec2((u.x - p) / (1.0 - p), u.y), base_draw)) {
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

// clearcoat.rs: LayeredBrdf::evaluate
vec3 brdf_evaluate(LayeredBrdf s, vec3 n, vec3 l, vec3 v) {
    vec3 base = beneath_evaluate(s, n, l, v);
    if (s.clearcoat.weight <= 0.0) {
        return base;
    }
    float n_dot_v = dot(n, v);
    float blend = clearcoat_blend(s.clearcoat, n_dot_v);
    vec3 h = normalize(l + v);
    float lobe = clearcoat_lobe(s.clearcoat, dot(n, l), n_dot_v, dot(n, h));
    return base * (1.0 - blend) + vec3(blend * lobe);
}

// clearcoat.rs: LayeredBrdf::pdf
float brdf_pdf(LayeredBrdf s, vec3 n, vec3 l, vec3 v) {
    float base = beneath_pdf(s, n, l, v);
    float n_dot_v = dot(n, v);
    float p = clearcoat_probability(s.clearcoat, n_dot_v);
    if (p <= 0.0 || dot(n, l) <= 0.0) {
        return base;
    }
    vec3 h = normalize(l + v);
    float coat = visible_normal_pdf(n_dot_v, dot(n, h), clearcoat_alpha(s.clearcoat));
    return p * coat + (1.0 - p) * base;
}

// clearcoat.rs: LayeredBrdf::sample; false where the draw carries no light.
bool brdf_sample(LayeredBrdf s, vec3 n, vec3 v, vec2 u, out BrdfSample draw) {
    float p = clearcoat_probability(s.clearcoat, dot(n, v));
    if (p <= 0.0) {
        return beneath_sample(s, n, v, u, draw);
    }
    vec3 direction;
    if (u.x < p) {
        vec3 t;
        vec3 b;
        orthonormal_frame(n, t, b);
        vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
        vec3 m = visible_normal(v_local, clearcoat_alpha(s.clearcoat), vec2(u.x / p, u.y));
        vec3 h = t * m.x + b * m.y + n * m.z;
        direction = 2.0 * dot(v, h) * h - v;
    } else {
        BrdfSample base_draw;
        if (!beneath_sample(s, n, v, vec2((u.x - p) / (1.0 - p), u.y), base_draw)) {
            return false;
        }
        direction = base_draw.direction;
    }
    float pdf = brdf_pdf(s, n, direction, v);
    return finish_draw(n, direction, pdf, brdf_evaluate(s, n, direction, v), draw);
}

#endif
