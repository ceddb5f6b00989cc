// The hit interface (see shading.glsl) answered by ray queries against the scene's TLAS
// (lensray-vulkan/src/scene/accel.rs: one BLAS per mesh, instance custom index = the mesh's first triangle).
// The including shader enables GL_EXT_ray_query and declares the trace set's bindings.
#ifndef LENSRAY_HIT_RAYQUERY_GLSL
#define LENSRAY_HIT_RAYQUERY_GLSL

// Confirms the query's candidate triangle where its alpha test lets it stop the ray: only
// alpha-tested meshes (geometry not marked opaque, scene/accel.rs) give candidates.
void test_candidate(rayQueryEXT rq, BlendCut cut) {
    if (rayQueryGetIntersectionTypeEXT(rq, false) == gl_RayQueryCandidateIntersectionTriangleEXT) {
        uint tri = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(rq, false))
                 + uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, false));
        if (triangle_stops_ray(tri, rayQueryGetIntersectionBarycentricsEXT(rq, false), cut)) {
            rayQueryConfirmIntersectionEXT(rq);
        }
    }
}

// Without alpha-tested surfaces every hit is opaque: the traversal need not offer candidates.
// With single-sided surfaces the rays cull back faces: only single-sided meshes' instances
// let them (the others are marked TRIANGLE_FACING_CULL_DISABLE, scene/accel.rs), so a ray that
// meets a single-sided triangle from behind passes through it, as on the CPU reference.
uint surfaces_ray_flags() {
    uint cull = SURFACES_SINGLE_SIDED ? gl_RayFlagsCullBackFacingTrianglesEXT : gl_RayFlagsNoneEXT;
    return cull | (SURFACES_ALPHA_TESTED ? gl_RayFlagsNoneEXT : gl_RayFlagsOpaqueEXT);
}

// The closest hit with t in (0, t_max) that stops a ray cutting BLEND surfaces with `cut`: the
// global triangle index, t and the weights of v1, v2.
bool closest_hit(vec3 origin, vec3 direction, float t_max, BlendCut cut, out Hit hit) {
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, tlas, surfaces_ray_flags(), 0xFFu, origin, 0.0, direction, t_max);
    while (rayQueryProceedEXT(rq)) {
        if (SURFACES_ALPHA_TESTED) {
            test_candidate(rq, cut);
        }
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

// Whether a surface that stops the ray lies along it with t in (0, t_max); the first ends the
// query.
bool occluded(vec3 origin, vec3 direction, float t_max, BlendCut cut) {
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, tlas, surfaces_ray_flags() | gl_RayFlagsTerminateOnFirstHitEXT,
                          0xFFu, origin, 0.0, direction, t_max);
    while (rayQueryProceedEXT(rq)) {
        if (SURFACES_ALPHA_TESTED) {
            test_candidate(rq, cut);
        }
    }
    return rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}

#endif
