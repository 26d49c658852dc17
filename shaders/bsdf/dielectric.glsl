// Dielectrics (glass, water): smooth (two delta lobes) or rough (Trowbridge-Reitz / GGX
// microfacet reflection and transmission).
// Reference: Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through
// Rough Surfaces", EGSR (eqs. 16, 17, 20, 21); Pharr, Jakob, Humphreys, "Physically Based
// Rendering", 4th ed., sec. 9.5 (smooth) and 9.7 (rough DielectricBxDF), whose structure this
// follows.
// JSON: "type": "dielectric" with "ior" (relative IOR n_inside / n_outside), "roughness" (GGX
//   alpha; below 1e-3 the smooth model is used) and "tint" (multiplies both lobes); their ranges
//   and defaults are the scene schema's (renderer/scene_schema.cpp, docs/scene-format.md).
// GpuMaterial: albedo.rgb = tint, params.x = alpha, params.y = eta (inside over outside).
// Conventions: the local frame is NOT turned towards the viewer for dielectrics: +z is the
//   outward (front) normal, so wo.z < 0 means the viewer is inside the medium, and the indices
//   are swapped there (eta -> 1/eta) by every Fresnel and refraction call.
// Smooth: F = fresnelDielectric(cos(wo), eta); reflection is chosen with probability F,
//   refraction with 1 - F (total internal reflection: F = 1, always reflect). Each lobe's f
//   carries its Fresnel factor, so the sample weight is 1 for reflection and 1 / etap^2 for
//   refraction.
// Rough: the generalized half vector wm = normalize(wo + etap wi) with etap = eta when wo is
//   outside and 1/eta when inside (for reflection etap = 1), turned to wm.z > 0; microfacets that
//   face away from wo or wi are discarded. Sampling draws a visible normal wm from wo first,
//   F = fresnelDielectric(wo.wm, eta) against that microfacet, reflects with probability F and
//   refracts with 1 - F; total internal reflection through the sampled microfacet gives F = 1 and
//   so falls back to reflection. The pdfs are
//     reflection:   D_wo(wm) / (4 |wo.wm|) * F
//     transmission: D_wo(wm) * |wi.wm| etap^2 / (wo.wm + etap wi.wm)^2 * (1 - F)
//   (the second factor is the transmission Jacobian dwm/dwi, Walter et al. eq. 17), and the BSDF
//     reflection:   tint D G2 F / (4 |cos wo| |cos wi|)
//     transmission: tint D G2 (1 - F) |wi.wm| |wo.wm| / (|cos wo| |cos wi| (wo.wm + etap wi.wm)^2)
//                   * etap^2 / etap^2
//   where the last etap^2 / etap^2 is the Jacobian's etap^2 times the 1 / etap^2 radiance
//   scaling (see specular.glsl: camera paths carry radiance, whose density changes by etap^2 across
//   the interface). pbrt-v4 writes the same thing as denom = (wi.wm + wo.wm / etap)^2.
// Smith term: height-correlated G2 (microfacet.glsl).
// Rough transmission alone (JSON "transmission" with roughness > 0, MAT_FLAG_NO_REFLECTION): the
//   same Trowbridge-Reitz BTDF without the reflection lobe, the rough counterpart of perfect
//   transmission (specular.glsl): every microfacet refracts all the light (F = 0), except where
//   it would totally reflect internally (F = 1, the light reflects off that microfacet). Sampling
//   and pdfs are the rough dielectric's with that F, so they stay consistent; the furnace loses
//   only what single-scattering GGX loses.
#ifndef BSDF_DIELECTRIC_GLSL
#define BSDF_DIELECTRIC_GLSL
#include "common.glsl"
#include "fresnel.glsl"
#include "microfacet.glsl"

// The smooth dielectric's two lobes, each with its selection probability as pdf: reflection
// (probability R) and refraction (probability T = 1 - R; invalid where it does not exist).
BsdfSample smoothDielectricReflection(GpuMaterial m, vec3 wo, float R) {
    BsdfSample s;
    s.wi = reflectLocal(wo);
    s.pdf = R;
    s.f = m.albedo.rgb * (R / abs(s.wi.z));
    s.flags = BSDF_FLAG_DELTA;
    return s;
}

BsdfSample smoothDielectricRefraction(GpuMaterial m, vec3 wo, float T) {
    BsdfSample s;
    float etap;
    if (!(T > 0.0) || !refractDir(wo, vec3(0.0, 0.0, 1.0), m.params.y, etap, s.wi) || s.wi.z == 0.0)
        return bsdfInvalidSample();
    s.pdf = T;
    s.f = m.albedo.rgb * (T / (abs(s.wi.z) * etap * etap));
    s.flags = BSDF_FLAG_DELTA | BSDF_FLAG_TRANSMISSION;
    return s;
}

BsdfSample smoothDielectricSample(GpuMaterial m, vec3 wo, float uc) {
    if (wo.z == 0.0) return bsdfInvalidSample();
    float R = fresnelDielectric(wo.z, m.params.y);
    // uc < R includes total internal reflection (R = 1)
    return uc < R ? smoothDielectricReflection(m, wo, R) : smoothDielectricRefraction(m, wo, 1.0 - R);
}

// The smooth dielectric's other lobe: given the lobe `taken` (a smoothDielectricSample), the
// sample the other choice would have given (its direction, f and pdf = its selection probability),
// or an invalid sample when that lobe is absent (total internal reflection, R = 0). For glass
// splitting (integrator/path.glsl).
BsdfSample smoothDielectricOtherLobe(GpuMaterial m, vec3 wo, BsdfSample taken) {
    float R = fresnelDielectric(wo.z, m.params.y);
    if ((taken.flags & BSDF_FLAG_TRANSMISSION) == 0u) return smoothDielectricRefraction(m, wo, 1.0 - R);
    return R > 0.0 ? smoothDielectricReflection(m, wo, R) : bsdfInvalidSample();
}

// The generalized half vector for the pair (wo, wi), wm.z > 0; false for degenerate pairs and for
// microfacets that face away from wo or wi.
bool dielectricHalfVector(vec3 wo, vec3 wi, float eta, out vec3 wm, out float etap) {
    float cosO = wo.z, cosI = wi.z;
    wm = vec3(0.0, 0.0, 1.0);
    etap = 1.0;
    if (cosO == 0.0 || cosI == 0.0) return false;
    bool reflect = cosO * cosI > 0.0;
    if (!reflect) etap = cosO > 0.0 ? eta : 1.0 / eta;
    vec3 h = wi * etap + wo;
    if (dot(h, h) == 0.0) return false;
    wm = normalize(h);
    if (wm.z < 0.0) wm = -wm;
    if (dot(wm, wi) * cosI < 0.0 || dot(wm, wo) * cosO < 0.0) return false;
    return true;
}

// Fresnel reflectance against microfacet wm: the dielectric's, or for rough transmission alone 0
// unless the microfacet reflects totally.
float roughDielectricFresnel(GpuMaterial m, float cosThetaI, float eta) {
    float F = fresnelDielectric(cosThetaI, eta);
    if ((m.info.y & MAT_FLAG_NO_REFLECTION) != 0u) F = F >= 1.0 ? 1.0 : 0.0;
    return F;
}

vec3 roughDielectricEval(GpuMaterial m, vec3 wo, vec3 wi) {
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    float eta = m.params.y;
    vec3 wm;
    float etap;
    if (!dielectricHalfVector(wo, wi, eta, wm, etap)) return vec3(0.0);
    float F = roughDielectricFresnel(m, dot(wo, wm), eta);
    float D = ggxD(wm, alpha), G = ggxG(wo, wi, alpha);
    if (wo.z * wi.z > 0.0) return m.albedo.rgb * (D * G * F / abs(4.0 * wo.z * wi.z));
    float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap) * wi.z * wo.z;
    // pbrt-v4's form: the Jacobian's etap^2 and the radiance 1/etap^2 cancel into 1/etap^2 here.
    float ft = D * (1.0 - F) * G * abs(dot(wi, wm) * dot(wo, wm) / denom) / (etap * etap);
    return m.albedo.rgb * ft;
}

float roughDielectricPdf(GpuMaterial m, vec3 wo, vec3 wi) {
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    float eta = m.params.y;
    vec3 wm;
    float etap;
    if (!dielectricHalfVector(wo, wi, eta, wm, etap)) return 0.0;
    float R = roughDielectricFresnel(m, dot(wo, wm), eta), T = 1.0 - R;
    if (wo.z * wi.z > 0.0) return ggxVisibleD(wo, wm, alpha) / (4.0 * abs(dot(wo, wm))) * R;
    float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap);
    float dwmDwi = abs(dot(wi, wm)) / denom;
    return ggxVisibleD(wo, wm, alpha) * dwmDwi * T;
}

BsdfSample roughDielectricSample(GpuMaterial m, vec3 wo, float uc, vec2 u) {
    if (wo.z == 0.0) return bsdfInvalidSample();
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    float eta = m.params.y;
    vec3 wm = ggxSampleVisibleNormal(wo, alpha, u);
    float R = roughDielectricFresnel(m, dot(wo, wm), eta), T = 1.0 - R;
    BsdfSample s;
    if (uc < R) {
        s.wi = reflectAbout(wo, wm);
        if (!sameHemisphere(wo, s.wi)) return bsdfInvalidSample();
        s.flags = 0u;
    } else {
        float etap;
        if (!refractDir(wo, wm, eta, etap, s.wi)) return bsdfInvalidSample();  // R = 1 there: unreachable
        if (sameHemisphere(wo, s.wi) || s.wi.z == 0.0) return bsdfInvalidSample();
        s.flags = BSDF_FLAG_TRANSMISSION;
    }
    // Evaluate through the same functions as eval/pdf, so that the sample, eval and pdf agree
    // exactly (the half vector recomputed from (wo, wi) is the sampled wm up to rounding).
    s.pdf = roughDielectricPdf(m, wo, s.wi);
    s.f = roughDielectricEval(m, wo, s.wi);
    return s;
}

#endif
