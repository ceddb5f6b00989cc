#version 460
// A real lens's ghosts on the GPU: lensray-core's camera/flare/ghosts.rs (FlareLens::distant_source)
// and optics/ghost.rs (ghost_vertex) and optics/coating.rs (Coating::reflectance), in f32.
// Step GHOST_STEP_TRACE: one invocation per grid ray, path and wavelength traces the ray
// unclipped and stores where it meets the film, the share it carries, its stop crossings and the
// rims' reach. Step GHOST_STEP_DRAW: one invocation per grid cell, path and wavelength draws the
// cell as four triangles around its middle, each spreading its power over the film bins whose
// centres it covers, clipped where the interpolated stop crossings fall outside the aperture's
// shape or the rims' reach passes 1; the bins are fixed-point sums (atomicAdd of uints, in any
// order the same), each plane scaled so that its light adds up to at most 2^31.
#include "interface.glsl"
#include "set_ghosts.glsl"
#include "camera.glsl"

layout(local_size_x = GHOST_GROUP_SIZE) in;

layout(push_constant) uniform PushBlock { GhostPush pc; };

// Complex numbers as vec2 (re, im).
vec2 c_mul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 c_div(vec2 a, vec2 b) {
    float d = b.x * b.x + b.y * b.y;
    return vec2(a.x * b.x + a.y * b.y, a.y * b.x - a.x * b.y) / d;
}
// The principal square root of a real number, possibly negative.
vec2 c_sqrt_real(float x) { return x >= 0.0 ? vec2(sqrt(x), 0.0) : vec2(0.0, sqrt(-x)); }
float c_norm_sqr(vec2 a) { return a.x * a.x + a.y * a.y; }
vec2 amplitude(vec2 a, vec2 b) { return c_div(a - b, a + b); }
vec2 layered(vec2 r01, vec2 r12, vec2 phase) {
    vec2 rp = c_mul(r12, phase);
    return c_div(r01 + rp, vec2(1.0, 0.0) + c_mul(r01, rp));
}

// coating.rs: Coating::reflectance. `coating`: (1 if layered, index, thickness nm, unused).
float coating_reflectance(vec4 coating, float n_from, float n_to, float cos_from, float lambda_nm) {
    float c = min(abs(cos_from), 1.0);
    float sin_invariant = n_from * sqrt(max(1.0 - c * c, 0.0));
    float inv2 = sin_invariant * sin_invariant;
    vec2 c0 = c_sqrt_real(n_from * n_from - inv2);
    vec2 c2 = c_sqrt_real(n_to * n_to - inv2);
    if (coating.x == 0.0) {
        vec2 s = amplitude(c0, c2);
        vec2 p = amplitude(c0 / (n_from * n_from), c2 / (n_to * n_to));
        return 0.5 * (c_norm_sqr(s) + c_norm_sqr(p));
    }
    float index = coating.y;
    vec2 c1 = c_sqrt_real(index * index - inv2);
    // delta = 2 pi d c1 / lambda; e^(-2 i delta) = e^(2 Im delta) (cos, sin)(-2 Re delta).
    vec2 delta = 2.0 * PI * coating.z * c1 / lambda_nm;
    vec2 phase = exp(2.0 * delta.y) * vec2(cos(-2.0 * delta.x), sin(-2.0 * delta.x));
    vec2 s = layered(amplitude(c0, c1), amplitude(c1, c2), phase);
    vec2 p0 = c0 / (n_from * n_from);
    vec2 p1 = c1 / (index * index);
    vec2 p2 = c2 / (n_to * n_to);
    vec2 p = layered(amplitude(p0, p1), amplitude(p1, p2), phase);
    return 0.5 * (c_norm_sqr(s) + c_norm_sqr(p));
}

// A ray on its way: the ray, the share it carries, its stop crossings and the rims' reach.
struct GhostRay {
    LensRay ray;
    float share;
    vec2 stops[3];
    uint crossings;
    float rim;
};

// ghost.rs: one step of ghost_vertex at surface s, going toward the film (or the scene),
// refracted (or reflected); `ghost`: the coatings' reflectance counts. False where the ray
// misses the surface or is totally internally reflected.
bool ghost_step(inout GhostRay g, uint s, bool to_film, bool reflects, bool ghost, float k,
                float lambda_nm) {
    float t;
    vec3 normal;
    if (!lens_intersect(s, g.ray, t, normal)) {
        return false;
    }
    vec3 p = g.ray.origin + t * g.ray.direction;
    if (s == lens.stop) {
        if (g.crossings < 3u) {
            g.stops[g.crossings] = p.xy;
        }
        g.crossings += 1u;
        return true;
    }
    float clear_radius = lens.surface_shape[s].z;
    g.rim = max(g.rim, (p.x * p.x + p.y * p.y) / (clear_radius * clear_radius));
    vec4 media = lens.surface_media[s];
    float before = media.x + media.z * k;
    float after = media.y + media.w * k;
    float n_from = to_film ? before : after;
    float n_to = to_film ? after : before;
    float cos_from = -dot(normal, g.ray.direction);
    float reflectance = ghost
        ? coating_reflectance(ghost_coatings[s], n_from, n_to, cos_from, lambda_nm)
        : 0.0;
    vec3 d = g.ray.direction;
    if (reflects) {
        g.share *= reflectance;
        d = d - 2.0 * dot(d, normal) * normal;
    } else {
        g.share *= 1.0 - reflectance;
        vec3 refracted;
        if (!lens_refract(d, normal, n_from / n_to, refracted)) {
            return false;
        }
        d = refracted;
    }
    g.ray.origin = p;
    g.ray.direction = d;
    return true;
}

// The vertices of path `path` at wavelength `w` start here.
uint vertex_plane(uint path, uint w) {
    uint vertices = (pc.grid + 1u) * (pc.grid + 1u);
    return (w * pc.paths + path) * vertices;
}

void trace_vertex(uint index) {
    uint vertices = (pc.grid + 1u) * (pc.grid + 1u);
    uint v = index % vertices;
    uint rest = index / vertices;
    uint path = rest % pc.paths;
    uint w = rest / pc.paths;
    uvec4 route = ghost_paths[path];
    bool ghost = route.z == 1u;
    float lambda_nm = ghost_wavelengths[w].x;
    float k = ghost_wavelengths[w].y;
    vec3 direction = vec3(pc.sin_field, 0.0, pc.cos_field);
    uint gx = v % (pc.grid + 1u);
    uint gy = v / (pc.grid + 1u);
    float grid = float(pc.grid);
    vec2 at = (2.0 * vec2(float(gx), float(gy)) - grid) / grid * pc.front_radius;
    GhostRay g;
    g.ray.origin = vec3(at, 0.0) - direction / direction.z;
    g.ray.direction = direction;
    g.share = 1.0;
    g.stops[0] = vec2(0.0);
    g.stops[1] = vec2(0.0);
    g.stops[2] = vec2(0.0);
    g.crossings = 0u;
    g.rim = 0.0;
    uint n = lens.surface_count;
    bool traced = true;
    if (!ghost) {
        for (uint s = 0u; s < n && traced; ++s) {
            traced = ghost_step(g, s, true, false, false, k, lambda_nm);
        }
    } else {
        uint i = route.x;
        uint j = route.y;
        for (uint s = 0u; s < j && traced; ++s) {
            traced = ghost_step(g, s, true, false, true, k, lambda_nm);
        }
        traced = traced && ghost_step(g, j, true, true, true, k, lambda_nm);
        for (uint s = j - 1u; s > i && traced; --s) {
            traced = traced && ghost_step(g, s, false, false, true, k, lambda_nm);
        }
        traced = traced && ghost_step(g, i, false, true, true, k, lambda_nm);
        for (uint s = i + 1u; s < n && traced; ++s) {
            traced = ghost_step(g, s, true, false, true, k, lambda_nm);
        }
    }
    vec3 d = g.ray.direction;
    traced = traced && d.z > 0.0;
    uint at_vertex = (vertex_plane(path, w) + v) * GHOST_VERTEX_VEC4S;
    if (!traced) {
        ghost_vertices[at_vertex + 2u] = vec4(0.0);
        return;
    }
    float t = (lens.film_z - g.ray.origin.z) / d.z;
    vec2 film = (g.ray.origin.xy + t * d.xy) / pc.bin_mm;
    ghost_vertices[at_vertex] = vec4(film, g.share, g.rim);
    ghost_vertices[at_vertex + 1u] = vec4(g.stops[0], g.stops[1]);
    ghost_vertices[at_vertex + 2u] = vec4(g.stops[2], float(g.crossings), 1.0);
}

// A grid cell's corner: its film point (bins), share, rims' reach, stop crossings.
struct Corner {
    vec2 at;
    float share;
    float rim;
    vec2 stops[3];
};

Corner corner_at(uint at_vertex) {
    vec4 a = ghost_vertices[at_vertex];
    vec4 b = ghost_vertices[at_vertex + 1u];
    vec4 c = ghost_vertices[at_vertex + 2u];
    Corner corner;
    corner.at = a.xy;
    corner.share = a.z;
    corner.rim = a.w;
    corner.stops[0] = b.xy;
    corner.stops[1] = b.zw;
    corner.stops[2] = c.xy;
    return corner;
}

// ghosts.rs: FlareLens::clear. What passes at barycentric weights `w` of triangle (a, b, c).
float clear_at(Corner a, Corner b, Corner c, vec3 w, uint crossings) {
    float rim = w.x * a.rim + w.y * b.rim + w.z * c.rim;
    if (rim > 1.0) {
        return 0.0;
    }
    float passed = 1.0;
    for (uint i = 0u; i < min(crossings, 3u); ++i) {
        vec2 p = w.x * a.stops[i] + w.y * b.stops[i] + w.z * c.stops[i];
        passed *= aperture_transmission(cam, p / lens.stop_radius);
    }
    return passed;
}

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

void deposit(uint plane, uint column, uint row, float value, float scale) {
    uint units = uint(value * scale + 0.5);
    if (units > 0u) {
        atomicAdd(ghost_film[plane + row * pc.columns + column], units);
    }
}

// ghosts.rs: FlareLens::draw_triangle.
void draw_triangle(Corner a, Corner b, Corner c, float power, uint crossings, uint plane,
                   float scale) {
    float area = cross2(b.at - a.at, c.at - a.at);
    vec2 half_size = 0.5 * vec2(float(pc.columns), float(pc.rows));
    vec2 low = min(min(a.at, b.at), c.at) + half_size;
    vec2 high = max(max(a.at, b.at), c.at) + half_size;
    vec2 span = max(high - low, vec2(0.0));
    if (span.x * span.y > GHOST_LARGEST_TRIANGLE_SHARE * float(pc.columns * pc.rows)) {
        return;
    }
    int c0 = max(int(ceil(low.x - 0.5)), 0);
    int r0 = max(int(ceil(low.y - 0.5)), 0);
    int c1 = min(int(floor(high.x - 0.5)), int(pc.columns) - 1);
    int r1 = min(int(floor(high.y - 0.5)), int(pc.rows) - 1);
    uint covered = 0u;
    for (int row = r0; row <= r1 && area != 0.0; ++row) {
        for (int column = c0; column <= c1; ++column) {
            vec2 p = vec2(float(column) + 0.5, float(row) + 0.5) - half_size;
            vec3 w = vec3(cross2(c.at - b.at, p - b.at), cross2(a.at - c.at, p - c.at),
                          cross2(b.at - a.at, p - a.at)) / area;
            covered += (w.x >= 0.0 && w.y >= 0.0 && w.z >= 0.0) ? 1u : 0u;
        }
    }
    if (covered == 0u) {
        vec2 p = (a.at + b.at + c.at) / 3.0 + half_size;
        vec2 cell = floor(p);
        if (cell.x >= 0.0 && cell.y >= 0.0 && cell.x < float(pc.columns) &&
            cell.y < float(pc.rows)) {
            float value = power * clear_at(a, b, c, vec3(1.0 / 3.0), crossings);
            deposit(plane, uint(cell.x), uint(cell.y), value, scale);
        }
        return;
    }
    float each = power / float(covered);
    for (int row = r0; row <= r1; ++row) {
        for (int column = c0; column <= c1; ++column) {
            vec2 p = vec2(float(column) + 0.5, float(row) + 0.5) - half_size;
            vec3 w = vec3(cross2(c.at - b.at, p - b.at), cross2(a.at - c.at, p - c.at),
                          cross2(b.at - a.at, p - a.at)) / area;
            if (w.x >= 0.0 && w.y >= 0.0 && w.z >= 0.0) {
                deposit(plane, uint(column), uint(row), each * clear_at(a, b, c, w, crossings),
                        scale);
            }
        }
    }
}

void draw_cell(uint index) {
    uint cells = pc.grid * pc.grid;
    uint cell = index % cells;
    uint rest = index / cells;
    uint path = rest % pc.paths;
    uint w = rest / pc.paths;
    uint gx = cell % pc.grid;
    uint gy = cell / pc.grid;
    uint row = pc.grid + 1u;
    uint base = vertex_plane(path, w);
    uint corners[4] = uint[4](gy * row + gx, gy * row + gx + 1u, (gy + 1u) * row + gx + 1u,
                              (gy + 1u) * row + gx);
    Corner q[4];
    for (uint i = 0u; i < 4u; ++i) {
        uint at_vertex = (base + corners[i]) * GHOST_VERTEX_VEC4S;
        if (ghost_vertices[at_vertex + 2u].w == 0.0) {
            return;
        }
        q[i] = corner_at(at_vertex);
    }
    uint crossings = uint(ghost_vertices[(base + corners[0]) * GHOST_VERTEX_VEC4S + 2u].z);
    Corner middle;
    middle.at = 0.25 * (q[0].at + q[1].at + q[2].at + q[3].at);
    middle.share = 0.25 * (q[0].share + q[1].share + q[2].share + q[3].share);
    middle.rim = 0.25 * (q[0].rim + q[1].rim + q[2].rim + q[3].rim);
    for (uint i = 0u; i < 3u; ++i) {
        middle.stops[i] = 0.25 * (q[0].stops[i] + q[1].stops[i] + q[2].stops[i] + q[3].stops[i]);
    }
    float power = 0.25 * pc.cell_share * middle.share;
    if (power <= 0.0) {
        return;
    }
    bool ghost = ghost_paths[path].z == 1u;
    uint plane = (2u * w + (ghost ? 0u : 1u)) * pc.columns * pc.rows;
    float scale = ghost ? ghost_wavelengths[w].z : ghost_wavelengths[w].w;
    for (uint i = 0u; i < 4u; ++i) {
        draw_triangle(q[i], q[(i + 1u) % 4u], middle, power, crossings, plane, scale);
    }
}

void main() {
    uint index = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x
        * GHOST_GROUP_SIZE;
    if (pc.step == GHOST_STEP_TRACE) {
        uint vertices = (pc.grid + 1u) * (pc.grid + 1u);
        if (index < vertices * pc.paths * pc.wavelengths) {
            trace_vertex(index);
        }
    } else {
        uint cells = pc.grid * pc.grid;
        if (index < cells * pc.paths * pc.wavelengths) {
            draw_cell(index);
        }
    }
}
