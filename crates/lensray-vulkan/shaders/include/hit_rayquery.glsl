// The hit interface (see shading.glsl) answered by ray queries against the scene's TLAS
// (lensray-vulkan/src/scene/accel.rs: one BLAS per mesh, instance custom index = the mesh's first triangle).
// The including shader enables GL_EXT_ray_query and declares the trace set's bindings.
#ifndef LENSRAY_HIT_RAYQUERY_GLSL
#define LENSRAY_HIT_RAYQUERY_GLSL

layout(set = 0, binding = TRACE_BINDING_TLAS) uniform accelerationStructureEXT tlas;

// The closest hit with t in (0, t_max): the global triangle index, t and the weights of v1, v2.
bool closest_hit(vec3 origin, vec3 direction, float t_max, out Hit hit) {
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, tlas, gl_RayFlagsOpaqueEXT, 0xFFu, origin, 0.0, direction, t_max);
    while (rayQueryProceedEXT(rq)) {
    }
    if (rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionNoneEXT) {
        return false;
    }
    hit.triangle = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(rq, true))
                 + uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
    hit.t = rayQueryGetIntersectionTEXT(rq, true);
    hit.barycentrics = rayQueryGetIntersectionBarycentricsEXT(rq, true);
    return true;
}

// Whether anything lies along the ray with t in (0, t_max); the first hit ends the query.
bool occluded(vec3 origin, vec3 direction, float t_max) {
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, tlas, gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT,
                          0xFFu, origin, 0.0, direction, t_max);
    while (rayQueryProceedEXT(rq)) {
    }
    return rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}

#endif
