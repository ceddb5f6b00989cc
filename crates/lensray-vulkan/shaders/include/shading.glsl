// Shading of the thin-lens compute pass, as specified for every renderer (lensray-core/src/settings/render.rs,
// the CPU reference, lensray-core/src/reference/render.rs): unlit (the diffuse colour of the
// closest hit) or lit (emission + one point light with a shadow ray), colours textured and
// filtered over the pinhole's pixel footprint. Include after a hit implementation
// (hit_rayquery.glsl or hit_software.glsl), which defines
//   bool closest_hit(vec3 origin, vec3 direction, float t_max, BlendCut cut, out Hit hit);
//   bool occluded(vec3 origin, vec3 direction, float t_max, BlendCut cut);
// over t in (0, t_max), and the trace parameters `params`. shade_hit shades a hit found either way
// (the raster path's rasterized one included).
#ifndef LENSRAY_SHADING_GLSL
#define LENSRAY_SHADING_GLSL

// The radiance leaving `hit` (the closest hit of `ray`) towards the ray's origin; `rays` counts
// the shadow ray, `shadowed` says whether it was blocked (the hybrid's plan looks for shadow
// boundaries).
vec3 shade_hit_shadowed(Ray ray, Hit hit, BlendCut cut, inout uint rays, out bool shadowed) {
    shadowed = false;
    uint tri = hit.triangle;
    Material mat = materials[triangle_material(tri)];
    bool textured = has_texture(mat.diffuse_texture) || has_texture(mat.emission_texture);
    if (params.shading == SHADING_UNLIT && !textured) {
        return mat.diffuse.xyz;
    }

    vec2 b = hit.barycentrics;  // weights of v1, v2
    vec3 p = ray_at(ray, hit.t);
    vec3 ng = triangle_geometric_normal(tri);
    vec3 ns = ng;
    if (triangle_has_normals(tri)) {
        vec3 n0 = normals[indices[3u * tri]].xyz;
        vec3 n1 = normals[indices[3u * tri + 1u]].xyz;
        vec3 n2 = normals[indices[3u * tri + 2u]].xyz;
        ns = normalize((1.0 - b.x - b.y) * n0 + b.x * n1 + b.y * n2);
    }
    if (dot(ng, ray.direction) > 0.0) {
        ng = -ng;
    }
    if (dot(ns, ray.direction) > 0.0) {
        ns = -ns;
    }
    vec3 diffuse = mat.diffuse.xyz;
    vec3 emission = mat.emission.xyz;
    if (textured) {
        // reference/render.rs: colours
        vec2 texcoord = triangle_texcoord(tri, b);
        Footprint f = params.footprint;
        vec3 dpdx = footprint_dp_along(f, p, ng, f.pixel_dx.xyz);
        vec3 dpdy = footprint_dp_along(f, p, ng, f.pixel_dy.xyz);
        vec2 dx;
        vec2 dy;
        triangle_texcoord_footprint(tri, dpdx, dpdy, dx, dy);
        diffuse = material_diffuse(mat, texcoord, dx, dy);
        emission = material_emission(mat, texcoord, dx, dy);
    }
    if (params.shading == SHADING_UNLIT) {
        return diffuse;
    }

    vec3 radiance = emission;
    // reference/surface.rs: shadow_origin
    vec3 o = p + ng * SHADOW_ORIGIN_OFFSET * (1.0 + max(max(abs(p.x), abs(p.y)), abs(p.z)));
    vec3 to_light = params.light_position.xyz - o;
    float dist = length(to_light);
    vec3 l = to_light / dist;
    float c = dot(ns, l);
    if (c > 0.0) {
        bool blocked = occluded(o, l, dist, shadow_cut(cut));
        rays += 1u;
        shadowed = blocked;
        if (!blocked) {
            radiance += diffuse * (1.0 / PI) * params.light_intensity.xyz * c / (dist * dist);
        }
    }
    return radiance;
}

vec3 shade_hit(Ray ray, Hit hit, BlendCut cut, inout uint rays) {
    bool shadowed;
    return shade_hit_shadowed(ray, hit, cut, rays, shadowed);
}

// The radiance along `ray`, which cuts BLEND surfaces with `cut`; `rays` counts the rays traced.
vec3 shade(Ray ray, BlendCut cut, inout uint rays) {
    Hit hit;
    bool found = closest_hit(ray.origin, ray.direction, T_MAX, cut, hit);
    rays += 1u;
    if (!found) {
        return params.background.xyz;
    }
    return shade_hit(ray, hit, cut, rays);
}

// The hit of `ray` with the plane of triangle `tri` (the raster path: the rasterizer found the
// triangle; only the distance and barycentric weights of v1, v2 are needed for shading).
Hit triangle_plane_hit(Ray ray, uint tri) {
    vec3 v0 = positions[indices[3u * tri]].xyz;
    vec3 e1 = positions[indices[3u * tri + 1u]].xyz - v0;
    vec3 e2 = positions[indices[3u * tri + 2u]].xyz - v0;
    // Moller-Trumbore without the inside tests.
    vec3 p = cross(ray.direction, e2);
    float inv_det = 1.0 / dot(e1, p);
    vec3 s = ray.origin - v0;
    vec3 q = cross(s, e1);
    Hit hit;
    hit.triangle = tri;
    hit.barycentrics = vec2(dot(s, p), dot(ray.direction, q)) * inv_det;
    hit.t = dot(e2, q) * inv_det;
    return hit;
}

#endif
