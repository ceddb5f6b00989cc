#version 460
// The hybrid path's plan on the device, from the G-buffer images: the same rules as the host's
// reference `Plan::new` (src/paths/hybrid.rs, docs/hybrid.md), in four dispatches recorded in
// one command buffer (HybridPlanPush.step):
//   TILES    one workgroup per HYBRID_TILE x HYBRID_TILE tile: each pixel's circle of confusion
//            (0 where nothing is covered), its tile's maximum; each pixel's edge mark (it differs
//            from its right or lower neighbour) into the summed-area table;
//   ROWS     one invocation per row: prefix sums of the marks along the row;
//   COLUMNS  one invocation per column: prefix sums down the column (the table is complete);
//   ENTRIES  one workgroup per tile: the tile's dilated CoC (maximum of the tiles that reach it),
//            per pixel the shortcut or a sample count, per row segment (a tile row) the busiest
//            pixel's count, the plan entries (TRACE_BINDING_PLAN).
// Arithmetic that decides is written as the host writes it (no contraction: `precise`), so the
// plans are equal (tests/hybrid.rs).

#include "camera.glsl"

layout(local_size_x = HYBRID_PLAN_GROUP_SIZE) in;

layout(set = 0, binding = HYBRID_PLAN_BINDING_NORMAL, rgba32f) readonly uniform image2D g_normal;
layout(set = 0, binding = HYBRID_PLAN_BINDING_ALBEDO, rgba32f) readonly uniform image2D g_albedo;
layout(set = 0, binding = HYBRID_PLAN_BINDING_VIEW_DEPTH, r32f) readonly uniform image2D g_depth;
layout(std430, set = 0, binding = HYBRID_PLAN_BINDING_TILES) buffer Tiles { float tile_max[]; };
layout(std430, set = 0, binding = HYBRID_PLAN_BINDING_EDGES) buffer Edges { uint table[]; };
layout(std430, set = 0, binding = HYBRID_PLAN_BINDING_PLAN) writeonly buffer Plan { vec4 plan[]; };
layout(push_constant) uniform PushBlock { HybridPlanPush pc; };

// Non-negative floats order as their bits: maxima by atomicMax on the bits.
shared uint tile_bits;
// Per pixel of the tile: -1 shortcut, else the samples to trace.
shared int counts[HYBRID_TILE][HYBRID_TILE];

const int REACH = int(HYBRID_MAX_REACH_TILES);
const int SIDE = 2 * REACH + 1;

// What the shading depends on differs between pixels a and b (unlit: coverage and albedo; lit:
// also the normal and depth).
bool differs(ivec2 a, ivec2 b) {
    vec4 na = imageLoad(g_normal, a);
    vec4 nb = imageLoad(g_normal, b);
    bool ca = na.w > 0.5;
    bool cb = nb.w > 0.5;
    if (ca != cb || imageLoad(g_albedo, a).xyz != imageLoad(g_albedo, b).xyz) {
        return true;
    }
    if (pc.shading != SHADING_LIT || !ca) {
        return false;
    }
    precise float d = na.x * nb.x + na.y * nb.y + na.z * nb.z;
    float da = imageLoad(g_depth, a).x;
    float db = imageLoad(g_depth, b).x;
    precise float limit = 0.02 * max(abs(da), abs(db));
    return d < 0.995 || abs(da - db) > limit;
}

uint stride() { return pc.width + 1u; }

// The tile this workgroup plans, and its pixel of local index i.
uvec2 tile_pixel(uint i) {
    return gl_WorkGroupID.xy * HYBRID_TILE + uvec2(i % HYBRID_TILE, i / HYBRID_TILE);
}

void step_tiles() {
    uint i = gl_LocalInvocationIndex;
    if (i == 0u) {
        tile_bits = 0u;
    }
    barrier();
    uvec2 p = tile_pixel(i);
    if (p.x < pc.width && p.y < pc.height) {
        ivec2 q = ivec2(p);
        if (imageLoad(g_normal, q).w > 0.5) {
            float coc = coc_radius_pixels(pc.projection, pc.aperture_radius, pc.focus_distance,
                                          pc.near_z, pc.pixels_per_screen_unit,
                                          imageLoad(g_depth, q).x);
            atomicMax(tile_bits, floatBitsToUint(coc));
        }
        bool edge = (p.x + 1u < pc.width && differs(q, q + ivec2(1, 0)))
                 || (p.y + 1u < pc.height && differs(q, q + ivec2(0, 1)));
        table[(p.y + 1u) * stride() + p.x + 1u] = edge ? 1u : 0u;
        // The table's first row and column stay 0.
        if (p.x == 0u) {
            table[(p.y + 1u) * stride()] = 0u;
        }
        if (p.y == 0u) {
            table[p.x + 1u] = 0u;
            if (p.x == 0u) {
                table[0] = 0u;
            }
        }
    }
    barrier();
    if (i == 0u) {
        tile_max[gl_WorkGroupID.y * pc.tiles_x + gl_WorkGroupID.x] = uintBitsToFloat(tile_bits);
    }
}

void step_rows() {
    uint y = gl_GlobalInvocationID.x;
    if (y >= pc.height) {
        return;
    }
    uint at = (y + 1u) * stride() + 1u;
    uint sum = 0u;
    for (uint x = 0u; x < pc.width; ++x) {
        sum += table[at + x];
        table[at + x] = sum;
    }
}

void step_columns() {
    uint x = gl_GlobalInvocationID.x;
    if (x >= pc.width) {
        return;
    }
    uint above = table[stride() + x + 1u];
    for (uint y = 1u; y < pc.height; ++y) {
        uint at = (y + 1u) * stride() + x + 1u;
        above += table[at];
        table[at] = above;
    }
}

// No edge mark within r pixels (Chebyshev) of p, and, for r > 1, that window inside the frame.
bool no_edge_within(uvec2 p, uint r) {
    if (r > 1u && (p.x < r || p.y < r || p.x + r >= pc.width || p.y + r >= pc.height)) {
        return false;
    }
    uint x0 = p.x >= r ? p.x - r : 0u;
    uint y0 = p.y >= r ? p.y - r : 0u;
    uint x1 = min(p.x + r + 1u, pc.width);
    uint y1 = min(p.y + r + 1u, pc.height);
    uint s = stride();
    return table[y1 * s + x1] + table[y0 * s + x0] == table[y0 * s + x1] + table[y1 * s + x0];
}

void step_entries() {
    uint i = gl_LocalInvocationIndex;
    ivec2 tile = ivec2(gl_WorkGroupID.xy);
    if (i == 0u) {
        tile_bits = 0u;
    }
    barrier();
    // Dilation: the tiles within HYBRID_MAX_REACH_TILES whose CoC m reaches this one (Chebyshev
    // distance d in tiles: d <= floor(m / HYBRID_TILE) + 1, i.e. (d - 1) * HYBRID_TILE <= m).
    float best = 0.0;
    for (int k = int(i); k < SIDE * SIDE; k += int(HYBRID_PLAN_GROUP_SIZE)) {
        ivec2 d = ivec2(k % SIDE, k / SIDE) - REACH;
        ivec2 s = tile + d;
        if (s.x < 0 || s.y < 0 || s.x >= int(pc.tiles_x) || s.y >= int(pc.tiles_y)) {
            continue;
        }
        float m = tile_max[uint(s.y) * pc.tiles_x + uint(s.x)];
        int gap = max(max(abs(d.x), abs(d.y)) - 1, 0) * int(HYBRID_TILE);
        if (m > 0.0 && float(gap) <= m) {
            best = max(best, m);
        }
    }
    atomicMax(tile_bits, floatBitsToUint(best));
    barrier();
    float coc = uintBitsToFloat(tile_bits);

    uvec2 p = tile_pixel(i);
    uvec2 local = uvec2(i % HYBRID_TILE, i / HYBRID_TILE);
    int n = -1;
    if (p.x < pc.width && p.y < pc.height) {
        // Beyond the width and height any radius crosses the frame: clamped before converting.
        uint radius = coc < HYBRID_SHORTCUT_COC ? 1u : uint(ceil(min(coc, 1e7))) + 1u;
        uint spp = max(pc.spp, 1u);
        if (no_edge_within(p, radius)) {
            n = -1;
        } else if (!(coc >= HYBRID_SHORTCUT_COC && coc < HYBRID_FULL_SPP_COC)) {
            n = int(spp);
        } else {
            precise float planned = ceil(float(spp) * coc / HYBRID_FULL_SPP_COC);
            n = int(clamp(uint(planned), 1u, spp));
        }
    }
    counts[local.y][local.x] = n;
    barrier();
    // A segment (HYBRID_SEGMENT == HYBRID_TILE: a tile row) traces as long as its busiest pixel:
    // where one pixel traces, all of it traces that many samples.
    int busiest = -1;
    for (uint x = 0u; x < HYBRID_TILE; ++x) {
        busiest = max(busiest, counts[local.y][x]);
    }
    if (p.x < pc.width && p.y < pc.height) {
        uint index = p.y * pc.width + p.x;
        if (busiest < 0) {
            vec3 value = pc.shading == SHADING_LIT ? vec3(0.0) : imageLoad(g_albedo, ivec2(p)).xyz;
            plan[index] = vec4(value, HYBRID_SHORTCUT);
        } else {
            plan[index] = vec4(0.0, 0.0, 0.0, float(busiest));
        }
    }
}

void main() {
    if (pc.step == HYBRID_PLAN_STEP_TILES) {
        step_tiles();
    } else if (pc.step == HYBRID_PLAN_STEP_ROWS) {
        step_rows();
    } else if (pc.step == HYBRID_PLAN_STEP_COLUMNS) {
        step_columns();
    } else {
        step_entries();
    }
}
