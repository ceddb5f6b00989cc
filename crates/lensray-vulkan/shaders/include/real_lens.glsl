// Mirror of lensray-core/src/camera/real_lens (mod.rs, pupil.rs) and the f32 tracer lensray-core/src/optics/trace.rs
// (`narrow`), function by function: a camera ray from a film point toward the exit pupil's
// region, refracted through every surface of the lens in the storage buffer `lens` (struct
// Lens in the generated interface.glsl, written by lensray-vulkan/src/core/conv.rs from the Rust lens).
// Included by camera.glsl where the shader defines LENS_BINDING (and APERTURE_TABLE_BINDING,
// whose image the stop reads). `precise`: no fused multiply-adds, Rust's roundings.
#ifndef LENSRAY_REAL_LENS_GLSL
#define LENSRAY_REAL_LENS_GLSL

layout(std430, set = 0, binding = LENS_BINDING) readonly buffer LensBlock { Lens lens; };

// trace.rs: LensRay
struct LensRay {
    vec3 origin;
    vec3 direction;
};

// trace.rs: refract. Snell's law in vector form; false at total internal reflection.
bool lens_refract(vec3 d, vec3 n, float eta, out vec3 refracted) {
    precise float cos_i = -dot(n, d);
    precise float sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if (sin2_t > 1.0) {
        refracted = vec3(0.0);
        return false;
    }
    precise float cos_t = sqrt(1.0 - sin2_t);
    precise vec3 r = eta * d + (eta * cos_i - cos_t) * n;
    refracted = r;
    return true;
}

// trace.rs: Interface::intersect. The root on the cap around the vertex; false if none.
bool lens_intersect(uint i, LensRay ray, out float t_hit, out vec3 normal) {
    vec4 shape = lens.surface_shape[i];
    float z = shape.x;
    float radius = shape.y;
    t_hit = 0.0;
    normal = vec3(0.0);
    if (radius == 0.0) {
        precise float t = (z - ray.origin.z) / ray.direction.z;
        if (!(t > 0.0 && !isinf(t))) {
            return false;
        }
        t_hit = t;
        normal = vec3(0.0, 0.0, -sign(ray.direction.z));
        return true;
    }
    precise vec3 o = ray.origin - vec3(0.0, 0.0, z + radius);
    precise float b = dot(o, ray.direction);
    precise float c = dot(o, o) - radius * radius;
    precise float discriminant = b * b - c;
    if (isnan(discriminant) || discriminant < 0.0) {
        return false;
    }
    precise float root = sqrt(discriminant);
    precise float near_t = -b - root;
    precise float far_t = -b + root;
    precise float near_z = o.z + near_t * ray.direction.z;
    precise float far_z = o.z + far_t * ray.direction.z;
    if (near_t > 0.0 && near_z * -radius > 0.0) {
        t_hit = near_t;
    } else if (far_t > 0.0 && far_z * -radius > 0.0) {
        t_hit = far_t;
    } else {
        return false;
    }
    precise vec3 n = (o + t_hit * ray.direction) / abs(radius);
    if (dot(n, ray.direction) > 0.0) {
        n = -n;
    }
    normal = n;
    return true;
}

// trace.rs: Interface::pass, toward the scene. False if the ray misses the surface, leaves
// its clear aperture or is totally internally reflected.
bool lens_pass_toward_scene(uint i, inout LensRay ray) {
    float t;
    vec3 normal;
    if (!lens_intersect(i, ray, t, normal)) {
        return false;
    }
    precise vec3 p = ray.origin + t * ray.direction;
    float aperture_radius = lens.surface_shape[i].z;
    precise float r2 = p.x * p.x + p.y * p.y;
    if (r2 > aperture_radius * aperture_radius) {
        return false;
    }
    if (lens.surface_shape[i].y == 0.0) {
        return true;
    }
    vec4 media = lens.surface_media[i];
    vec3 direction;
    if (!lens_refract(ray.direction, normal, media.y / media.x, direction)) {
        return false;
    }
    ray.origin = p;
    ray.direction = direction;
    return true;
}

// aperture/mod.rs: Aperture::transmission, at a point of the unit shape's plane.
float aperture_transmission(Camera cam, vec2 p) {
    precise vec2 q = vec2(p.x, p.y / cam.aperture_aspect);
#ifdef APERTURE_TABLE_BINDING
    if (cam.aperture_image_columns > 0u) {
        vec2 c = cam.aperture_turn.xy;
        precise vec2 r = vec2(c.x * q.x + c.y * q.y, c.x * q.y - c.y * q.x);
        if (abs(r.x) > 1.0 || abs(r.y) > 1.0) {
            return 0.0;
        }
        // aperture/image.rs: ApertureImage::cell_of
        uint columns = cam.aperture_image_columns;
        uint rows = cam.aperture_image_rows;
        precise float fx = (r.x + 1.0) * 0.5 * float(columns);
        precise float fy = (1.0 - r.y) * 0.5 * float(rows);
        int x = clamp(int(floor(fx)), 0, int(columns) - 1);
        int y = clamp(int(floor(fy)), 0, int(rows) - 1);
        return aperture_table[lens.aperture_transmission_start + uint(y) * columns + uint(x)];
    }
#endif
    uint n = cam.aperture_fan_len;
    if (n == 0u) {
        precise float q2 = q.x * q.x + q.y * q.y;
        return q2 <= 1.0 ? 1.0 : 0.0;
    }
    for (uint i = 0u; i < n; ++i) {
        uint j = (i + 1u) % n;
        vec4 pair_i = cam.aperture_fan[i / 2u];
        vec4 pair_j = cam.aperture_fan[j / 2u];
        vec2 a = (i % 2u == 0u) ? pair_i.xy : pair_i.zw;
        vec2 b = (j % 2u == 0u) ? pair_j.xy : pair_j.zw;
        precise vec2 edge = b - a;
        precise vec2 to_q = q - a;
        precise float side = edge.x * to_q.y - edge.y * to_q.x;
        if (side < 0.0) {
            return 0.0;
        }
    }
    return 1.0;
}

// real_lens/mod.rs: RealLens::trace_to_scene. The ray from the film through every surface;
// false if blocked, else the stop's transmission where it crossed.
bool lens_trace_to_scene(Camera cam, inout LensRay ray, out float transmission) {
    transmission = 1.0;
    for (uint k = 0u; k < lens.surface_count; ++k) {
        uint i = lens.surface_count - 1u - k;
        if (i == lens.stop) {
            float t;
            vec3 normal;
            if (!lens_intersect(i, ray, t, normal)) {
                return false;
            }
            precise vec3 p = ray.origin + t * ray.direction;
            transmission = aperture_transmission(cam, vec2(p.x, p.y) / lens.stop_radius);
            if (transmission <= 0.0) {
                return false;
            }
            continue;
        }
        if (!lens_pass_toward_scene(i, ray)) {
            return false;
        }
    }
    return true;
}

// real_lens/mod.rs: RealLens::film_point (the image inverted on the film).
vec3 lens_film_point(vec2 p_raster) {
    precise float u = (p_raster.x - lens.raster_centre_x) * lens.film_mm_per_pixel;
    precise float v = (lens.raster_centre_y - p_raster.y) * lens.film_mm_per_pixel;
    return vec3(-u, -v, lens.film_z);
}

// real_lens/pupil.rs: ExitPupil::sample. The rear-plane point of lens sample u for film point
// `film`, turned to its angle; `area` the region's area (mm^2).
vec3 lens_pupil_sample(vec3 film, vec2 u, out float area) {
    precise float r = sqrt(film.x * film.x + film.y * film.y);
    precise float t = r / lens.film_radius * float(LENS_PUPIL_BINS);
    uint bin = min(uint(t), LENS_PUPIL_BINS - 1u);
    precise float f = clamp(t - float(bin), 0.0, 1.0);
    vec4 inner = lens.pupil_inner[bin];
    vec4 outer = lens.pupil_outer[bin];
    precise vec2 centre = inner.xy + f * (outer.xy - inner.xy);
    precise vec2 half_sides = inner.zw + f * (outer.zw - inner.zw);
    precise vec2 q = centre + half_sides * (2.0 * u - vec2(1.0));
    float c = 1.0;
    float s = 0.0;
    if (r > 0.0) {
        c = film.x / r;
        s = film.y / r;
    }
    precise vec2 turned = vec2(c * q.x - s * q.y, s * q.x + c * q.y);
    precise float a = 4.0 * max(half_sides.x, 0.0) * max(half_sides.y, 0.0);
    area = a;
    return vec3(turned, lens.rear_z);
}

// projective.rs: Camera::generate_ray (real_lens/mod.rs: RealLens::camera_ray,
// camera_from_lens). False when the lens blocks the ray; the thin lens: first_order_ray, weight 1.
bool generate_ray(Camera cam, vec2 p_raster, vec2 lens_u, out Ray r,
                               out float weight) {
    if (lens.surface_count == 0u) {
        r = first_order_ray(cam, p_raster, lens_u);
        weight = 1.0;
        return true;
    }
    r.origin = vec3(0.0);
    r.direction = vec3(0.0, 0.0, 1.0);
    weight = 0.0;
    vec3 film = lens_film_point(p_raster);
    float area;
    vec3 rear = lens_pupil_sample(film, lens_u, area);
    vec3 direction = normalize(rear - film);
    LensRay ray = LensRay(film, direction);
    float transmission;
    if (!lens_trace_to_scene(cam, ray, transmission)) {
        return false;
    }
    precise float cos2 = direction.z * direction.z;
    precise float w = transmission * (cos2 * cos2) * area * lens.inverse_centre_integral;
    weight = w;
    const float scale = 1.0 / 1000.0;  // physical.rs: MM_PER_WORLD_UNIT
    vec3 origin = vec3(ray.origin.x * scale, ray.origin.y * scale,
                       (lens.entrance_pupil_z - ray.origin.z) * scale);
    vec3 dir = vec3(ray.direction.x, ray.direction.y, -ray.direction.z);
    r.origin = (cam.world_from_camera * vec4(origin, 1.0)).xyz;
    r.direction = (cam.world_from_camera * vec4(dir, 0.0)).xyz;
    return true;
}

#endif
