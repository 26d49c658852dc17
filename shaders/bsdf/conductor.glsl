// Conductors: Fresnel reflection with the full complex-IOR equations (eta + i k per RGB channel),
// smooth (a delta mirror lobe) or rough (Trowbridge-Reitz / GGX microfacets, microfacet.glsl).
// Reference: Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., sec. 9.5 and 9.6
// (ConductorBxDF); Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces".
//   f(wo, wi) = tint * D(wm) G2(wo, wi) F(wo.wm) / (4 cos(wo) cos(wi)),  wm = normalize(wo + wi)
//   pdf(wi)   = D_wo(wm) / (4 |wo.wm|)   (visible normals, then the reflection Jacobian)
// JSON (docs/scene-format.md): { "type": "conductor", "metal": "gold" | "copper" | "aluminium" |
//   "silver" | "chromium" | "platinum" | "perfect" | "custom" (default "aluminium"),
//   "eta": [r, g, b] > 0 and "k": [r, g, b] >= 0 (only with "custom"), "roughness": GGX alpha in
//   [0, 1] (default 0; below 1e-3 the smooth model is used), "tint": [r, g, b] in [0, 1]
//   (default 1), "energy_compensation": true | false (default false) }.
// GpuMaterial: albedo.rgb = tint, params.x = alpha, eta.rgb / k.rgb = the complex IOR,
//   info.y & MAT_FLAG_FRESNEL_ONE: F = 1 (the "perfect" metal, used by the furnace tests),
//   info.y & MAT_FLAG_ENERGY_COMPENSATION: multiple-scattering compensation, see below.
// Energy compensation: single-scattering GGX loses the light that bounces more than once between
// microfacets (about 3% at alpha 0.1, 60% at alpha 1 for F = 1). We scale the single-scattering
// lobe by 1 + F0 (1 - E(mu_o)) / E(mu_o), where E(mu, alpha) is the directional albedo of the
// F = 1 lobe (Turquin 2019, "Practical multiple scattering compensation for microfacet models",
// eq. 10; the scheme Blender Cycles and Filament use). E is tabulated on the CPU at startup
// (shaders/bsdf/ggx_albedo.comp, run once per renderer) with this file's D and G2. With F = 1 the lobe then
// reflects exactly 1 for every wo. The factor depends on wo only, so the compensated lobe is not
// exactly reciprocal (Kulla & Conty 2017 is, at the price of an extra sampled lobe); the sampling
// is unchanged, so the pdf is that of the uncompensated lobe.
#ifndef BSDF_CONDUCTOR_GLSL
#define BSDF_CONDUCTOR_GLSL
#include "common.glsl"
#include "fresnel.glsl"
#include "microfacet.glsl"

vec3 conductorFresnel(GpuMaterial m, float cosThetaI) {
    if ((m.info.y & MAT_FLAG_FRESNEL_ONE) != 0u) return vec3(1.0);
    return fresnelComplex(cosThetaI, m.eta.rgb, m.k.rgb);
}

// Directional albedo E(mu, alpha) of the F = 1 GGX lobe: bilinear in the CPU-made table
// (GGX_ALBEDO_TABLE_SIZE^2 entries, mu = i / (N - 1) fastest, alpha = j / (N - 1)).
float ggxAlbedo(float mu, float alpha) {
    const int N = GGX_ALBEDO_TABLE_SIZE;
    vec2 x = clamp(vec2(mu, alpha), 0.0, 1.0) * float(N - 1);
    ivec2 i0 = min(ivec2(x), ivec2(N - 2));
    vec2 t = x - vec2(i0);
    float e00 = bsdfTable(BSDF_TABLE_GGX + i0.y * N + i0.x), e10 = bsdfTable(BSDF_TABLE_GGX + i0.y * N + i0.x + 1);
    float e01 = bsdfTable(BSDF_TABLE_GGX + (i0.y + 1) * N + i0.x), e11 = bsdfTable(BSDF_TABLE_GGX + (i0.y + 1) * N + i0.x + 1);
    return mix(mix(e00, e10, t.x), mix(e01, e11, t.x), t.y);
}

vec3 roughConductorCompensation(GpuMaterial m, vec3 wo, float alpha) {
    if ((m.info.y & MAT_FLAG_ENERGY_COMPENSATION) == 0u) return vec3(1.0);
    float e = max(ggxAlbedo(wo.z, alpha), 1e-3);
    vec3 f0 = conductorFresnel(m, 1.0);
    return 1.0 + f0 * (1.0 - e) / e;
}

vec3 roughConductorEval(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    vec3 wm = wo + wi;
    if (dot(wm, wm) == 0.0) return vec3(0.0);
    wm = normalize(wm);
    vec3 F = conductorFresnel(m, dot(wo, wm));
    return m.albedo.rgb * roughConductorCompensation(m, wo, alpha) * F *
           (ggxD(wm, alpha) * ggxG(wo, wi, alpha) / (4.0 * wo.z * wi.z));
}

float roughConductorPdf(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    vec3 wm = wo + wi;
    if (dot(wm, wm) == 0.0) return 0.0;
    wm = normalize(wm);
    return ggxVisibleD(wo, wm, alpha) / (4.0 * abs(dot(wo, wm)));
}

BsdfSample roughConductorSample(GpuMaterial m, vec3 wo, vec2 u) {
    if (wo.z <= 0.0) return bsdfInvalidSample();
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    vec3 wm = ggxSampleVisibleNormal(wo, alpha, u);
    BsdfSample s;
    s.wi = reflectAbout(wo, wm);
    s.flags = 0u;
    if (s.wi.z <= 0.0) return bsdfInvalidSample();  // reflected below the surface: lost energy
    s.pdf = ggxVisibleD(wo, wm, alpha) / (4.0 * abs(dot(wo, wm)));
    s.f = roughConductorEval(m, wo, s.wi);
    return s;
}

// Smooth: the delta mirror lobe with the Fresnel term at the incident angle.
BsdfSample smoothConductorSample(GpuMaterial m, vec3 wo) {
    if (wo.z <= 0.0) return bsdfInvalidSample();
    BsdfSample s;
    s.wi = reflectLocal(wo);
    s.pdf = 1.0;
    s.f = m.albedo.rgb * conductorFresnel(m, wo.z) / wo.z;
    s.flags = BSDF_FLAG_DELTA;
    return s;
}

#endif
