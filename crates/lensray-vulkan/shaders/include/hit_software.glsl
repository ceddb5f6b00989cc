// The hit interface (see shading.glsl) answered by a stack-based traversal of the project's own
// BVH (lensray-vulkan/src/scene/bvh.rs): the compressed 8-wide BVH of Ylitie, Karras and Laine
// (2017). A node holds up to eight children's boxes quantized on a grid (one 80-byte fetch, eight
// slab tests on the decoded planes), leaves of 1 to 3 triangles are named by their parent,
// triangles are stored in leaf order. The stack holds node groups (a first child index and a
// mask of the children still to visit), visited nearest-first by the ray's octant (the build
// orders each node's child slots by direction); a leaf's triangles are tested as soon as its box
// is hit, shortening the ray before the next node is fetched. The closest hit is the smallest t,
// ties going to the smallest triangle index, so the order candidates are met in never changes
// the result. The triangle test is Woop, Benthin and Wald's watertight one, as in the CPU
// reference (lensray-core/src/reference/triangle.rs). Needs no extension: runs on any Vulkan 1.2
// device.
#ifndef LENSRAY_HIT_SOFTWARE_GLSL
#define LENSRAY_HIT_SOFTWARE_GLSL

#extension GL_EXT_control_flow_attributes : require

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

// The hit of triangle `slot` with t in (0, t_max): t and the weights of v1, v2. A triangle that
// moves while the shutter is open (v1.w 1) is met where trace_moment has it.
bool intersect_triangle(TraversalRay r, uint slot, float t_max, out float t, out vec2 barycentrics) {
    BvhTriangle tri = bvh_triangles[slot];
    if (tri.v1.w != 0.0) {
        uint first = 3u * uint(tri.v0.w);
        tri.v0.xyz = vertex_position(indices[first]);
        tri.v1.xyz = vertex_position(indices[first + 1u]);
        tri.v2.xyz = vertex_position(indices[first + 2u]);
    }
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
    // det < 0: the ray sees the triangle clockwise, its back face (the CPU reference's
    // is_back_face); a single-sided triangle lets it pass.
    if (det == 0.0
        || (SURFACES_SINGLE_SIDED && det < 0.0 && triangle_single_sided(uint(tri.v0.w)))) {
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

// The ray's octant as the build orders child slots (obvhs's octant, inverted): 4 for x >= 0,
// 2 for y >= 0, 1 for z >= 0.
uint traversal_octant(vec3 direction) {
    return (direction.x < 0.0 ? 0u : 4u) | (direction.y < 0.0 ? 0u : 2u)
        | (direction.z < 0.0 ? 0u : 1u);
}

// The children of node `index` whose boxes the ray enters before t_max: `nodes` is the group of
// its child nodes (first index; bit 24 + (slot ^ octant) for each hit, the node mask in bits
// 0-7), `triangles` the group of its hit leaves' triangles (first slot; a bit a triangle).
void intersect_node(TraversalRay r, uint index, uint octant, float t_max, out uvec2 nodes,
                    out uvec2 triangles) {
    BvhNode n = bvh_nodes[index];
    vec3 origin = uintBitsToFloat(n.header.xyz);
    uint packed = n.header.w;
    vec3 cell = uintBitsToFloat((uvec3(packed, packed >> 8u, packed >> 16u) & 0xffu) << 23u);
    uint imask = packed >> 24u;
    // The ray in the node's grid (Ylitie et al.): a plane q cells from the origin is met at
    // q * cell_t + origin_t, one fma a plane. cell_t is exact (cells are powers of two).
    vec3 cell_t = cell * r.inv_direction;
    vec3 origin_t = origin * r.inv_direction - r.origin_inv;
    // Along a negative direction the upper plane is met first: the near and far planes are
    // chosen once a node, and t grows with q along each axis (fma is monotonic), so each
    // child's entry and exit are the slab test's min and max without computing both.
    bvec3 negative = lessThan(r.inv_direction, vec3(0.0));
    uvec4 x = negative.x ? n.x_planes.zwxy : n.x_planes;
    uvec4 y = negative.y ? n.y_planes.zwxy : n.y_planes;
    uvec4 z = negative.z ? n.z_planes.zwxy : n.z_planes;
    uint hits = 0u;
    [[unroll]] for (uint i = 0u; i < 8u; ++i) {
        uint word = i >> 2u;
        uint shift = (i & 3u) * 8u;
        // An empty child's meta is 0: it sets no bit, so it needs no branch.
        uint meta = (n.links[2u + word] >> shift) & 0xffu;
        vec3 q_near = vec3((uvec3(x[word], y[word], z[word]) >> shift) & 0xffu);
        vec3 q_far = vec3((uvec3(x[word + 2u], y[word + 2u], z[word + 2u]) >> shift) & 0xffu);
        vec3 t_near = q_near * cell_t + origin_t;
        vec3 t_far = q_far * cell_t + origin_t;
        float near = max(max(t_near.x, t_near.y), max(t_near.z, 0.0));
        float far = min(min(t_far.x, t_far.y), min(t_far.z, t_max)) * SLAB_FAR_SCALE;
        bool inner = ((imask >> i) & 1u) != 0u;
        uint bits = (meta >> 5u) << ((meta & 0x1fu) ^ (inner ? octant : 0u));
        hits |= near <= far ? bits : 0u;
    }
    nodes = uvec2(n.links.x, (hits & 0xff000000u) | imask);
    triangles = uvec2(n.links.y, hits & 0x00ffffffu);
}

// The closest hit with t in (0, t_max), or with `any_hit` the first one found.
bool traverse(vec3 origin, vec3 direction, float t_max, bool any_hit, BlendCut cut,
              out uint hit_slot, out float hit_t, out vec2 hit_barycentrics) {
    TraversalRay r = traversal_ray(origin, direction);
    uint octant = traversal_octant(direction);
    uvec2 stack[BVH_STACK_SIZE];
    uint depth = 0u;
    // The root, as the one child node of a group at node 0.
    uvec2 nodes = uvec2(0u, 0x80000000u);
    uvec2 triangles = uvec2(0u);
    bool found = false;
    uint hit_index = 0u;
    hit_slot = 0u;
    hit_t = t_max;
    hit_barycentrics = vec2(0.0);
    while (true) {
        if ((nodes.y & 0xff000000u) != 0u) {
            uint bit = findMSB(nodes.y);
            nodes.y &= ~(1u << bit);
            uint slot = (bit - 24u) ^ octant;
            // Child nodes are stored in slot order: those in lower slots come first.
            uint node = nodes.x + bitCount(nodes.y & ~(0xffffffffu << slot));
            if ((nodes.y & 0xff000000u) != 0u) {
                stack[depth] = nodes;
                depth += 1u;
            }
            intersect_node(r, node, octant, hit_t, nodes, triangles);
        }
        while (triangles.y != 0u) {
            uint bit = findMSB(triangles.y);
            triangles.y &= ~(1u << bit);
            uint slot = triangles.x + bit;
            // Up to the closest hit so far and two ulps beyond it: a hit at the same t passes
            // the scaled range test, and the rule below decides.
            float bound = found ? uintBitsToFloat(floatBitsToUint(hit_t) + 2u) : t_max;
            float t;
            vec2 bary;
            if (!intersect_triangle(r, slot, bound, t, bary)) {
                continue;
            }
            uint index = uint(bvh_triangles[slot].v0.w);
            bool closer = !found || t < hit_t || (t == hit_t && index < hit_index);
            if (closer && (!SURFACES_ALPHA_TESTED || triangle_stops_ray(index, bary, cut))) {
                found = true;
                hit_t = t;
                hit_slot = slot;
                hit_index = index;
                hit_barycentrics = bary;
                if (any_hit) {
                    return true;
                }
            }
        }
        if ((nodes.y & 0xff000000u) == 0u) {
            if (depth == 0u) {
                break;
            }
            depth -= 1u;
            nodes = stack[depth];
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
