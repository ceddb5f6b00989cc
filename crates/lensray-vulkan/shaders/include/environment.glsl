#ifndef LENSRAY_ENVIRONMENT_GLSL
#define LENSRAY_ENVIRONMENT_GLSL

// An environment map and its sampling by power: the mirror of
// lensray-core/src/scene/environment/{mod,sampling}.rs, op for op, so that the same point draws
// the same texel. Needs EnvironmentGroup's buffers (`environment`, `env_texels`,
// `env_row_cdfs`, `env_rows_cdf`) and PI.

// The image coordinates ([0, 1)^2, u across, v down) world direction d (unit) sees: the turn
// undone (a counter-clockwise turn seen from above takes +X towards -Z), then +Y up, the
// centre column along -Z, u growing towards +X.
vec2 env_uv_from_world(vec3 d) {
    float c = environment.turn.x;
    float s = environment.turn.y;
    float x = c * d.x - s * d.z;
    float z = s * d.x + c * d.z;
    float u = 0.5 + atan(x, -z) / (2.0 * PI);
    float v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    return vec2(u - floor(u), v);
}

// The world direction (unit) at image coordinates uv.
vec3 env_world_from_uv(vec2 uv) {
    float phi = (uv.x - 0.5) * (2.0 * PI);
    float theta = uv.y * PI;
    float sin_theta = sin(theta);
    vec3 d = vec3(sin_theta * sin(phi), cos(theta), -sin_theta * cos(phi));
    float c = environment.turn.x;
    float s = environment.turn.y;
    return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// The texel (column, row) uv falls in.
uvec2 env_texel_at(vec2 uv) {
    uint column = min(uint(uv.x * float(environment.width)), environment.width - 1u);
    uint row = min(uint(uv.y * float(environment.height)), environment.height - 1u);
    return uvec2(column, row);
}

vec3 env_texel(uvec2 texel) {
    return env_texels[texel.y * environment.width + texel.x].rgb * environment.intensity;
}

// Radiance arriving from direction d (unit, pointing away from the scene).
vec3 env_radiance(vec3 d) {
    return env_texel(env_texel_at(env_uv_from_world(d)));
}

// Density per solid angle of texel (column, row) at image height v.
float env_texel_pdf(uvec2 texel, float v) {
    uint base = texel.y * (environment.width + 1u) + texel.x;
    float weight = env_row_cdfs[base + 1u] - env_row_cdfs[base];
    float sin_theta = sin(v * PI);
    if (weight <= 0.0 || sin_theta <= 0.0) {
        return 0.0;
    }
    float pdf_uv = weight / environment.total * float(environment.width * environment.height);
    return pdf_uv / (2.0 * PI * PI * sin_theta);
}

// Density per solid angle of drawing direction d (unit).
float env_pdf(vec3 d) {
    vec2 uv = env_uv_from_world(d);
    return env_texel_pdf(env_texel_at(uv), uv.y);
}

// The interval of a cumulative table (entries first .. first + count, from 0, increasing) x
// falls in, and where in it (x: the interval's index, y: 0..1): the last entry whose start is
// at most x, stepping back over empty intervals at the end. `rows` picks the table: the rows'
// (env_rows_cdf) or a row's (env_row_cdfs from first).
vec2 env_invert(bool rows, uint first, uint count, float x) {
    uint last = count - 2u;
    // partition_point(c <= x): the first entry above x.
    uint lo = 0u;
    uint hi = count;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        float c = rows ? env_rows_cdf[mid] : env_row_cdfs[first + mid];
        if (c <= x) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    uint index = min(lo > 0u ? lo - 1u : 0u, last);
    float start = rows ? env_rows_cdf[index] : env_row_cdfs[first + index];
    float end = rows ? env_rows_cdf[index + 1u] : env_row_cdfs[first + index + 1u];
    while (index > 0u && end <= start) {
        index -= 1u;
        end = start;
        start = rows ? env_rows_cdf[index] : env_row_cdfs[first + index];
    }
    float width = end - start;
    float within = width > 0.0 ? clamp((x - start) / width, 0.0, 1.0 - 5.9604645e-8) : 0.5;
    return vec2(float(index), within);
}

// The direction point u ([0, 1)^2) draws, its density per solid angle (0: none) and its
// texel; false when the row drawn does not emit.
bool env_sample(vec2 u, out vec3 direction, out float pdf, out uvec2 texel) {
    uint width = environment.width;
    vec2 row_pick = env_invert(true, 0u, environment.height + 1u, u.y * environment.total);
    uint row = uint(row_pick.x);
    uint stride = width + 1u;
    float row_weight = env_row_cdfs[row * stride + width];
    if (row_weight <= 0.0) {
        return false;
    }
    vec2 column_pick = env_invert(false, row * stride, stride, u.x * row_weight);
    uint column = uint(column_pick.x);
    vec2 uv = vec2(
        (float(column) + column_pick.y) / float(width),
        (float(row) + row_pick.y) / float(environment.height));
    direction = env_world_from_uv(uv);
    texel = uvec2(column, row);
    pdf = env_texel_pdf(texel, uv.y);
    return pdf > 0.0;
}

#endif
