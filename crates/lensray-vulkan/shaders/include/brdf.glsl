// Mirror of lensray-core/src/reference/brdf.rs, brdf_sampling.rs and transmission.rs, function
// by function: glTF's metallic-roughness BRDF (the specification's Appendix B) with
// KHR_materials_transmission's light through the dielectric, and the draws from it. The
// layers over it (sheen, clear coat) are layers.glsl.
// Include after the generated interface (MIN_ROUGHNESS, PI) and lights.glsl
// (orthonormal_frame, cosine_direction).
#ifndef LENSRAY_BRDF_GLSL
#define LENSRAY_BRDF_GLSL

// brdf.rs: Dielectric
struct Dielectric {
    float ior;
    float transmission;
    float eta;
};

// brdf.rs: MetallicRoughness
struct MetallicRoughness {
    vec3 base_colour;
    float metallic;
    float roughness;
    float specular;
    Dielectric dielectric;
};

// brdf.rs: Dielectric::f0
float dielectric_f0(Dielectric d) {
    float r = (d.ior - 1.0) / (d.ior + 1.0);
    return r * r;
}

// brdf.rs: Dielectric::outside_cosine; false beyond the critical angle.
bool outside_cosine(Dielectric d, float cos_v, out float outside) {
    outside = cos_v;
    if (d.eta >= 1.0) {
        return true;
    }
    float sin2 = max(1.0 - cos_v * cos_v, 0.0) / (d.eta * d.eta);
    outside = sqrt(max(1.0 - sin2, 0.0));
    return sin2 < 1.0;
}

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

// brdf.rs: MetallicRoughness::alpha
float brdf_alpha(MetallicRoughness s) {
    float r = clamp(s.roughness, MIN_ROUGHNESS, 1.0);
    return r * r;
}

// brdf.rs: MetallicRoughness::transmits
bool brdf_transmits(MetallicRoughness s) {
    return s.dielectric.transmission > 0.0 && s.metallic < 1.0;
}

// brdf.rs: MetallicRoughness::fresnel
vec3 brdf_fresnel(MetallicRoughness s, float v_dot_h) {
    float cos_outside;
    if (!outside_cosine(s.dielectric, v_dot_h, cos_outside)) {
        return vec3(1.0);
    }
    vec3 f0 = mix(vec3(dielectric_f0(s.dielectric) * s.specular), s.base_colour, s.metallic);
    float f90 = s.specular + (1.0 - s.specular) * s.metallic;
    return schlick_fresnel(f0, f90, cos_outside);
}

// transmission.rs: mirrored
vec3 mirrored(vec3 n, vec3 l) {
    return l - 2.0 * dot(n, l) * n;
}

// transmission.rs: refract; false beyond the critical angle.
bool refract_view(vec3 v, vec3 m, float eta, out vec3 l) {
    float c = dot(v, m);
    float sin2 = max(1.0 - c * c, 0.0) / (eta * eta);
    float cos_t = sqrt(max(1.0 - sin2, 0.0));
    l = -v / eta + m * (c / eta - cos_t);
    return sin2 < 1.0;
}

// transmission.rs: refraction_normal; false where no microfacet refracts v into l.
bool refraction_normal(vec3 n, vec3 l, vec3 v, float eta, out vec3 h) {
    h = -normalize(v + eta * l);
    if (dot(n, h) < 0.0) {
        h = -h;
    }
    return !any(isnan(h)) && dot(v, h) > 0.0 && dot(l, h) < 0.0;
}

// transmission.rs: MetallicRoughness::transmitted
vec3 brdf_transmitted(MetallicRoughness s, vec3 n, vec3 l, vec3 v) {
    float n_dot_v = dot(n, v);
    if (!brdf_transmits(s) || n_dot_v <= 0.0) {
        return vec3(0.0);
    }
    float n_dot_l = -dot(n, l);
    float alpha = brdf_alpha(s);
    float eta = s.dielectric.eta;
    float lobe;
    float v_dot_h;
    if (eta == 1.0) {
        vec3 h = normalize(mirrored(n, l) + v);
        lobe = ggx_distribution(dot(n, h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
        v_dot_h = dot(v, h);
    } else {
        vec3 h;
        if (!refraction_normal(n, l, v, eta, h)) {
            return vec3(0.0);
        }
        v_dot_h = dot(v, h);
        float l_dot_h = dot(l, h);
        float denominator = v_dot_h + eta * l_dot_h;
        float dv = ggx_distribution(dot(n, h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
        lobe = 4.0 * v_dot_h * -l_dot_h * dv / (denominator * denominator);
    }
    vec3 through = vec3(1.0) - brdf_fresnel(s, v_dot_h);
    return through * s.base_colour * (1.0 - s.metallic) * (s.dielectric.transmission * lobe);
}

// brdf.rs: MetallicRoughness::evaluate
vec3 brdf_evaluate(MetallicRoughness s, vec3 n, vec3 l, vec3 v) {
    float n_dot_l = dot(n, l);
    if (n_dot_l < 0.0) {
        return brdf_transmitted(s, n, l, v);
    }
    vec3 h = normalize(l + v);
    float n_dot_v = max(dot(n, v), 0.0);
    float alpha = brdf_alpha(s);
    vec3 fresnel = brdf_fresnel(s, abs(dot(v, h)));
    float specular = ggx_distribution(dot(n, h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
    vec3 diffuse = s.base_colour * (1.0 - s.metallic) * ((1.0 - s.dielectric.transmission) * (1.0 / PI));
    return (vec3(1.0) - fresnel) * diffuse + fresnel * specular;
}

// brdf_sampling.rs: MetallicRoughness::lobe_probabilities (x: specular, y: glass).
vec2 lobe_probabilities(MetallicRoughness s, float n_dot_v) {
    if (n_dot_v <= 0.0) {
        return vec2(0.0);
    }
    float dielectric = 1.0 - s.metallic;
    float t = s.dielectric.transmission;
    float specular = clamp(s.metallic + dielectric * ((1.0 - t) * 0.5 * s.specular), 0.0, 1.0);
    float glass = clamp(dielectric * t, 0.0, 1.0 - specular);
    return vec2(specular, glass);
}

// brdf_sampling.rs: MetallicRoughness::glass_reflectance
float glass_reflectance(MetallicRoughness s, float v_dot_h) {
    vec3 f = brdf_fresnel(s, v_dot_h);
    return clamp((f.x + f.y + f.z) / 3.0, 0.0, 1.0);
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

// transmission.rs: MetallicRoughness::transmission_pdf (v_dot_h: the refracting microfacet's).
float transmission_pdf(MetallicRoughness s, vec3 n, vec3 l, vec3 v, out float v_dot_h) {
    float n_dot_v = dot(n, v);
    float alpha = brdf_alpha(s);
    float eta = s.dielectric.eta;
    vec3 h;
    if (eta == 1.0) {
        h = normalize(mirrored(n, l) + v);
        v_dot_h = dot(v, h);
        return visible_normal_pdf(n_dot_v, dot(n, h), alpha);
    }
    v_dot_h = 1.0;
    if (!refraction_normal(n, l, v, eta, h)) {
        return 0.0;
    }
    v_dot_h = dot(v, h);
    float l_dot_h = dot(l, h);
    float denominator = v_dot_h + eta * l_dot_h;
    float normal_pdf = 4.0 * v_dot_h * visible_normal_pdf(n_dot_v, dot(n, h), alpha);
    return normal_pdf * eta * eta * -l_dot_h / (denominator * denominator);
}

// brdf_sampling.rs: MetallicRoughness::pdf
float brdf_pdf(MetallicRoughness s, vec3 n, vec3 l, vec3 v) {
    float n_dot_l = dot(n, l);
    float n_dot_v = dot(n, v);
    vec2 p = lobe_probabilities(s, n_dot_v);
    bool below = n_dot_l < 0.0;
    if (below ? p.y <= 0.0 : n_dot_l <= 0.0) {
        return 0.0;
    }
    float v_dot_h;
    float normal_pdf;
    if (below) {
        normal_pdf = transmission_pdf(s, n, l, v, v_dot_h);
    } else {
        vec3 h = normalize(l + v);
        v_dot_h = dot(v, h);
        normal_pdf = visible_normal_pdf(n_dot_v, dot(n, h), brdf_alpha(s));
    }
    float reflecting = p.y > 0.0 ? glass_reflectance(s, v_dot_h) : 0.0;
    if (below) {
        return p.y * (1.0 - reflecting) * normal_pdf;
    }
    float diffuse = (1.0 - p.x - p.y) * n_dot_l * (1.0 / PI);
    float share = p.x + p.y * reflecting;
    if (share <= 0.0) {
        return diffuse;
    }
    return share * normal_pdf + diffuse;
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

// brdf_sampling.rs: visible_normal_around
vec3 visible_normal_around(vec3 n, vec3 v, float alpha, vec2 u) {
    vec3 t;
    vec3 b;
    orthonormal_frame(n, t, b);
    vec3 m = visible_normal(vec3(dot(v, t), dot(v, b), dot(v, n)), alpha, u);
    return t * m.x + b * m.y + n * m.z;
}

// transmission.rs: MetallicRoughness::transmitted_through; false where nothing goes below.
bool transmitted_through(MetallicRoughness s, vec3 n, vec3 v, vec3 h, out vec3 l) {
    float eta = s.dielectric.eta;
    if (eta == 1.0) {
        l = mirrored(n, 2.0 * dot(v, h) * h - v);
    } else if (!refract_view(v, h, eta, l)) {
        return false;
    }
    return dot(n, l) < 0.0;
}

// brdf_sampling.rs: BrdfSample
struct BrdfSample {
    vec3 direction;
    float pdf;
    vec3 weight;
};

// brdf_sampling.rs: finish_draw; false where the draw carries no light. f is evaluated before
// the test (GLSL has no closures); a discarded draw drops it.
bool finish_draw(vec3 n, vec3 direction, float pdf, vec3 f, out BrdfSample draw) {
    float c = abs(dot(n, direction));
    if (c <= 0.0 || pdf <= 0.0 || isinf(pdf)) {
        return false;
    }
    draw.direction = direction;
    draw.pdf = pdf;
    draw.weight = f * (c / pdf);
    return true;
}

// brdf_sampling.rs: MetallicRoughness::sample; false where the draw carries no light. u.z picks
// whether a glass draw's microfacet reflects.
bool brdf_sample(MetallicRoughness s, vec3 n, vec3 v, vec3 u, out BrdfSample draw) {
    vec2 p = lobe_probabilities(s, dot(n, v));
    vec3 direction;
    if (u.x < p.x + p.y) {
        bool glass = u.x >= p.x;
        vec2 at = vec2(glass ? (u.x - p.x) / p.y : u.x / p.x, u.y);
        vec3 h = visible_normal_around(n, v, brdf_alpha(s), at);
        if (!glass || u.z < glass_reflectance(s, dot(v, h))) {
            direction = 2.0 * dot(v, h) * h - v;
            // The draws' density counts only what goes above the surface.
            if (dot(n, direction) <= 0.0) {
                return false;
            }
        } else if (!transmitted_through(s, n, v, h, direction)) {
            return false;
        }
    } else {
        direction = cosine_direction(n, vec2((u.x - p.x - p.y) / (1.0 - p.x - p.y), u.y));
    }
    float pdf = brdf_pdf(s, n, direction, v);
    return finish_draw(n, direction, pdf, brdf_evaluate(s, n, direction, v), draw);
}

#endif
