#version 460
// The hybrid path's plan on the device, from the G-buffer images: the same rules as the host's
// reference `Plan::new` (src/probes/hybrid_plan.rs, docs/hybrid.md), in four dispatches recorded in
// one command buffer (HybridPlanPush.step), one invocation per tile, row, column or segment (no
// barriers or shared memory: CPU drivers pay much for them):
//   (lit: trace.comp's pre-pass first: each pixel's shortcut value and shadow state)
//   TILES    per tile: each pixel's circle of confusion (0 where nothing is covered), the tile's
//            maximum; each pixel's edge mark (it differs from its right or lower neighbour)
//            into the summed-area table;
//   ROWS     per row: prefix sums of the marks along the row;
//   COLUMNS  per column: prefix sums down the column (the table is complete);
//   DILATE   per tile: its dilated CoC (maximum of the tiles that reach it);
//   ENTRIES  per row segment (a tile row: its pixels share the tile's CoC): per pixel the
//            shortcut or the sample count, the segment's shared decision, the plan entries
//            (the trace pass's `plan`).
// Arithmetic that decides is written as the host writes it (no contraction: `precise`), so the
// plans are equal (tests/hybrid.rs).

#include "set_hybrid_plan.glsl"
#include "camera.glsl"

layout(local_size_x = HYBRID_PLAN_GROUP_SIZE) in;

layout(push_constant) uniform PushBlock { HybridPlanPush pc; };

const int REACH = int(HYBRID_MAX_REACH_TILES);
const int SIDE = 2 * REACH + 1;

// What the shading depends on differs between pixels a and b (unlit: coverage and albedo; lit:
// also the normal, the depth and whether the light is blocked, from the pre-pass: a shadow
// boundary, which no G-buffer shows).
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
    bool shadow_edge = plan[a.y * int(pc.width) + a.x].w != plan[b.y * int(pc.width) + b.x].w;
    return d < 0.995 || abs(da - db) > limit || shadow_edge;
}

uint stride() { return pc.width + 1u; }

// One invocation per tile (serial over its pixels: no barriers, which cost much on CPU
// drivers).
void step_tiles() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= pc.tiles_x * pc.tiles_y) {
        return;
    }
    uvec2 corner = uvec2(t % pc.tiles_x, t / pc.tiles_x) * HYBRID_TILE;
    float tile = 0.0;
    for (uint ly = 0u; ly < HYBRID_TILE; ++ly) {
        for (uint lx = 0u; lx < HYBRID_TILE; ++lx) {
            uvec2 p = corner + uvec2(lx, ly);
            if (p.x >= pc.width || p.y >= pc.height) {
                continue;
            }
            ivec2 q = ivec2(p);
            if (imageLoad(g_normal, q).w > 0.5) {
                tile = max(tile, coc_radius_pixels(pc.coc, vec2(p) + 0.5,
                                                   imageLoad(g_depth, q).x));
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
    }
    tile_max[t] = tile;
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

// One invocation per tile: its dilated CoC, the maximum of the tiles within
// HYBRID_MAX_REACH_TILES whose CoC m reaches it (Chebyshev distance d in tiles:
// d <= floor(m / HYBRID_TILE) + 1, i.e. (d - 1) * HYBRID_TILE <= m), after the tiles' own.
void step_dilate() {
    uint t = gl_GlobalInvocationID.x;
    uint count = pc.tiles_x * pc.tiles_y;
    if (t >= count) {
        return;
    }
    ivec2 tile = ivec2(t % pc.tiles_x, t / pc.tiles_x);
    float best = 0.0;
    for (int dy = -REACH; dy <= REACH; ++dy) {
        int y = tile.y + dy;
        if (y < 0 || y >= int(pc.tiles_y)) {
            continue;
        }
        for (int dx = -REACH; dx <= REACH; ++dx) {
            int x = tile.x + dx;
            if (x < 0 || x >= int(pc.tiles_x)) {
                continue;
            }
            float m = tile_max[uint(y) * pc.tiles_x + uint(x)];
            int gap = max(max(abs(dx), abs(dy)) - 1, 0) * int(HYBRID_TILE);
            if (m > 0.0 && float(gap) <= m) {
                best = max(best, m);
            }
        }
    }
    tile_max[count + t] = best;
}

// One invocation per segment (HYBRID_SEGMENT == HYBRID_TILE: a tile row): per pixel the
// shortcut or the samples to trace (every one); where one pixel traces, all of the segment
// traces; the entries.
void step_entries() {
    uint g = gl_GlobalInvocationID.x;
    if (g >= pc.tiles_x * pc.height) {
        return;
    }
    uint y = g / pc.tiles_x;
    uint tx = g % pc.tiles_x;
    float coc = tile_max[pc.tiles_x * pc.tiles_y + (y / HYBRID_TILE) * pc.tiles_x + tx];
    // src/probes/hybrid_plan.rs: window_radius (why 1 + floor(coc + 1/2)). Beyond the width and
    // height any radius crosses the frame: clamped before converting.
    uint radius = 1u + uint(floor(min(coc, 1e7) + HYBRID_SHORTCUT_COC));
    // A traced pixel traces every sample (as the host's plan).
    uint planned = max(pc.spp, 1u);
    uint x0 = tx * HYBRID_TILE;
    uint x1 = min(x0 + HYBRID_TILE, pc.width);
    // Every pixel of a segment has the same CoC: one window radius.
    bool traces = false;
    for (uint x = x0; x < x1; ++x) {
        traces = traces || !no_edge_within(uvec2(x, y), radius);
    }
    for (uint x = x0; x < x1; ++x) {
        uint index = y * pc.width + x;
        // Lit, every pixel keeps the pre-pass's value in xyz: the shortcut samples of its
        // neighbours reproject onto it (trace.comp).
        vec3 value = pc.shading == SHADING_LIT ? plan[index].xyz : vec3(0.0);
        // The surface's depth at the pixel centre, for the lit reprojection (trace.comp).
        ivec2 q = ivec2(x, y);
        surface_depth[index] = imageLoad(g_normal, q).w > 0.5 ? imageLoad(g_depth, q).x : 0.0;
        if (traces) {
            plan[index] = vec4(value, float(planned));
        } else {
            if (pc.shading != SHADING_LIT) {
                value = imageLoad(g_albedo, ivec2(x, y)).xyz;
            }
            plan[index] = vec4(value, HYBRID_SHORTCUT);
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
    } else if (pc.step == HYBRID_PLAN_STEP_DILATE) {
        step_dilate();
    } else {
        step_entries();
    }
}
