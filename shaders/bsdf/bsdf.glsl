// The one wrapper around every material model (the integrator and the test kernels call only
// these): chooses the model by GpuMaterial::info.x (MAT_*), works in the local frame (+z = the
// shading normal; turned towards wo for reflection-only models, the unflipped front normal for
// transmissive ones, see bsdfHasTransmission), and rejects degenerate samples (zero or non-finite
// pdf or value, wi in the tangent plane) for every model in one place.
// The models, their references and their parameters: one file each (lambert, oren_nayar,
// specular, dielectric, conductor); docs/materials.md compares them.
#ifndef BSDF_BSDF_GLSL
#define BSDF_BSDF_GLSL
#include "common.glsl"
#include "lambert.glsl"
#include "oren_nayar.glsl"
#include "specular.glsl"
#include "dielectric.glsl"
#include "conductor.glsl"

// True for models that transmit: their local frame must keep the front side (wo.z < 0 = inside).
bool bsdfHasTransmission(GpuMaterial m) {
    uint t = m.info.x;
    return t == MAT_TRANSMISSION || t == MAT_DIELECTRIC || t == MAT_ROUGH_DIELECTRIC;
}

// True when every lobe is a delta (eval and pdf are zero everywhere; light sampling is useless).
bool bsdfIsDelta(GpuMaterial m) {
    uint t = m.info.x;
    return t == MAT_MIRROR || t == MAT_TRANSMISSION || t == MAT_DIELECTRIC || t == MAT_CONDUCTOR;
}

vec3 bsdfEval(GpuMaterial m, vec3 wo, vec3 wi) {
    switch (m.info.x) {
    case MAT_DIFFUSE: return lambertEval(m.albedo.rgb, wo, wi);
    case MAT_OREN_NAYAR: return orenNayarEval(m, wo, wi);
    case MAT_EON: return eonEval(m, wo, wi);
    case MAT_ROUGH_DIELECTRIC: return roughDielectricEval(m, wo, wi);
    case MAT_ROUGH_CONDUCTOR: return roughConductorEval(m, wo, wi);
    default: return vec3(0.0);  // delta models
    }
}

float bsdfPdf(GpuMaterial m, vec3 wo, vec3 wi) {
    switch (m.info.x) {
    case MAT_DIFFUSE: return lambertPdf(wo, wi);
    case MAT_OREN_NAYAR:
    case MAT_EON: return orenNayarPdf(wo, wi);
    case MAT_ROUGH_DIELECTRIC: return roughDielectricPdf(m, wo, wi);
    case MAT_ROUGH_CONDUCTOR: return roughConductorPdf(m, wo, wi);
    default: return 0.0;
    }
}

// Both at once, for light sampling: one switch instead of two keeps the integrator's code (and
// its register use) smaller, since every call site inlines every model.
vec3 bsdfEvalPdf(GpuMaterial m, vec3 wo, vec3 wi, out float pdf) {
    switch (m.info.x) {
    case MAT_DIFFUSE: pdf = lambertPdf(wo, wi); return lambertEval(m.albedo.rgb, wo, wi);
    case MAT_OREN_NAYAR: pdf = orenNayarPdf(wo, wi); return orenNayarEval(m, wo, wi);
    case MAT_EON: pdf = orenNayarPdf(wo, wi); return eonEval(m, wo, wi);
    case MAT_ROUGH_DIELECTRIC: pdf = roughDielectricPdf(m, wo, wi); return roughDielectricEval(m, wo, wi);
    case MAT_ROUGH_CONDUCTOR: pdf = roughConductorPdf(m, wo, wi); return roughConductorEval(m, wo, wi);
    default: pdf = 0.0; return vec3(0.0);
    }
}

// u.xy: the direction, u.z: the choice between lobes (dielectrics).
BsdfSample bsdfSample(GpuMaterial m, vec3 wo, vec3 u) {
    BsdfSample s;
    switch (m.info.x) {
    case MAT_MIRROR: s = mirrorSample(m, wo); break;
    case MAT_TRANSMISSION: s = transmissionSample(m, wo); break;
    case MAT_DIELECTRIC: s = smoothDielectricSample(m, wo, u.z); break;
    case MAT_ROUGH_DIELECTRIC: s = roughDielectricSample(m, wo, u.z, u.xy); break;
    case MAT_CONDUCTOR: s = smoothConductorSample(m, wo); break;
    case MAT_ROUGH_CONDUCTOR: s = roughConductorSample(m, wo, u.xy); break;
    default: {  // the cosine-sampled diffuse models
        s.wi = lambertSample(wo, u.xy);
        s.pdf = bsdfPdf(m, wo, s.wi);
        s.f = bsdfEval(m, wo, s.wi);
        s.flags = 0u;
        break;
    }
    }
    bool finite = !any(isnan(s.f)) && !any(isinf(s.f)) && !isnan(s.pdf) && !isinf(s.pdf);
    if (!(s.pdf > 0.0) || !finite || s.wi.z == 0.0 || !(maxComponent(s.f) > 0.0)) return bsdfInvalidSample();
    return s;
}

bool bsdfIsBlack(GpuMaterial m) { return m.info.x == MAT_DIFFUSE && maxComponent(m.albedo.rgb) <= 0.0; }

#endif
