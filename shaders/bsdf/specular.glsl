// The two ideal delta lobes.
//   Perfect mirror: wi = (-wo.x, -wo.y, wo.z), reflectance "tint" at every angle (no Fresnel).
//     JSON: { "type": "mirror", "tint": [r, g, b] in [0, 1], default [1, 1, 1] }.
//   Perfect transmission: all light refracts (Snell's law, relative IOR "ior" = n_inside /
//     n_outside, default 1: straight through), none is reflected, except under total internal
//     reflection where the mirror direction is taken. No Fresnel: an idealisation, for thin
//     films, windows and tests. JSON: { "type": "transmission", "tint", "ior": [1, 4] (default 1) }.
//     The radiance crossing the interface is scaled by 1 / etap^2 (etap = the IOR ratio crossed,
//     eta entering, 1/eta leaving): radiance is not conserved across a refraction, because the
//     solid angle is compressed by etap^2 (Veach 1997 sec. 5.2; pbrt-v4 sec. 9.5.2). The camera
//     paths this renderer traces carry radiance, so the factor is always applied.
// Both are delta distributions: eval and pdf are 0, sample returns the single direction with
// pdf 1 and f = coefficient / |cos(wi)| (so the sample weight is the coefficient).
// Reference: Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., sec. 9.3 and 9.5.
#ifndef BSDF_SPECULAR_GLSL
#define BSDF_SPECULAR_GLSL
#include "common.glsl"
#include "fresnel.glsl"

BsdfSample mirrorSample(GpuMaterial m, vec3 wo) {
    if (wo.z <= 0.0) return bsdfInvalidSample();
    BsdfSample s;
    s.wi = reflectLocal(wo);
    s.pdf = 1.0;
    s.f = m.albedo.rgb / wo.z;
    s.flags = BSDF_FLAG_DELTA;
    return s;
}

// wo may be on either side: wo.z < 0 means the viewer is inside.
BsdfSample transmissionSample(GpuMaterial m, vec3 wo) {
    if (wo.z == 0.0) return bsdfInvalidSample();
    BsdfSample s;
    s.pdf = 1.0;
    float etap;
    if (!refractDir(wo, vec3(0.0, 0.0, 1.0), m.params.y, etap, s.wi)) {
        s.wi = reflectLocal(wo);
        s.f = m.albedo.rgb / abs(wo.z);
        s.flags = BSDF_FLAG_DELTA;
        return s;
    }
    s.f = m.albedo.rgb / (abs(s.wi.z) * etap * etap);
    s.flags = BSDF_FLAG_DELTA | BSDF_FLAG_TRANSMISSION;
    return s;
}

#endif
