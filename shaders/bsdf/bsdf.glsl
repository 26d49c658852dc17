// The one wrapper around every material model (the integrator and the test kernels call only
// these): chooses the model by GpuMaterial::info.x (MAT_*), works in the local frame (+z = the
// shading normal; turned towards wo for reflection-only models, the unflipped front normal for
// transmissive ones, see bsdfHasTransmission), and rejects degenerate samples (zero or non-finite
// pdf or value, wi in the tangent plane) for every model in one place.
// The models, their references and their parameters: one file each (lambert, oren_nayar,
// specular, dielectric, conductor), listed once in models.glsl; docs/materials.md compares them.
#ifndef BSDF_BSDF_GLSL
#define BSDF_BSDF_GLSL
#include "models.glsl"

// Each operation is one switch over the list of models (models.glsl). Each model's code is guarded
// by HAS_MATERIAL (scene/features.glsl): a scene-specialised program keeps only the models its
// scene uses (on llvmpipe every case of a switch runs, under a lane mask, whatever the data).
#define BSDF_EVAL_CASE(id, eval, pdf, sample, traits) case id: if (HAS_MATERIAL(id)) return eval; break;
#define BSDF_PDF_CASE(id, eval, pdf, sample, traits) case id: if (HAS_MATERIAL(id)) return pdf; break;
#define BSDF_EVAL_PDF_CASE(id, eval, pdf_, sample, traits) case id: if (HAS_MATERIAL(id)) { pdf = pdf_; return eval; } break;
#define BSDF_SAMPLE_CASE(id, eval, pdf, sample, traits) case id: if (HAS_MATERIAL(id)) s = sample; break;
#define BSDF_TRAITS_CASE(id, eval, pdf, sample, traits) case id: return traits;

uint bsdfTraits(GpuMaterial m) {
    switch (m.info.x) {
    BSDF_MODELS(BSDF_TRAITS_CASE)
    default: return 0u;
    }
}

// True for models that transmit: their local frame must keep the front side (wo.z < 0 = inside).
bool bsdfHasTransmission(GpuMaterial m) { return (bsdfTraits(m) & BSDF_TRANSMITS) != 0u; }

// True for the thin-walled models (bsdf/thin.glsl): they transmit, but nothing refracts and no
// interior is entered.
bool bsdfIsThin(GpuMaterial m) { return m.info.x == MAT_THIN_DIELECTRIC || m.info.x == MAT_DIFFUSE_TRANSMISSION; }

// True when every lobe is a delta (eval and pdf are zero everywhere; light sampling is useless).
bool bsdfIsDelta(GpuMaterial m) { return (bsdfTraits(m) & BSDF_DELTA) != 0u; }

vec3 bsdfEval(GpuMaterial m, vec3 wo, vec3 wi) {
    switch (m.info.x) {
    BSDF_MODELS(BSDF_EVAL_CASE)
    default: break;
    }
    return vec3(0.0);
}

float bsdfPdf(GpuMaterial m, vec3 wo, vec3 wi) {
    switch (m.info.x) {
    BSDF_MODELS(BSDF_PDF_CASE)
    default: break;
    }
    return 0.0;
}

// Both at once, for light sampling: one switch instead of two keeps the integrator's code (and
// its register use) smaller, since every call site inlines every model.
vec3 bsdfEvalPdf(GpuMaterial m, vec3 wo, vec3 wi, out float pdf) {
    switch (m.info.x) {
    BSDF_MODELS(BSDF_EVAL_PDF_CASE)
    default: break;
    }
    pdf = 0.0;
    return vec3(0.0);
}

// The diffuse models' sampling: wi ~ cos(theta) over the hemisphere of wo, then the model's own
// value and pdf.
BsdfSample cosineSampled(GpuMaterial m, vec3 wo, vec3 u) {
    BsdfSample s;
    s.wi = lambertSample(wo, u.xy);
    s.f = bsdfEvalPdf(m, wo, s.wi, s.pdf);
    s.flags = 0u;
    return s;
}

// u.xy: the direction, u.z: the choice between lobes (dielectrics).
BsdfSample bsdfSample(GpuMaterial m, vec3 wo, vec3 u) {
    BsdfSample s = bsdfInvalidSample();
    switch (m.info.x) {
    BSDF_MODELS(BSDF_SAMPLE_CASE)
    default: break;
    }
    bool finite = !any(isnan(s.f)) && !any(isinf(s.f)) && !isnan(s.pdf) && !isinf(s.pdf);
    if (!(s.pdf > 0.0) || !finite || s.wi.z == 0.0 || !(maxComponent(s.f) > 0.0)) return bsdfInvalidSample();
    return s;
}

bool bsdfIsBlack(GpuMaterial m) { return m.info.x == MAT_DIFFUSE && maxComponent(m.albedo.rgb) <= 0.0; }

#endif
