// Mirror of lensray-core/src/camera/real_lens (mod.rs, pupil.rs) and the f32 tracer lensray-core/src/optics/trace.rs
// (`narrow`), function by function: a camera ray from a film point toward the exit pupil's
// region, refracted through every surface of the lens in the storage buffer `lens` (struct
// Lens in the generated interface.glsl, written by lensray-vulkan/src/core/conv.rs from the Rust lens).
// Included by camera.glsl where the shader's set holds the lens (GROUP_LENS; and GROUP_APERTURE,
// whose image the stop reads). `precise`: no fused multiply-adds, Rust's roundings.
#ifndef LENSRAY_REAL_LENS_GLSL
#define LENSRAY_REAL_LENS_GLSL

// trace.rs: LensRay
struct LensRay {
    vec3 origin;
    vec3 direction;
};

// optics/glass.rs: dispersion_offset_f32. The offset k of wavelength lambda_nm: a medium's
// index there is n_d + B k.
float dispersion_offset(float lambda_nm) {
    precise float l = lambda_nm * 1e-3;
    precise float k = 1.0 / (l * l) - 1.0 / (GLASS_LAMBDA_D_UM * GLASS_LAMBDA_D_UM);
    return k;
}

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

// trace.rs: Interface::intersect_sphere. The vertex sphere's root on the cap around the
// vertex; false if none.
bool lens_intersect_sphere(uint i, LensRay ray, out float t_hit, out vec3 normal) {
    vec4 shape = lens.surface_shape[i];
    float z = shape.x;
    float radius = shape.y;
    t_hit = 0.0;
    normal = vec3(0.0);
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

// trace.rs: Interface::sag. An asphere's sag and its derivative with respect to r^2; false
// where it is undefined.
bool lens_sag(uint i, float r2, out float sag, out float slope) {
    vec4 shape = lens.surface_shape[i];
    vec4 low = lens.surface_asphere_low[i];
    vec4 high = lens.surface_asphere_high[i];
    float a[8] = float[8](low.x, low.y, low.z, low.w, high.x, high.y, high.z, high.w);
    sag = 0.0;
    slope = 0.0;
    precise float c = 1.0 / shape.y;
    precise float q2 = 1.0 - (1.0 + shape.w) * c * c * r2;
    if (!(q2 >= 0.0)) {
        return false;
    }
    precise float q = sqrt(q2);
    precise float poly = 0.0;
    precise float d = 0.0;
    for (int j = 7; j >= 0; --j) {
        d = d * r2 + float(j + 1) * a[j];
        poly = poly * r2 + a[j];
    }
    precise float s = c * r2 / (1.0 + q) + poly * r2;
    precise float ds = c / (2.0 * q) + d;
    sag = s;
    slope = ds;
    return true;
}

// trace.rs: Interface::newton. Newton's iteration on the asphere's sag from the vertex
// sphere's root (or the vertex plane); the normal from the sag's gradient. False if the sag
// is undefined on the way or the iteration does not converge in front of the ray.
bool lens_newton(uint i, LensRay ray, out float t_hit, out vec3 normal) {
    float z_vertex = lens.surface_shape[i].x;
    vec3 o = ray.origin;
    vec3 d = ray.direction;
    float t_sphere;
    vec3 unused;
    precise float t = (z_vertex - o.z) / d.z;
    if (lens_intersect_sphere(i, ray, t_sphere, unused)) {
        t = t_sphere;
    }
    t_hit = 0.0;
    normal = vec3(0.0);
    for (uint n = 0u; n < LENS_NEWTON_ITERATIONS; ++n) {
        precise float x = o.x + t * d.x;
        precise float y = o.y + t * d.y;
        precise float z = o.z + t * d.z;
        float sag;
        float slope;
        if (!lens_sag(i, x * x + y * y, sag, slope)) {
            return false;
        }
        precise float f = (z - z_vertex) - sag;
        precise float df = d.z - 2.0 * slope * (x * d.x + y * d.y);
        precise float step = f / df;
        if (isnan(step) || isinf(step)) {
            return false;
        }
        t = t - step;
        if (abs(step) <= LENS_NEWTON_TOLERANCE * (1.0 + abs(t))) {
            if (!(t > 0.0)) {
                return false;
            }
            precise float hx = o.x + t * d.x;
            precise float hy = o.y + t * d.y;
            if (!lens_sag(i, hx * hx + hy * hy, sag, slope)) {
                return false;
            }
            precise vec3 g = vec3(-2.0 * slope * hx, -2.0 * slope * hy, 1.0);
            precise vec3 n_hat = g * (1.0 / sqrt(g.x * g.x + g.y * g.y + g.z * g.z));
            if (dot(n_hat, d) > 0.0) {
                n_hat = -n_hat;
            }
            t_hit = t;
            normal = n_hat;
            return true;
        }
    }
    return false;
}

// trace.rs: Interface::intersect. The flat stop's plane, an asphere's Newton root or the
// sphere's root on the cap; false if none.
bool lens_intersect(uint i, LensRay ray, out float t_hit, out vec3 normal) {
    vec4 shape = lens.surface_shape[i];
    t_hit = 0.0;
    normal = vec3(0.0);
    if (shape.y == 0.0) {
        precise float t = (shape.x - ray.origin.z) / ray.direction.z;
        if (!(t > 0.0 && !isinf(t))) {
            return false;
        }
        t_hit = t;
        normal = vec3(0.0, 0.0, -sign(ray.direction.z));
        return true;
    }
    if ((lens.asphere_mask & (1u << i)) != 0u) {
        return lens_newton(i, ray, t_hit, normal);
    }
    return lens_intersect_sphere(i, ray, t_hit, normal);
}

// trace.rs: Interface::pass_at, toward the scene at dispersion offset k. False if the ray
// misses the surface, leaves its clear aperture or is totally internally reflected.
bool lens_pass_toward_scene(uint i, inout LensRay ray, float k) {
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
    precise float before = media.x + media.z * k;
    precise float after = media.y + media.w * k;
    vec3 direction;
    if (!lens_refract(ray.direction, normal, after / before, direction)) {
        return false;
    }
    ray.origin = p;
    ray.direction = direction;
    return true;
}

// aperture/mod.rs: Aperture::transmission, at a point of the unit shape's plane.
float aperture_transmission(Camera cam, vec2 p) {
    precise vec2 q = vec2(p.x, p.y / cam.aperture_aspect);
#ifdef GROUP_APERTURE
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

// real_lens/mod.rs: RealLens::trace_to_scene_at. The ray from the film through every surface
// at dispersion offset k; false if blocked, else the stop's transmission where it crossed.
bool lens_trace_to_scene(Camera cam, inout LensRay ray, float k, out float transmission) {
    transmission = 1.0;
    for (uint j = 0u; j < lens.surface_count; ++j) {
        uint i = lens.surface_count - 1u - j;
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
        if (!lens_pass_toward_scene(i, ray, k)) {
            return false;
        }
    }
    return true;
}

// real_lens/mod.rs: RealLens::film_point, film.rs: FilmFrame::point (the image inverted on
// the film, which a tilted lens does not face).
vec3 lens_film_point(vec2 p_raster) {
    precise float u = (p_raster.x - lens.raster_centre_x) * lens.film_mm_per_pixel;
    precise float v = (lens.raster_centre_y - p_raster.y) * lens.film_mm_per_pixel;
    vec3 o = lens.film_origin.xyz;
    vec3 r = lens.film_right.xyz;
    vec3 p = lens.film_up.xyz;
    precise vec3 film = (o + r * -u) + p * -v;
    return film;
}

// real_lens/mod.rs: turn. m v as ((c0 x + c1 y) + c2 z) with m's columns.
vec3 lens_turn(vec3 v) {
    vec3 c0 = lens.camera_from_lens[0].xyz;
    vec3 c1 = lens.camera_from_lens[1].xyz;
    vec3 c2 = lens.camera_from_lens[2].xyz;
    precise vec3 out_v = (c0 * v.x + c1 * v.y) + c2 * v.z;
    return out_v;
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

// real_lens/mod.rs: RealLens::generate_ray (and camera_from_lens), in camera space, of film
// point `film` (lens_film_point) at dispersion offset k. False when the lens blocks the ray.
bool generate_ray(Camera cam, vec3 film, vec2 lens_u, float k, out Ray r, out float weight) {
    r.origin = vec3(0.0);
    r.direction = vec3(0.0, 0.0, 1.0);
    weight = 0.0;
    float area;
    vec3 rear = lens_pupil_sample(film, lens_u, area);
    vec3 direction = normalize(rear - film);
    LensRay ray = LensRay(film, direction);
    float transmission;
    if (!lens_trace_to_scene(cam, ray, k, transmission)) {
        return false;
    }
    // RealLens::finish: cos^4, and a tilted film's factor (exactly 1 untilted).
    vec3 n = lens.film_normal.xyz;
    precise float cos2 = direction.z * direction.z;
    precise float cos_film = (direction.x * n.x + direction.y * n.y) + direction.z * n.z;
    precise float ratio = lens.film_origin.w / (film.z - lens.rear_z);
    precise float tilted = (cos_film / direction.z) * (ratio * ratio);
    precise float w =
        transmission * (cos2 * cos2) * area * lens.inverse_centre_integral * tilted;
    weight = w;
    // RealLens::camera_from_lens: flipped along the axis, turned by the tilt.
    const float scale = 1.0 / 1000.0;  // physical.rs: MM_PER_WORLD_UNIT
    precise vec3 turned =
        lens_turn(vec3(ray.origin.x, ray.origin.y, lens.entrance_pupil_z - ray.origin.z));
    r.origin = vec3(turned.x * scale, turned.y * scale, turned.z * scale);
    r.direction = lens_turn(vec3(ray.direction.x, ray.direction.y, -ray.direction.z));
    return true;
}

#endif
