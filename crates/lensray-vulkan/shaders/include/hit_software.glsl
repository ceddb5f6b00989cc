// The hit interface (see shading.glsl) answered by a stack-based traversal of the project's own
// BVH (lensray-vulkan/src/scene/bvh.rs): nodes hold both children's boxes (one fetch, two slab tests), leaves are
// named by their parent (first triangle, count), triangles are stored in leaf order. Ordered
// traversal: leaves are tested as soon as their box is hit (shortening the ray), then the nearer
// inner child is visited first and the other pushed with its entry distance, so that a popped
// node beyond the closest hit so far costs no fetch (+4% rays/s on the default scene). A stack
// in shared memory instead of this local array measured ~3% slower on lavapipe. The triangle test is Woop, Benthin and
// Wald's watertight one, as in the CPU reference (lensray-core/src/reference/triangle.rs). Needs no
// extension: runs on any Vulkan 1.2 device.
#ifndef LENSRAY_HIT_SOFTWARE_GLSL
#define LENSRAY_HIT_SOFTWARE_GLSL

// Far ends of slab intervals are scaled up by this (1 + 2 gamma(3), Ize 2013) so rounding never
// culls a box that the triangle test would hit.
const float SLAB_FAR_SCALE = 1.0000004;
// Direction components smaller than this are replaced by it (keeping the sign): finite inverses.
const float MIN_DIRECTION = 1e-20;

struct TraversalRay {
    vec3 origin;
    vec3 inv_direction;
    vec3 origin_inv;  // origin * inv_direction: slabs as one fma per plane
    // The watertight test's frame (axis permutation, then shear) as three rows: the ray becomes
    // +z and the test works on the xy projection.
    vec3 shear_x;
    vec3 shear_y;
    vec3 shear_z;
};

vec3 unit_axis(uint k) { return vec3(equal(uvec3(k), uvec3(0u, 1u, 2u))); }

TraversalRay traversal_ray(vec3 origin, vec3 direction) {
    TraversalRay r;
    r.origin = origin;
    vec3 small = mix(vec3(MIN_DIRECTION), vec3(-MIN_DIRECTION), lessThan(direction, vec3(0.0)));
    vec3 safe = mix(direction, small, lessThan(abs(direction), vec3(MIN_DIRECTION)));
    r.inv_direction = 1.0 / safe;
    r.origin_inv = origin * r.inv_direction;

    vec3 a = abs(direction);
    uint kz = a.x > a.y ? (a.x > a.z ? 0u : 2u) : (a.y > a.z ? 1u : 2u);
    uint kx = kz == 2u ? 0u : kz + 1u;
    uint ky = kx == 2u ? 0u : kx + 1u;
    // Keep the projected winding independent of the direction's sign.
    if (direction[kz] < 0.0) {
        uint swap = kx;
        kx = ky;
        ky = swap;
    }
    float inv_z = 1.0 / direction[kz];
    vec3 ez = unit_axis(kz);
    r.shear_x = unit_axis(kx) - direction[kx] * inv_z * ez;
    r.shear_y = unit_axis(ky) - direction[ky] * inv_z * ez;
    r.shear_z = inv_z * ez;
    return r;
}

vec3 to_ray_frame(TraversalRay r, vec3 p) {
    vec3 q = p - r.origin;
    return vec3(dot(r.shear_x, q), dot(r.shear_y, q), dot(r.shear_z, q));
}

// The hit of triangle `slot` with t in (0, t_max): t and the weights of v1, v2.
bool intersect_triangle(TraversalRay r, uint slot, float t_max, out float t, out vec2 barycentrics) {
    BvhTriangle tri = bvh_triangles[slot];
    vec3 a = to_ray_frame(r, tri.v0.xyz);
    vec3 b = to_ray_frame(r, tri.v1.xyz);
    vec3 c = to_ray_frame(r, tri.v2.xyz);
    // Edge functions, unfused: a shared edge gives exactly opposite values in both triangles.
    precise float u = c.x * b.y - c.y * b.x;
    precise float v = a.x * c.y - a.y * c.x;
    precise float w = b.x * a.y - b.y * a.x;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) {
        return false;
    }
    float det = u + v + w;
    if (det == 0.0) {
        return false;
    }
    float t_scaled = u * a.z + v * b.z + w * c.z;
    // The range test on the scaled distance: the division only for hits.
    float s = det < 0.0 ? -1.0 : 1.0;
    if (!(t_scaled * s > 0.0 && t_scaled * s < t_max * (det * s))) {
        return false;
    }
    float inv_det = 1.0 / det;
    t = t_scaled * inv_det;
    barycentrics = vec2(v, w) * inv_det;
    return true;
}

// Entry distance of the ray into the box [lo, hi], or a negative value for a miss (the box
// ahead of t_max only).
float slab_entry(TraversalRay r, vec3 lo, vec3 hi, float t_max) {
    vec3 t0 = lo * r.inv_direction - r.origin_inv;
    vec3 t1 = hi * r.inv_direction - r.origin_inv;
    vec3 near3 = min(t0, t1);
    vec3 far3 = max(t0, t1);
    float near = max(max(near3.x, near3.y), max(near3.z, 0.0));
    float far = min(min(far3.x, far3.y), min(far3.z, t_max)) * SLAB_FAR_SCALE;
    return near <= far ? near : -1.0;
}

// The closest hit with t in (0, t_max), or with `any_hit` the first one found.
bool traverse(vec3 origin, vec3 direction, float t_max, bool any_hit, BlendCut cut,
              out uint hit_slot, out float hit_t, out vec2 hit_barycentrics) {
    TraversalRay r = traversal_ray(origin, direction);
    uint stack[BVH_STACK_SIZE];
    // Entry distance of each pushed node: popped nodes beyond the closest hit are skipped.
    float stack_near[BVH_STACK_SIZE];
    uint depth = 0u;
    uint node = 0u;
    bool found = false;
    hit_slot = 0u;
    hit_t = t_max;
    hit_barycentrics = vec2(0.0);
    while (true) {
        BvhNode n = bvh_nodes[node];
        float near_a = slab_entry(r, vec3(n.a_xy.xz, n.ab_z.x), vec3(n.a_xy.yw, n.ab_z.y), hit_t);
        float near_b = slab_entry(r, vec3(n.b_xy.xz, n.ab_z.z), vec3(n.b_xy.yw, n.ab_z.w), hit_t);
        uvec4 children = n.children;
        // Leaf children now: their hits shorten the ray before the inner children are chosen.
        for (uint k = 0u; k < 2u; ++k) {
            uint count = k == 0u ? children.z : children.w;
            float near = k == 0u ? near_a : near_b;
            if (count == 0u || near < 0.0) {
                continue;
            }
            uint first = k == 0u ? children.x : children.y;
            for (uint slot = first; slot < first + count; ++slot) {
                float t;
                vec2 bary;
                if (intersect_triangle(r, slot, hit_t, t, bary)
                    && (!SURFACES_ALPHA_TESTED
                        || triangle_stops_ray(uint(bvh_triangles[slot].v0.w), bary, cut))) {
                    found = true;
                    hit_t = t;
                    hit_slot = slot;
                    hit_barycentrics = bary;
                    if (any_hit) {
                        return true;
                    }
                }
            }
        }
        bool visit_a = children.z == 0u && near_a >= 0.0 && near_a <= hit_t;
        bool visit_b = children.w == 0u && near_b >= 0.0 && near_b <= hit_t;
        if (visit_a && visit_b) {
            bool b_first = near_b < near_a;
            node = b_first ? children.y : children.x;
            stack[depth] = b_first ? children.x : children.y;
            stack_near[depth] = b_first ? near_a : near_b;
            depth += 1u;
        } else if (visit_a || visit_b) {
            node = visit_a ? children.x : children.y;
        } else {
            while (depth > 0u && stack_near[depth - 1u] > hit_t) {
                depth -= 1u;
            }
            if (depth == 0u) {
                break;
            }
            depth -= 1u;
            node = stack[depth];
        }
    }
    return found;
}

// The closest hit with t in (0, t_max) that stops a ray cutting BLEND surfaces with `cut`: the
// global triangle index, t and the weights of v1, v2.
bool closest_hit(vec3 origin, vec3 direction, float t_max, BlendCut cut, out Hit hit) {
    uint slot;
    bool found = traverse(origin, direction, t_max, false, cut, slot, hit.t, hit.barycentrics);
    // Exact: the index is below 2^24 (lensray-vulkan/src/scene/bvh.rs).
    hit.triangle = found ? uint(bvh_triangles[slot].v0.w) : 0u;
    return found;
}

// Whether a surface that stops the ray lies along it with t in (0, t_max); the first ends the
// traversal.
bool occluded(vec3 origin, vec3 direction, float t_max, BlendCut cut) {
    uint slot;
    float t;
    vec2 barycentrics;
    return traverse(origin, direction, t_max, true, cut, slot, t, barycentrics);
}

#endif
