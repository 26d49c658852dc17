// The surface material's transmission and subsurface (OpenPBR Surface 1.1), as parts: materials of
// their own in the material buffer (renderer/gpu_materials.cpp writes them), chosen at each hit.
//
// OpenPBR's dielectric base is a mix, under the specular interface, of transmission (weight T),
// subsurface (S) and the glossy-diffuse base:  T trans + (1 - T) (S sss + (1 - S) glossy_diffuse).
// Transmission and subsurface are the same interface over different interiors, so each part is a
// dielectric (the surface's specular IOR and roughness) whose interior medium is the
// transmission's (transmission_color / depth / scatter, as the dielectric material's) or the
// subsurface's (a dense medium walked at random, MAT_FLAG_RANDOM_WALK); in a thin-walled surface
// they are a thin dielectric sheet and a thin diffuse transmitter (bsdf/thin.glsl). With
// w = T + (1 - T) S the interface's share of the dielectric base, M the metalness and
// top + A(wo) x the sheen and coat over what lies below (surface.glsl: top their reflection lobes,
// A(wo) = (1 - E_sheen(wo)) (1 - E_coat(wo)) coat_color what they pass), the surface is
//     f = top + A(wo) [M metal + (1 - M) ((1 - w) glossy_diffuse + w part)]
// and a hit chooses, by one random number, the part (probability q) or the rest (1 - q):
//     part:  f_part(wo, wi) A(wo) (1 - M) w / q
//     rest:  (top + A(wo) s [M' metal + (1 - M') glossy_diffuse]) / (1 - q),
//            s = M + (1 - M)(1 - w), M' = M / s   (the surface with coat_color times s, metalness M')
// which is f in expectation for every wi. The factors depend on wo only, so next event estimation
// and BSDF sampling at the vertex use the chosen material as they would any other, and MIS
// between them stays exact. q = mean(A) (1 - M) w / (E_top + mean(A)), E_top = 1 - (1 - E_sheen)
// (1 - E_coat): about the part's share of what the surface returns.
// Light leaving a closed object through its surface (the path inside, a back-face hit) meets the
// part it is in (the stack says which) and passes the sheen and coat on its way out: f for wi
// outside is multiplied by A(wi). Each crossing of the interface (in or out) is tinted by
// transmission_color where transmission_depth is 0 (a surface tint, as OpenPBR defines it).
#ifndef INTEGRATOR_SURFACE_PARTS_GLSL
#define INTEGRATOR_SURFACE_PARTS_GLSL
#include "../bsdf/surface.glsl"
#include "medium.glsl"

// What the hit's chosen part changes at its vertex: the tint of light crossing the interface
// (wi on the other side from wo) and, when the path leaves the object, the sheen and coat it passes
// (coat: wc, alpha, ior; sheen: rgb colour times weight, w roughness).
struct SurfacePartVertex {
    bool isPart;
    vec3 crossTint;
    bool leaving;
    vec4 coat;
    vec4 sheen;
};

// The part's share of the dielectric base, w, and the probability that a part chosen is the
// transmission (the first part's params.z and params.w; renderer/gpu_materials.cpp).
bool surfaceHasParts(GpuMaterial m) {
    return HAS_MEDIA(MEDIA_SURFACE_PARTS) && m.info.x == MAT_SURFACE &&
           (m.info.y & (MAT_FLAG_TRANSMISSION_PART | MAT_FLAG_SUBSURFACE_PART)) != 0u;
}

// The fraction the sheen and coat of surface m pass at cos theta = mu (A above, without the colour).
float surfaceLayersPass(float mu, vec4 coat, vec4 sheen) {
    float a = 1.0;
    if (coat.x > 0.0) a *= 1.0 - coat.x * dielectricAlbedo(mu, max(coat.y, GGX_MIN_ALPHA), coat.z);
    float sw = maxComponent(sheen.rgb);
    if (sw > 0.0) a *= 1.0 - sw * sheenAlbedo(mu, sheen.w);
    return a;
}

// At a hit on surface `mat` (index `index`, textures applied, shading normal ns): chooses the part
// or the rest (see the header), replacing mat and index by the part's when it is chosen. Returns
// the weight (wo only) that multiplies the path's throughput; pv says what the vertex does with
// light crossing the surface.
vec3 surfaceChoosePart(inout GpuMaterial mat, inout uint index, vec3 wo, vec3 ng, vec3 ns, uvec4 stack, float u,
                       out SurfacePartVertex pv) {
    pv.isPart = false;
    pv.crossTint = vec3(1.0);
    pv.leaving = false;
    pv.coat = vec4(mat.params.w, mat.eta.w, mat.k.w, 0.0);
    pv.sheen = mat.sheen;
    uint first = mat.info.w;
    bool hasT = (mat.info.y & MAT_FLAG_TRANSMISSION_PART) != 0u;
    bool hasS = (mat.info.y & MAT_FLAG_SUBSURFACE_PART) != 0u;
    GpuMaterial part = loadMaterial(first);
    bool thin = part.info.x == MAT_THIN_DIELECTRIC || part.info.x == MAT_DIFFUSE_TRANSMISSION;
    vec3 coatColor = mat.k.rgb;
    float alpha = mat.params.x;  // the textured specular roughness, for the part's interface
    if (!thin && dot(ng, wo) < 0.0) {
        // Inside: the part whose interior the path is in (the transmission's unless the stack
        // holds only the subsurface's).
        uint chosen = first;
        if (hasT && hasS && stackRemove(stack, first + 1u) == stack) chosen = first + 1u;
        if (chosen != first) part = loadMaterial(chosen);
        pv.isPart = true;
        pv.leaving = true;
        pv.crossTint = coatColor * (chosen == first && hasT ? part.sheen.rgb : vec3(1.0));
        if (part.info.x == MAT_ROUGH_DIELECTRIC) part.params.x = alpha;
        mat = part;
        index = chosen;
        return vec3(1.0);
    }
    float mu = clamp(abs(dot(ns, wo)), 1e-4, 1.0);
    float A = surfaceLayersPass(mu, pv.coat, pv.sheen);
    float meanA = A * surfaceMean(coatColor);
    float M = mat.albedo.w;
    float w = part.params.z;
    float q = meanA * (1.0 - M) * w / max(1.0 - A + meanA, 1e-6);
    if (u < q) {
        bool transmission = hasT && u < q * part.params.w;
        uint chosen = transmission || !hasT ? first : first + 1u;
        if (chosen != first) part = loadMaterial(chosen);
        pv.isPart = true;
        if (transmission) pv.crossTint = part.sheen.rgb;
        if (part.info.x == MAT_ROUGH_DIELECTRIC || part.info.x == MAT_THIN_DIELECTRIC ||
            part.info.x == MAT_DIFFUSE_TRANSMISSION)
            part.params.x = alpha;
        mat = part;
        index = chosen;
        return coatColor * (A * (1.0 - M) * w / q);
    }
    float s = M + (1.0 - M) * (1.0 - w);
    mat.albedo.w = s > 0.0 ? M / s : 0.0;
    mat.k.rgb *= s;
    return vec3(1.0 / (1.0 - q));
}

// The factor of a part's f for wi (world space) at a vertex pv: the crossing tint where wi is on
// the other side of the surface (geometric normal ng) from wo, and the layers passed when leaving.
vec3 surfacePartFactor(SurfacePartVertex pv, vec3 ng, vec3 wo, vec3 wi, vec3 ns) {
    if (!pv.isPart || (dot(ng, wo) > 0.0) == (dot(ng, wi) > 0.0)) return vec3(1.0);
    vec3 f = pv.crossTint;
    if (pv.leaving) f *= surfaceLayersPass(clamp(abs(dot(ns, wi)), 1e-4, 1.0), pv.coat, pv.sheen);
    return f;
}

#endif
