// Mirror of lensray-core/src/camera (projective.rs, thin_lens.rs), function by function. The matrices come
// from the Rust `Camera` (struct Camera in the generated interface.glsl): there is no second
// camera here. The camera-ray functions carry the Rust names (GLSL has no methods: a method's
// overload takes its receiver's data from `cam` or `lens`): generate_ray is Camera's (the one
// entry, where the shader binds a lens), ThinLens's and RealLens's; pinhole_ray and
// first_order_ray are Camera's.
#ifndef LENSRAY_CAMERA_GLSL
#define LENSRAY_CAMERA_GLSL

#include "interface.glsl"
#include "sampler.glsl"

struct Ray {
    vec3 origin;
    vec3 direction;
};

vec3 ray_at(Ray r, float t) { return r.origin + r.direction * t; }

// thin_lens.rs: sin_cos_quarter, for |x| <= pi/4.
vec2 sin_cos_quarter(float x) {
    precise float z = x * x;
    precise float s = ((-1.9515296e-4 * z + 8.332161e-3) * z - 1.6666655e-1) * z * x + x;
    precise float c = ((2.4433157e-5 * z - 1.3887316e-3) * z + 4.1666646e-2) * z * z - 0.5 * z + 1.0;
    return vec2(s, c);
}

// thin_lens.rs: concentric_sample_disk
vec2 concentric_sample_disk(vec2 u) {
    vec2 offset = 2.0 * u - vec2(1.0);
    if (offset.x == 0.0 && offset.y == 0.0) {
        return vec2(0.0);
    }
    const float FRAC_PI_4 = 0.78539816339744830962;
    bool x_major = abs(offset.x) > abs(offset.y);
    float radius = x_major ? offset.x : offset.y;
    float t = x_major ? offset.y / offset.x : offset.x / offset.y;
    vec2 sc = sin_cos_quarter(FRAC_PI_4 * t);
    return radius * (x_major ? sc.yx : sc.xy);
}

// aperture/fan.rs: sample_fan. `precise`: no fused multiply-adds, the same roundings as Rust.
vec2 sample_fan(Camera cam, vec2 u) {
    precise vec2 offset = 2.0 * u - vec2(1.0);
    if (offset.x == 0.0 && offset.y == 0.0) {
        return vec2(0.0);
    }
    precise float r;
    precise float a;
    if (abs(offset.x) > abs(offset.y)) {
        r = offset.x;
        a = 0.125 * (offset.y / offset.x);
    } else {
        r = offset.y;
        a = 0.25 - 0.125 * (offset.x / offset.y);
    }
    if (r < 0.0) {
        r = -r;
        a += 0.5;
    }
    if (a < 0.0) {
        a += 1.0;
    }
    uint n = cam.aperture_fan_len;
    precise float s = a * float(n);
    uint i = min(uint(s), n - 1u);
    precise float t = s - float(i);
    uint j = (i + 1u) % n;
    vec4 pair_i = cam.aperture_fan[i / 2u];
    vec4 pair_j = cam.aperture_fan[j / 2u];
    vec2 p0 = (i % 2u == 0u) ? pair_i.xy : pair_i.zw;
    vec2 p1 = (j % 2u == 0u) ? pair_j.xy : pair_j.zw;
    precise vec2 p = r * (p0 + t * (p1 - p0));
    return p;
}

#ifdef GROUP_APERTURE
// The aperture image's tables (aperture/image.rs, ApertureImage::table) are `aperture_table`.

// aperture/image.rs: invert, over the n + 1 values of aperture_table from `start` (a
// branch-free binary search whose steps depend on n only). Returns the interval and the
// position inside it.
vec2 invert_table(uint start, uint n, float u) {
    uint base = 0u;
    for (uint len = n; len > 1u; ) {
        uint half_len = len / 2u;
        base = aperture_table[start + base + half_len] <= u ? base + half_len : base;
        len -= half_len;
    }
    float lo = aperture_table[start + base];
    float hi = aperture_table[start + base + 1u];
    precise float w = (u - lo) / (hi - lo);
    return vec2(float(base), w);
}

// aperture/image.rs: ApertureImage::sample
vec2 sample_aperture_image(Camera cam, vec2 u) {
    uint columns = cam.aperture_image_columns;
    uint rows = cam.aperture_image_rows;
    vec2 row = invert_table(0u, rows, u.y);
    uint start = rows + 1u + uint(row.x) * (columns + 1u);
    vec2 column = invert_table(start, columns, u.x);
    precise float x = (column.x + column.y) / float(columns);
    precise float y = (row.x + row.y) / float(rows);
    precise vec2 p = vec2(2.0 * x - 1.0, 1.0 - 2.0 * y);
    return p;
}
#endif

// aperture/mod.rs: Aperture::unit_point
vec2 aperture_unit_point(Camera cam, vec2 u) {
    precise vec2 p;
#ifdef GROUP_APERTURE
    if (cam.aperture_image_columns > 0u) {
        vec2 q = sample_aperture_image(cam, u);
        vec2 c = cam.aperture_turn.xy;
        p = vec2(c.x * q.x - c.y * q.y, c.y * q.x + c.x * q.y);
    } else
#endif
    if (cam.aperture_fan_len == 0u) {
        p = concentric_sample_disk(u);
    } else {
        p = sample_fan(cam, u);
    }
    precise vec2 squeezed = vec2(p.x, p.y * cam.aperture_aspect);
    return squeezed;
}

// thin_lens.rs: ThinLens::lens_point
vec2 lens_point(Camera cam, vec2 lens_u) {
    precise vec2 p = cam.aperture_radius * aperture_unit_point(cam, lens_u);
    return p;
}

// thin_lens.rs: ThinLens::across. n . v for the plane of focus's normal n = (focus_tilt, 1).
float focus_across(Camera cam, vec3 v) {
    precise float d = cam.focus_tilt.x * v.x + cam.focus_tilt.y * v.y + v.z;
    return d;
}

// thin_lens.rs: ThinLens::generate_ray, in camera space from the aperture-centre ray
// `pinhole` (the focal point in homogeneous form: see there); a closed lens keeps `pinhole`.
Ray generate_ray(Camera cam, Ray pinhole, vec2 lens_u) {
    if (cam.aperture_radius <= 0.0) {
        return pinhole;
    }
    precise float a = cam.focus_distance - focus_across(cam, pinhole.origin);
    precise float b = focus_across(cam, pinhole.direction);
    precise float scale = a / (cam.focus_distance - pinhole.origin.z);
    precise vec2 lens = lens_point(cam, lens_u) * scale;
    Ray r;
    r.origin = pinhole.origin + vec3(lens, 0.0);
    precise vec3 direction = pinhole.direction * a - vec3(lens, 0.0) * b;
    r.direction = normalize(direction);
    return r;
}

// coc.rs: CocLens::radius_pixels. Radius, in pixels, of the circle of confusion of the surface
// at view depth z seen through raster point p_raster.
float coc_radius_pixels(CocLens c, vec2 p_raster, float z) {
    precise float tilt = c.tilt_origin + c.tilt_dx * p_raster.x + c.tilt_dy * p_raster.y;
    precise float off_plane;
    if (c.projection == PROJECTION_PERSPECTIVE) {
        off_plane = (z * (1.0 + tilt) - c.focus_distance) / z;
    } else {
        off_plane = z + tilt - c.focus_distance;
    }
    precise float r = c.scale * abs(off_plane);
    return r;
}

// projective.rs: Camera::pinhole_ray, in camera space.
Ray pinhole_ray(Camera cam, vec2 p_raster) {
    vec3 p_screen = (cam.screen_from_raster * vec4(p_raster, 0.0, 1.0)).xyz;
    Ray r;
    if (cam.projection == PROJECTION_ORTHOGRAPHIC) {
        r.origin = vec3(p_screen.xy, cam.near_z);
        r.direction = vec3(0.0, 0.0, 1.0);
    } else {
        r.origin = vec3(0.0);
        r.direction = normalize(vec3(p_screen.x * cam.near_z, p_screen.y * cam.near_z, cam.near_z));
    }
    return r;
}

// ray.rs: Ray::transformed, by the affine a_from_b.
Ray ray_transformed(Ray ray, mat4 a_from_b) {
    Ray r;
    r.origin = (a_from_b * vec4(ray.origin, 1.0)).xyz;
    r.direction = (a_from_b * vec4(ray.direction, 0.0)).xyz;
    return r;
}

// motion.rs: slerp of unit quaternions (xyzw) along the shorter arc.
vec4 slerp(vec4 a, vec4 b, float f) {
    float c = dot(a, b);
    if (c < 0.0) {
        c = -c;
        b = -b;
    }
    if (c > 0.9995) {
        return normalize(a * (1.0 - f) + b * f);
    }
    float angle = acos(c);
    float inverse_sin = 1.0 / sin(angle);
    return a * (sin((1.0 - f) * angle) * inverse_sin) + b * (sin(f * angle) * inverse_sin);
}

// glam's Quat * Vec3.
vec3 quat_rotate(vec4 q, vec3 v) {
    vec3 b = q.xyz;
    return v * (q.w * q.w - dot(b, b)) + b * (dot(v, b) * 2.0) + cross(b, v) * (q.w * 2.0);
}

// motion.rs: CameraMotion::moment, the moment in the span of a moving camera's sample.
float motion_moment(Camera cam, CameraSample cs) {
    float row_share = clamp(cs.film.y / cam.motion_height, 0.0, 1.0);
    return clamp(cs.time * cam.motion_exposure_share + row_share * cam.motion_rolling_share, 0.0,
                 1.0);
}

// projective.rs: Camera::sample_moment (the span's middle when the shutter takes no time).
float sample_moment(Camera cam, CameraSample cs) {
    return cam.motion_steps == 0u ? 0.5 : motion_moment(cam, cs);
}

// motion.rs: CameraMotion::moment then pose_at; CameraPose::world_point and world_vector.
Ray moving_ray(Camera cam, Ray ray, CameraSample cs) {
    float moment = motion_moment(cam, cs);
    float s = moment * float(cam.motion_steps - 1u);
    uint i = min(uint(s), cam.motion_steps - 2u);
    float f = s - float(i);
    vec3 eye = cam.motion_eye[i].xyz + (cam.motion_eye[i + 1u].xyz - cam.motion_eye[i].xyz) * f;
    vec4 rotation = slerp(cam.motion_rotation[i], cam.motion_rotation[i + 1u], f);
    Ray r;
    r.origin = eye + quat_rotate(rotation, ray.origin * vec3(1.0, 1.0, -1.0));
    r.direction = quat_rotate(rotation, ray.direction * vec3(1.0, 1.0, -1.0));
    return r;
}

// projective.rs: Camera::world_ray.
Ray world_ray(Camera cam, Ray ray, CameraSample cs) {
    if (cam.motion_steps == 0u) {
        return ray_transformed(ray, cam.world_from_camera);
    }
    return moving_ray(cam, ray, cs);
}

// projective.rs: Camera::first_order_ray, in world space.
Ray first_order_ray(Camera cam, CameraSample cs) {
    Ray camera_ray = generate_ray(cam, pinhole_ray(cam, cs.film), cs.lens);
    return world_ray(cam, camera_ray, cs);
}

#ifdef GROUP_LENS
#include "real_lens.glsl"

// projective.rs: Camera::generate_ray, in world space: the lens kind's ray (a pinhole's, a thin
// lens's, or the real lens's at wavelength lambda, nm; 0: the d line). False when the real lens
// blocks it (`r` then the camera-space axis, `weight` 0).
bool generate_ray(Camera cam, CameraSample cs, float lambda, out Ray r, out float weight) {
    Ray camera_ray;
    weight = 1.0;
    if (lens.surface_count != 0u) {
        float k = lambda > 0.0 ? dispersion_offset(lambda) : 0.0;
        vec3 film = lens_film_point(cs.film);
        if (!generate_ray(cam, film, cs.lens, k, camera_ray, weight)) {
            r = camera_ray;
            return false;
        }
    } else if (cam.aperture_radius <= 0.0) {
        camera_ray = pinhole_ray(cam, cs.film);
    } else {
        camera_ray = generate_ray(cam, pinhole_ray(cam, cs.film), cs.lens);
    }
    r = world_ray(cam, camera_ray, cs);
    return true;
}
#endif

#endif
