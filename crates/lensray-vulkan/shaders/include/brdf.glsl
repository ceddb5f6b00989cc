// Mirror of lensray-core/src/reference/brdf.rs, function by function: glTF's metallic-roughness
// BRDF (the specification's Appendix B). Include after the generated interface (DIELECTRIC_F0,
// MIN_ROUGHNESS, PI).
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

#endif
