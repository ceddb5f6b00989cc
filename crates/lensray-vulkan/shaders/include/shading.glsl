// Shading of the thin-lens compute pass, as specified for every renderer (lensray-core/src/settings/render.rs,
// the CPU reference, lensray-core/src/reference/): unlit (the diffuse colour of the closest hit)
// or lit: at each surface of a path, emission + the scene's lights, each through a shadow ray,
// + the emissive triangles drawn by power and from the BRDF (emitters.glsl) + the sky (a uniform one or the scene's map) drawn from the sky and from the BRDF, weighed by
// multiple importance sampling (sky.glsl), each reflected by the metallic-roughness BRDF of
// layers.glsl; colours textured and filtered over the pinhole's pixel footprint at the camera's
// surface, unfiltered after a bounce. Include after a hit implementation (hit_rayquery.glsl,
// hit_software.glsl or hit_rtpipeline.glsl), which defines
//   bool closest_hit(vec3 origin, vec3 direction, float t_max, BlendCut cut, out Hit hit);
//   bool occluded(vec3 origin, vec3 direction, float t_max, BlendCut cut);
// over t in (0, t_max), and the trace parameters `params`. trace.comp's shade_sample walks the
// path (reference/integrator.rs).
#ifndef LENSRAY_SHADING_GLSL
#define LENSRAY_SHADING_GLSL

#extension GL_EXT_control_flow_attributes : require

#include "lights.glsl"
#include "layers.glsl"
#include "environment.glsl"
#include "sky.glsl"
#include "emitters.glsl"
#include "surface_frame.glsl"

// reference/lighting.rs: LightDraw (the cut is the camera ray's; shadow_cut derives the
// shadow and bounce rays' from it). `centred` (the hybrid's pre-pass) draws every point at
// (0.5, 0.5).
struct LightDraw {
    BlendCut cut;
    PixelSampler state;
    uint sample_index;
    bool centred;
};

// reference/integrator.rs: vertex_points (xy: the sky's point, zw: the BRDF's).
vec4 vertex_points(LightDraw draw, uint vertex) {
    if (draw.centred) {
        return vec4(0.5);
    }
    uvec4 d = vertex_dimensions(vertex);
    return vec4(pixel_dimension(draw.state, draw.sample_index, d.x),
                pixel_dimension(draw.state, draw.sample_index, d.y),
                pixel_dimension(draw.state, draw.sample_index, d.z),
                pixel_dimension(draw.state, draw.sample_index, d.w));
}

// reference/integrator.rs: vertex_points, the BRDF point's third coordinate (whether glass
// reflects; `centred`: 0.5).
float fresnel_point(LightDraw draw, uint vertex) {
    if (draw.centred) {
        return 0.5;
    }
    return pixel_dimension(draw.state, draw.sample_index, fresnel_dimension(vertex));
}

// reference/integrator.rs: vertex_points, the sky point's third coordinate (which of a map's
// candidates; `centred`: 0.5).
float sky_pick_point(LightDraw draw, uint vertex) {
    if (draw.centred) {
        return 0.5;
    }
    return pixel_dimension(draw.state, draw.sample_index, sky_pick_dimension(vertex));
}

// reference/integrator.rs: emitter_points (`centred`: (0.5, 0.5)).
vec2 emitter_point(LightDraw draw, uint vertex) {
    if (draw.centred) {
        return vec2(0.5);
    }
    uvec2 d = emitter_dimensions(vertex);
    return vec2(pixel_dimension(draw.state, draw.sample_index, d.x),
                pixel_dimension(draw.state, draw.sample_index, d.y));
}

// reference/lighting.rs: LitLane (o: the shadow rays' origin, `offset` off the surface along
// ng; v: towards the viewer; attenuation: the extinction of the volume a ray that met the
// surface crossed, integrator.rs: volume_transmittance).
struct LitSurface {
    vec3 o;
    float offset;
    vec3 ns;
    vec3 ng;
    vec3 v;
    LayeredBrdf brdf;
    float occlusion;
    vec3 attenuation;
};

// lighting.rs: leaves
bool leaves(LitSurface s, vec3 d) {
    float g = dot(d, s.ng);
    float n = dot(d, s.ns);
    return (g > 0.0 && (n > 0.0 || coat_reflects(s.brdf, s.ns, d)))
        || (g < 0.0 && n < 0.0 && brdf_transmits(s.brdf));
}

// reference/surface.rs: origin_towards
vec3 origin_towards(LitSurface s, vec3 d) {
    return dot(d, s.ng) < 0.0 ? s.o - s.ng * (2.0 * s.offset) : s.o;
}

// sky.rs: sky_along
vec3 sky_along(LitSurface s, BrdfSample draw) {
    float w = power_heuristic(draw.pdf, sky_pdf(s.ns, draw.direction));
    return draw.weight * sky_radiance(draw.direction) * (w * s.occlusion);
}

// sky.rs: sky_draw. The sky's draw at point `u` (its third coordinate picks among a map's
// candidates, where the surface is a metal): false where none is drawn, else the direction and
// the light it brings.
bool sky_draw(LitSurface s, vec3 u, out vec3 direction, out vec3 reflected) {
    uint candidates =
        sky_is_map() && s.brdf.base.metallic >= SKY_RESAMPLED_METALLIC ? SKY_CANDIDATES : 1u;
    float pick = u.z;
    float total = 0.0;
    bool picked = false;
    float picked_pdf = 0.0;
    float picked_target = 0.0;
    direction = vec3(0.0);
    reflected = vec3(0.0);
    for (uint k = 0u; k < candidates; ++k) {
        vec3 d;
        float pdf;
        vec3 arriving;
        if (!sky_sample(s.ns, candidate_point(u.xy, k), d, pdf, arriving) || !leaves(s, d)) {
            continue;
        }
        vec3 light = brdf_reflected(s.brdf, s.ns, d, s.v) * arriving;
        if (candidates == 1u) {
            picked = true;
            direction = d;
            picked_pdf = pdf;
            reflected = light;
            break;
        }
        float target = luminance(light);
        if (!(target > 0.0)) {
            continue;
        }
        total += target / pdf;
        float keep = target / pdf / total;
        if (pick < keep) {
            pick /= keep;
            picked = true;
            direction = d;
            picked_pdf = pdf;
            picked_target = target;
            reflected = light;
        } else {
            pick = (pick - keep) / (1.0 - keep);
        }
    }
    if (!picked) {
        return false;
    }
    float w = power_heuristic(picked_pdf, brdf_pdf(s.brdf, s.ns, direction, s.v));
    float scale = candidates == 1u ? w / picked_pdf
                                   : w * (total / (float(candidates) * picked_target));
    reflected *= scale * s.occlusion;
    return true;
}

// reference/emitters.rs: Renderer::emitter_light's lane: the shadow ray to the point `u` draws
// on the emitters and the light it brings, weighed against the BRDF's draw where `mis`.
bool emitter_draw(LitSurface s, vec2 u, bool mis, out vec3 direction, out float t_max,
                  out vec3 reflected) {
    vec2 on_triangle;
    uint tri = emitter_pick(u, on_triangle);
    vec2 b;
    vec3 position = uniform_point(tri, on_triangle, b);
    vec3 origin = brdf_transmits(s.brdf) ? origin_towards(s, position - s.o) : s.o;
    vec3 to_light = position - origin;
    float distance = length(to_light);
    direction = to_light / distance;
    t_max = distance * (1.0 - EMITTER_SHADOW_SHORTEN);
    reflected = vec3(0.0);
    if (!(distance > 0.0) || !leaves(s, direction)) {
        return false;
    }
    vec3 emission = emission_towards(tri, b, direction);
    float pdf = emitter_pdf(tri, direction, distance);
    if (emission == vec3(0.0) || !(pdf > 0.0) || isinf(pdf)) {
        return false;
    }
    float w = mis ? power_heuristic(pdf, brdf_pdf(s.brdf, s.ns, direction, s.v)) : 1.0;
    reflected = brdf_reflected(s.brdf, s.ns, direction, s.v) * emission * (w / pdf);
    return true;
}

// reference/lighting.rs: direct_light, emitters.rs: Renderer::emitter_light (where
// emitters_light(), at `emitter_u`, weighed against the BRDF where `emitter_mis`), then sky.rs:
// Renderer::sky_light and, where `along` (a path's last surface), Renderer::sky_along_draws
// with the BRDF's `draw`: steps i < lights.length() are the lights, the next the emitters', the
// next the sky's own draw at `sky_point`, the last the sky along `draw`.
// One shadow-ray call site, so the traversal is inlined once. `shadowed` gets bit i set where
// light i (i < 24) is blocked: the hybrid's plan compares it between neighbours.
vec3 direct_light(LitSurface s, vec2 emitter_u, bool emitter_mis, vec3 sky_point, bool along,
                  BrdfSample draw, BlendCut cut, inout uint rays, out uint shadowed) {
    shadowed = 0u;
    vec3 radiance = vec3(0.0);
    uint count = lights.length();
    bool sky = sky_lights();
    bool emitters = emitters_light();
    for (uint i = 0u; i < count + 3u; ++i) {
        vec3 direction;
        float t_max = T_MAX;
        vec3 reflected;
        if (i < count) {
            Incident incident;
            Light light = light_at(i);
            if (!light_incident(light, s.o, incident)) {
                continue;
            }
            // A light above the base's normal or the coat's is seen from the front.
            if (dot(s.ns, incident.direction) <= 0.0
                && !coat_reflects(s.brdf, s.ns, incident.direction)) {
                // Light from behind reaches the viewer only through the surface.
                if (!brdf_transmits(s.brdf)
                    || !light_incident(light, origin_towards(s, incident.direction), incident)
                    || !leaves(s, incident.direction)) {
                    continue;
                }
            }
            direction = incident.direction;
            t_max = incident.distance;
            reflected = brdf_reflected(s.brdf, s.ns, direction, s.v) * incident.irradiance;
        } else if (i == count) {
            if (!emitters || !emitter_draw(s, emitter_u, emitter_mis, direction, t_max, reflected)) {
                continue;
            }
        } else if (i == count + 1u) {
            if (!sky) {
                break;
            }
            if (!sky_draw(s, sky_point, direction, reflected)) {
                continue;
            }
        } else {
            if (!along) {
                break;
            }
            direction = draw.direction;
            reflected = sky_along(s, draw);
        }
        rays += 1u;
        // A light above the shading normal (or the coat's) is seen from the front whatever the
        // geometric normal says (lighting.rs: direct_light); every other draw left the side it
        // goes to.
        bool front = i < count
            && (dot(s.ns, direction) > 0.0 || coat_reflects(s.brdf, s.ns, direction));
        if (!occluded(front ? s.o : origin_towards(s, direction), direction, t_max, cut)) {
            radiance += reflected;
        } else if (i < min(count, 24u)) {
            shadowed |= 1u << i;
        }
    }
    return radiance;
}

// reference/transmission.rs: dielectric_of
Dielectric material_dielectric(Material m, float transmission, bool back_face) {
    float eta = m.ior;
    if (transmission > 0.0) {
        eta = m.thin != 0u ? 1.0 : back_face ? 1.0 / m.ior : m.ior;
    }
    return Dielectric(m.ior, transmission, eta);
}

// Every texture of `m` in its slot (TEXEL_*), filtered at `texcoords` over the footprint `dx`,
// `dy`; vec4(1.0) where `m` has none. One loop the compiler keeps: lavapipe inlines every call,
// and a filtering per texture made the textured trace variants take minutes to compile
// (docs/testing.md, "Where CI's time goes"). A slot whose texel the material's factors then
// ignore (an emission texture of a black emission) is filtered all the same: the values are
// those of material.rs.
void material_texels(Material m, vec4 texcoords, vec4 dx, vec4 dy,
                     out vec4 t[MATERIAL_TEXEL_SLOTS]) {
    [[dont_unroll]] for (uint k = 0u; k < MATERIAL_TEXEL_SLOTS; ++k) {
        TextureRef r = material_texture(m, k);
        t[k] = has_texture(r) ? texture_sample(r, texcoords, dx, dy) : vec4(1.0);
    }
}

// reference/integrator.rs: shade_surface and colours. The surface `hit` (the closest hit of
// `ray`) as its light needs it; false where the shading is unlit, `emission` then holding the
// colour. Textures are filtered over the pinhole's footprint where `filtered` (the camera's
// surface), read at their finest level otherwise.
bool surface_at(Ray ray, Hit hit, bool filtered, out LitSurface s, out vec3 emission) {
    uint tri = hit.triangle;
    Material mat = materials[triangle_material(tri)];
    bool textured = SURFACES_TEXTURED && material_is_textured(mat);
    bool coloured = SURFACES_TEXTURED && triangle_has_colours(tri);
    if (params.shading == SHADING_UNLIT && !textured && !coloured) {
        emission = mat.diffuse.xyz;
        return false;
    }

    vec2 b = hit.barycentrics;  // weights of v1, v2
    vec3 p = ray_at(ray, hit.t);
    vec3 ng = triangle_geometric_normal(tri);
    vec3 ns = ng;
    if (triangle_has_normals(tri)) {
        vec3 n0 = vertex_normal(indices[3u * tri]).xyz;
        vec3 n1 = vertex_normal(indices[3u * tri + 1u]).xyz;
        vec3 n2 = vertex_normal(indices[3u * tri + 2u]).xyz;
        ns = normalize((1.0 - b.x - b.y) * n0 + b.x * n1 + b.y * n2);
    }
    bool back_face = dot(ng, ray.direction) > 0.0;
    if (back_face) {
        ng = -ng;
    }
    if (dot(ns, ray.direction) > 0.0) {
        ns = -ns;
    }
    vec3 diffuse = mat.diffuse.xyz;
    emission = mat.emission.xyz;
    vec2 metallic_roughness = vec2(mat.metallic, mat.roughness);
    vec2 clearcoat = vec2(mat.clearcoat, mat.clearcoat_roughness);
    float transmission = mat.transmission;
    vec4 sheen = mat.sheen_colour;
    float occlusion = 1.0;
    vec3 coat_normal = ns;
    if (textured) {
        vec4 texcoords = triangle_texcoords(tri, b);
        vec4 dx = vec4(0.0);
        vec4 dy = vec4(0.0);
        if (filtered) {
            Footprint f = params.footprint;
            vec3 dpdx = footprint_dp_along(f, p, ng, f.pixel_dx.xyz);
            vec3 dpdy = footprint_dp_along(f, p, ng, f.pixel_dy.xyz);
            triangle_texcoord_footprint(tri, dpdx, dpdy, dx, dy);
        }
        vec4 t[MATERIAL_TEXEL_SLOTS];
        material_texels(mat, texcoords, dx, dy, t);
        diffuse = material_diffuse_with(mat, t[TEXEL_DIFFUSE]);
        metallic_roughness = material_metallic_roughness_with(mat, t[TEXEL_METALLIC_ROUGHNESS]);
        clearcoat = material_clearcoat_with(mat, t[TEXEL_CLEARCOAT], t[TEXEL_CLEARCOAT_ROUGHNESS]);
        transmission = material_transmission_with(mat, t[TEXEL_TRANSMISSION]);
        sheen = material_sheen_with(mat, t[TEXEL_SHEEN_COLOUR], t[TEXEL_SHEEN_ROUGHNESS]);
        emission = material_emission_with(mat, t[TEXEL_EMISSION]);
        occlusion = material_occlusion_with(mat, t[TEXEL_OCCLUSION]);
        // The coat's normal is the vertex normal tilted by the coat's own map, not the base's;
        // both in one loop the compiler keeps, as the texels (material_texels).
        vec3 vertex_ns = ns;
        [[dont_unroll]] for (uint k = 0u; k < 2u; ++k) {
            bool coat = k == 0u;
            vec3 n = normal_mapped(coat ? mat.clearcoat_normal_texture : mat.normal_texture,
                                   coat ? mat.clearcoat_normal_scale : mat.normal_scale, tri, b,
                                   vertex_ns, t[coat ? TEXEL_CLEARCOAT_NORMAL : TEXEL_NORMAL]);
            if (coat) {
                coat_normal = n;
            } else {
                ns = n;
            }
        }
    }
    if (coloured) {
        diffuse = vertex_coloured(diffuse, tri, b);
    }
    if (params.shading == SHADING_UNLIT) {
        emission = diffuse;
        return false;
    }

    // reference/surface.rs: shadow_origin
    s.offset = SHADOW_ORIGIN_OFFSET * (1.0 + max(max(abs(p.x), abs(p.y)), abs(p.z)));
    s.o = p + ng * s.offset;
    s.v = -normalize(ray.direction);
    s.ns = reflection_safe_normal(ng, s.v, ns);
    s.ng = ng;
    if (clearcoat.x > 0.0) {
        coat_normal = reflection_safe_normal(ng, s.v, coat_normal);
    }
    s.brdf = LayeredBrdf(
        MetallicRoughness(diffuse, metallic_roughness.x, metallic_roughness.y, mat.specular,
                          material_dielectric(mat, transmission, back_face)),
        Clearcoat(clearcoat.x, clearcoat.y, coat_normal), Sheen(sheen.xyz, sheen.w));
    s.occlusion = occlusion;
    s.attenuation = back_face && mat.thin == 0u ? mat.attenuation.xyz : vec3(0.0);
    return true;
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
