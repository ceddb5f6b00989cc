#version 460
// Thin-lens compute pass: spp camera samples per pixel, each traced with a ray query against the
// TLAS and shaded as specified for every renderer (src/render/settings.rs, the CPU reference).
// One dispatch covers some rows (strided) and a range of samples; sums accumulate in `accum`
// (xyz: the sum, w: how many samples), which holds a band of rows of the image (bounded by the
// device's storage-buffer range).
#extension GL_EXT_ray_query : require

#include "camera.glsl"
#include "sampler.glsl"
#define SCENE_SET 0
#include "scene.glsl"

layout(local_size_x = TRACE_GROUP_SIZE, local_size_y = TRACE_GROUP_SIZE) in;

layout(set = 0, binding = TRACE_BINDING_TLAS) uniform accelerationStructureEXT tlas;
layout(std430, set = 0, binding = TRACE_BINDING_ACCUM) buffer Accum { vec4 accum[]; };
layout(std430, set = 0, binding = TRACE_BINDING_COUNTERS) buffer Counters { uint rays_traced; };
layout(std140, set = 0, binding = TRACE_BINDING_PARAMS) uniform ParamsBlock { TraceParams params; };
layout(push_constant) uniform PushBlock { TracePush pc; };

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
    // reference/surface.rs: shadow_origin
    vec3 o = p + ng * SHADOW_ORIGIN_OFFSET * (1.0 + max(max(abs(p.x), abs(p.y)), abs(p.z)));
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
    vec4 before = accum[slot];
    vec3 sum = before.xyz;
    uint rays = 0u;
    for (uint s = pc.sample_begin; s < pc.sample_end; ++s) {
        CameraSample cs = camera_sample(params.sampler_kind, params.seed, uvec2(x, y), params.width, s);
        Ray ray = generate_ray(params.camera, cs.film, cs.lens);
        sum += shade(ray, rays);
    }
    // w counts the samples added (exact in float up to 2^24): the preview divides by it.
    accum[slot] = vec4(sum, before.w + float(pc.sample_end - pc.sample_begin));
    atomicAdd(rays_traced, rays);
}
