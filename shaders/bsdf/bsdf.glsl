// The one wrapper around every material model: chooses the model, keeps wo and wi in the local
// frame (+z = shading normal, already turned towards wo), and rejects degenerate samples.
#ifndef BSDF_BSDF_GLSL
#define BSDF_BSDF_GLSL
#include "../scene/buffers.glsl"
#include "lambert.glsl"

#define BSDF_FLAG_DELTA 1u

struct BsdfSample {
    vec3 wi;       // local frame
    vec3 f;        // BSDF value (without the cosine)
    float pdf;     // solid-angle pdf; for delta lobes the discrete probability of the lobe
    uint flags;    // BSDF_FLAG_*
};

vec3 bsdfEval(GpuMaterial m, vec3 wo, vec3 wi) {
    return lambertEval(m.albedo.rgb, wo, wi);
}

float bsdfPdf(GpuMaterial m, vec3 wo, vec3 wi) {
    return lambertPdf(wo, wi);
}

BsdfSample bsdfSample(GpuMaterial m, vec3 wo, vec2 u) {
    BsdfSample s;
    s.flags = 0u;
    s.wi = lambertSample(wo, u);
    s.pdf = lambertPdf(wo, s.wi);
    s.f = lambertEval(m.albedo.rgb, wo, s.wi);
    if (!(s.pdf > 0.0)) { s.pdf = 0.0; s.f = vec3(0.0); }
    return s;
}

bool bsdfIsBlack(GpuMaterial m) { return m.info.x == MAT_DIFFUSE && maxComponent(m.albedo.rgb) <= 0.0; }

#endif
