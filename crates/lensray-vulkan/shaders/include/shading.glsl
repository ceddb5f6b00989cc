// Shading of the thin-lens compute pass, as specified for every renderer (lensray-core/src/settings/render.rs,
// the CPU reference, lensray-core/src/reference/render.rs): unlit (the diffuse colour of the
// closest hit) or lit (emission + the scene's lights, each through a shadow ray, + the
// environment through a cosine-distributed ray, each reflected by the metallic-roughness BRDF of
// brdf.glsl), colours textured and filtered over the
// pinhole's pixel footprint. Include after a hit implementation
// (hit_rayquery.glsl or hit_software.glsl), which defines
//   bool closest_hit(vec3 origin, vec3 direction, float t_max, BlendCut cut, out Hit hit);
//   bool occluded(vec3 origin, vec3 direction, float t_max, BlendCut cut);
// over t in (0, t_max), and the trace parameters `params`. shade_hit_shadowed shades a hit found
// either way (the raster path's rasterized one included).
#ifndef LENSRAY_SHADING_GLSL
#define LENSRAY_SHADING_GLSL

#include "brdf.glsl"
#include "lights.glsl"
#include "surface_frame.glsl"

// reference/lighting.rs: LightDraw (the cut is the camera ray's; shadow_cut derives the
// shadow rays' from it).
struct LightDraw {
    BlendCut cut;
    vec2 environment;
};

// reference/lighting.rs: direct_light. `shadowed` gets bit i set where light i (i < 24) is
// blocked: the hybrid's plan compares it between neighbours. Step i < lights.length() is light
// i, the last step the environment: one shadow-ray call site, so the traversal is inlined once.
vec3 direct_light(vec3 o, vec3 ns, vec3 ng, vec3 v, MetallicRoughness brdf, float occlusion,
                  LightDraw draw, inout uint rays, out uint shadowed) {
    shadowed = 0u;
    vec3 radiance = vec3(0.0);
    BlendCut cut = shadow_cut(draw.cut);
    uint count = lights.length();
    bool sky = params.environment.xyz != vec3(0.0);
    for (uint i = 0u; i <= count; ++i) {
        vec3 direction;
        float t_max;
        vec3 reflected;
        if (i < count) {
            Incident incident;
            if (!light_incident(lights[i], o, incident)) {
                continue;
            }
            float c = dot(ns, incident.direction);
            if (c <= 0.0) {
                continue;
            }
            direction = incident.direction;
            t_max = incident.distance;
            reflected = brdf_evaluate(brdf, ns, direction, v) * c * incident.irradiance;
        } else {
            if (!sky) {
                break;
            }
            // Density cos / pi: the estimate of the reflected f L cos is f L pi where the ray
            // leaves; a direction under the surface's own plane is blocked by the surface.
            direction = cosine_direction(ns, draw.environment);
            if (dot(direction, ng) <= 0.0 || dot(ns, direction) <= 0.0) {
                break;
            }
            t_max = T_MAX;
            reflected = brdf_evaluate(brdf, ns, direction, v) * (PI * occlusion)
                * params.environment.xyz;
        }
        rays += 1u;
        if (!occluded(o, direction, t_max, cut)) {
            radiance += reflected;
        } else if (i < min(count, 24u)) {
            shadowed |= 1u << i;
        }
    }
    return radiance;
}

// The radiance leaving `hit` (the closest hit of `ray`) towards the ray's origin; `rays` counts
// the shadow and environment rays, `shadowed` says which lights were blocked (the hybrid's plan
// looks for shadow boundaries).
vec3 shade_hit_shadowed(Ray ray, Hit hit, LightDraw draw, inout uint rays, out uint shadowed) {
    shadowed = 0u;
    uint tri = hit.triangle;
    Material mat = materials[triangle_material(tri)];
    bool textured = SURFACES_TEXTURED && material_is_textured(mat);
    bool coloured = SURFACES_TEXTURED && triangle_has_colours(tri);
    if (params.shading == SHADING_UNLIT && !textured && !coloured) {
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
    vec2 metallic_roughness = vec2(mat.metallic, mat.roughness);
    float occlusion = 1.0;
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
        metallic_roughness = material_metallic_roughness(mat, texcoord, dx, dy);
        emission = material_emission(mat, texcoord, dx, dy);
        occlusion = material_occlusion(mat, texcoord, dx, dy);
        ns = normal_mapped(mat, tri, b, ns, texcoord, dx, dy);
    }
    if (coloured) {
        diffuse = vertex_coloured(diffuse, tri, b);
    }
    if (params.shading == SHADING_UNLIT) {
        return diffuse;
    }

    // reference/surface.rs: shadow_origin
    vec3 o = p + ng * SHADOW_ORIGIN_OFFSET * (1.0 + max(max(abs(p.x), abs(p.y)), abs(p.z)));
    MetallicRoughness brdf =
        MetallicRoughness(diffuse, metallic_roughness.x, metallic_roughness.y, mat.specular);
    vec3 v = -normalize(ray.direction);
    return emission + direct_light(o, ns, ng, v, brdf, occlusion, draw, rays, shadowed);
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
