// Rough diffuse reflection: three variants of Oren-Nayar, all sampled cosine-weighted
// (pdf = cos(wi) / pi), all two-sided in the local frame (wo.z > 0 and wi.z > 0 required).
//
// 1. "oren_nayar" (MAT_OREN_NAYAR): the qualitative model of Oren & Nayar 1994, "Generalization
//    of Lambert's Reflectance Model", SIGGRAPH, eq. 30 (as in pbrt-v3 sec. 8.4.2):
//      f = albedo / pi * (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta))
//      A = 1 - sigma^2 / (2 (sigma^2 + 0.33)),  B = 0.45 sigma^2 / (sigma^2 + 0.09)
//      alpha = max(theta_i, theta_o), beta = min(theta_i, theta_o)
//    with sigma the standard deviation of the facet slope angle in radians. It models only single
//    scattering between V-cavities, so it loses energy as sigma grows (white furnace at normal
//    incidence = A: 0.87 at sigma 0.5, 0.62 at sigma 1).
//    JSON: { "type": "oren_nayar", "albedo": [r, g, b] in [0, 1], "sigma": radians in
//    [0, pi/2] (default 0.5), "energy_compensation": false }.
//    With "energy_compensation": true (MAT_FLAG_ENERGY_COMPENSATION) f is multiplied by the global
//    factor 1 / (1 - 0.33 sigma^2 / (sigma^2 + 0.09)): it restores much of the lost energy on
//    average but is not exact: it depends on neither direction, so some angles still lose energy
//    and others can exceed 1 (docs/materials.md lists measured furnace values).
// 2. "eon" (MAT_EON): the energy-preserving Oren-Nayar of Portsmouth, Kutz & Hill 2025, "EON: A
//    practical energy-preserving rough diffuse BRDF", JCGT 14(1) (arXiv 2410.18026), the diffuse
//    model of OpenPBR 1.1: Fujii's improved Oren-Nayar single-scattering lobe (FON) plus a
//    multiple-scattering lobe built from FON's analytic directional albedo E_F (Kulla-Conty form),
//    so that with albedo 1 the reflected energy is exactly 1 for every wo, and f is reciprocal.
//    This file transcribes the paper's listing 1 with the exact E_F.
//    JSON: { "type": "eon", "albedo": [r, g, b] in [0, 1], "roughness": r in [0, 1] (default 0.5) }.
//    Its r is FON's roughness (sigma' in the paper), not the slope deviation sigma of (1).
// GpuMaterial: albedo.rgb = albedo, params.x = sigma (1) or r (2).
#ifndef BSDF_OREN_NAYAR_GLSL
#define BSDF_OREN_NAYAR_GLSL
#include "common.glsl"
#include "../lib/sampling.glsl"

float orenNayarCompensation(float sigma) {
    float s2 = sigma * sigma;
    return 1.0 / (1.0 - 0.33 * s2 / (s2 + 0.09));
}

vec3 orenNayarEval(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    float sigma = m.params.x, s2 = sigma * sigma;
    float A = 1.0 - s2 / (2.0 * (s2 + 0.33));
    float B = 0.45 * s2 / (s2 + 0.09);
    float sinI = safeSqrt(1.0 - wi.z * wi.z), sinO = safeSqrt(1.0 - wo.z * wo.z);
    float maxCos = 0.0;
    if (sinI > 1e-4 && sinO > 1e-4) maxCos = max(0.0, (wi.x * wo.x + wi.y * wo.y) / (sinI * sinO));
    float sinAlpha, tanBeta;
    if (wi.z > wo.z) {  // theta_i < theta_o
        sinAlpha = sinO;
        tanBeta = sinI / wi.z;
    } else {
        sinAlpha = sinI;
        tanBeta = sinO / wo.z;
    }
    float f = INV_PI * (A + B * maxCos * sinAlpha * tanBeta);
    if ((m.info.y & MAT_FLAG_ENERGY_COMPENSATION) != 0u) f *= orenNayarCompensation(sigma);
    return m.albedo.rgb * f;
}

const float EON_C1 = 0.5 - 2.0 / (3.0 * PI);           // constant1_FON
const float EON_C2 = 2.0 / 3.0 - 28.0 / (15.0 * PI);   // constant2_FON

// FON directional albedo, exact (listing 1, E_FON_exact); mu clamped away from the removable
// singularity at 0.
float eonAlbedoF(float mu, float r) {
    mu = clamp(mu, 1e-6, 1.0);
    float AF = 1.0 / (1.0 + EON_C1 * r);
    float BF = r * AF;
    float Si = safeSqrt(1.0 - mu * mu);
    float G = Si * (acos(mu) - Si * mu) + (2.0 / 3.0) * ((Si / mu) * (1.0 - Si * Si * Si) - Si);
    return AF + (BF * INV_PI) * G;
}

vec3 eonEval(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    vec3 rho = m.albedo.rgb;
    float r = m.params.x;
    float muI = wi.z, muO = wo.z;
    float s = dot(wi, wo) - muI * muO;
    float sOverT = s > 0.0 ? s / max(muI, muO) : s;
    float AF = 1.0 / (1.0 + EON_C1 * r);
    vec3 fss = (rho * INV_PI) * AF * (1.0 + r * sOverT);
    float EFo = eonAlbedoF(muO, r), EFi = eonAlbedoF(muI, r);
    float avgEF = AF * (1.0 + EON_C2 * r);
    vec3 rhoMs = (rho * rho) * avgEF / (vec3(1.0) - rho * (1.0 - avgEF));
    const float eps = 1e-7;
    vec3 fms = (rhoMs * INV_PI) * max(eps, 1.0 - EFo) * max(eps, 1.0 - EFi) / max(eps, 1.0 - avgEF);
    return fss + fms;
}

float orenNayarPdf(vec3 wo, vec3 wi) { return (wo.z > 0.0 && wi.z > 0.0) ? cosineHemispherePdf(wi.z) : 0.0; }

#endif
