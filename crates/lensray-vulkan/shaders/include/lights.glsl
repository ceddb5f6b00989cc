// Mirror of lensray-core/src/scene/light.rs, function by function: the scene's punctual lights
// and the environment's cosine-distributed direction. Include after scene.glsl and
// camera.glsl (concentric_sample_disk).
#ifndef LENSRAY_LIGHTS_GLSL
#define LENSRAY_LIGHTS_GLSL

// light.rs: Incident
struct Incident {
    vec3 direction;
    float distance;
    vec3 irradiance;
};

// Light `i` of the scene's, where trace_moment has it: a light that moves while the shutter is
// open (position.w -(row + 1)) between its steps (motion.rs: LightSteps::at; the upload's rows:
// lensray-vulkan/src/upload/motion.rs).
Light light_at(uint i) {
    Light light = lights[i];
    if (light.position.w < 0.0) {
        uint row = uint(-light.position.w) - 1u;
        light.position = vec4(moving_attribute(row, 0u).xyz, 1.0);
        vec3 d = moving_attribute(row, 1u).xyz;
        light.direction.xyz = dot(d, d) > 0.0 ? normalize(d) : vec3(0.0);
    }
    return light;
}

// light.rs: Light::incident; false where the light gives nothing at `origin`.
bool light_incident(Light light, vec3 origin, out Incident incident) {
    if (light.kind == LIGHT_DIRECTIONAL) {
        incident.direction = -light.direction.xyz;
        incident.distance = T_MAX;
        incident.irradiance = light.intensity.xyz;
        return true;
    }
    vec3 to_light = light.position.xyz - origin;
    float dist = length(to_light);
    if (light.kind == LIGHT_NONE || dist <= 0.0) {
        return false;
    }
    vec3 direction = to_light / dist;
    float scale = 1.0 / (dist * dist);
    if (light.range > 0.0) {
        float r = dist / light.range;
        float window = clamp(1.0 - r * r * r * r, 0.0, 1.0);
        scale *= window * window;
    }
    if (light.kind == LIGHT_SPOT) {
        float cos_angle = -dot(direction, light.direction.xyz);
        float t = clamp((cos_angle - light.cos_outer) / max(light.cos_inner - light.cos_outer, 1e-3),
                        0.0, 1.0);
        scale *= t * t;
    }
    if (scale <= 0.0) {
        return false;
    }
    incident.direction = direction;
    incident.distance = dist;
    incident.irradiance = light.intensity.xyz * scale;
    return true;
}

// light.rs: orthonormal_frame
void orthonormal_frame(vec3 n, out vec3 t, out vec3 b) {
    // copysign(1, n.z), -0 included, as Rust's.
    float s = (floatBitsToUint(n.z) >> 31) != 0u ? -1.0 : 1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// light.rs: cosine_direction
vec3 cosine_direction(vec3 n, vec2 u) {
    vec2 d = concentric_sample_disk(u);
    float z = sqrt(max(1.0 - dot(d, d), 0.0));
    vec3 t;
    vec3 b;
    orthonormal_frame(n, t, b);
    return t * d.x + b * d.y + n * z;
}

#endif
