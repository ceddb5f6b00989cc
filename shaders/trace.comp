#version 460
// Thin-lens compute pass: spp camera samples per pixel, each traced with a ray query against the
// TLAS and shaded as specified for every renderer (src/render/settings.rs, the CPU reference).
// One dispatch covers some rows (strided) and a range of samples; sums accumulate in `accum`, which holds a
// band of rows of the image (bounded by the device's storage-buffer range).
#extension GL_EXT_ray_query : require

#include "camera.glsl"
#include "sampler.glsl"
#define SCENE_SET 0
#include "scene.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 5) uniform accelerationStructureEXT tlas;
layout(std430, set = 0, binding = 6) buffer Accum { vec4 accum[]; };
layout(std430, set = 0, binding = 7) buffer Counters { uint rays_traced; };
layout(std140, set = 0, binding = 8) uniform Params {
    Camera cam;
    vec4 background;
    vec4 light_position;
    vec4 light_intensity;
    uint width;
    uint height;
    uint seed;
    uint shading;
    uint sampler_kind;  // SAMPLER_SOBOL or SAMPLER_INDEPENDENT
    uint pad0;
    uint pad1;
    uint pad2;
} params;

// This dispatch covers the blocks of 8 rows block_first + i * block_stride (i < block_count)
// of the band of band_height rows starting at image row band_origin.
layout(push_constant) uniform Push {
    uint band_origin;  // accum holds the rows band_origin.. of the image
    uint band_height;
    uint block_first;
    uint block_stride;
    uint block_count;
    uint sample_begin;
    uint sample_end;
} pc;

const uint SHADING_UNLIT = 0u;
const uint SHADING_LIT = 1u;
const float PI = 3.14159265358979323846;
const float T_MAX = 1e30;

// The radiance along `ray`; `rays` counts the ray queries traced.
vec3 shade(Ray ray, inout uint rays) {
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, tlas, gl_RayFlagsOpaqueEXT, 0xFFu, ray.origin, 0.0, ray.direction, T_MAX);
    while (rayQueryProceedEXT(rq)) {
    }
    rays += 1u;
    if (rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionNoneEXT) {
        return params.background.xyz;
    }
    uint tri = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(rq, true))
             + uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
    Material mat = materials[triangle_material(tri)];
    if (params.shading == SHADING_UNLIT) {
        return mat.diffuse.xyz;
    }

    float t = rayQueryGetIntersectionTEXT(rq, true);
    vec2 b = rayQueryGetIntersectionBarycentricsEXT(rq, true);  // weights of v1, v2
    vec3 p = ray_at(ray, t);
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

    vec3 radiance = mat.emission.xyz;
    vec3 o = p + ng * 1e-4 * (1.0 + max(max(abs(p.x), abs(p.y)), abs(p.z)));
    vec3 to_light = params.light_position.xyz - o;
    float dist = length(to_light);
    vec3 l = to_light / dist;
    float c = dot(ns, l);
    if (c > 0.0) {
        rayQueryEXT shadow;
        rayQueryInitializeEXT(shadow, tlas, gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT,
                              0xFFu, o, 0.0, l, dist);
        while (rayQueryProceedEXT(shadow)) {
        }
        rays += 1u;
        if (rayQueryGetIntersectionTypeEXT(shadow, true) == gl_RayQueryCommittedIntersectionNoneEXT) {
            radiance += mat.diffuse.xyz * (1.0 / PI) * params.light_intensity.xyz * c / (dist * dist);
        }
    }
    return radiance;
}

void main() {
    uint x = gl_GlobalInvocationID.x;
    uint block = gl_WorkGroupID.y;
    uint band_row = (pc.block_first + block * pc.block_stride) * gl_WorkGroupSize.y
                  + gl_LocalInvocationID.y;
    uint y = pc.band_origin + band_row;
    if (x >= params.width || block >= pc.block_count || band_row >= pc.band_height) {
        return;
    }
    uint slot = band_row * params.width + x;
    vec3 sum = accum[slot].xyz;
    uint rays = 0u;
    for (uint s = pc.sample_begin; s < pc.sample_end; ++s) {
        CameraSample cs = camera_sample(params.sampler_kind, params.seed, uvec2(x, y), params.width, s);
        Ray ray = generate_ray(params.cam, cs.film, cs.lens);
        sum += shade(ray, rays);
    }
    accum[slot] = vec4(sum, 0.0);
    atomicAdd(rays_traced, rays);
}
