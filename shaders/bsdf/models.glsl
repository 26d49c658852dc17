// The one list of material models: each line names a model's MAT_* id (shaders/shared/layout.h)
// and how bsdf.glsl evaluates, weighs and samples it, as expressions in the names every BSDF
// operation has in scope (GpuMaterial m; vec3 wo, wi; vec3 u: u.xy the direction, u.z the choice
// between lobes), and its traits. bsdf.glsl expands this list into each of its operations, so
// there is no hand-written switch to keep in step: a new model is its own file (included below)
// and one line here (docs/design.md, "Adding a BSDF").
//   MODEL(id, eval, pdf, sample, traits)
//   eval:   f(wo, wi) * 1 (cosine not included), vec3(0.0) for delta models
//   pdf:    solid-angle pdf of sampling wi, 0.0 for delta models
//   sample: a BsdfSample (cosineSampled() draws wi ~ cos and evaluates the model)
//   traits: BSDF_DELTA (every lobe is a delta: light sampling is useless), BSDF_TRANSMITS (the
//           local frame keeps the front side: wo.z < 0 means inside)
#ifndef BSDF_MODELS_GLSL
#define BSDF_MODELS_GLSL
#include "common.glsl"
#include "lambert.glsl"
#include "oren_nayar.glsl"
#include "specular.glsl"
#include "dielectric.glsl"
#include "conductor.glsl"
#include "surface.glsl"
#include "thin.glsl"

#define BSDF_DELTA 1u
#define BSDF_TRANSMITS 2u

#define BSDF_MODELS(MODEL)                                                                                  \
    MODEL(MAT_DIFFUSE, lambertEval(m.albedo.rgb, wo, wi), lambertPdf(wo, wi), cosineSampled(m, wo, u), 0u)  \
    MODEL(MAT_OREN_NAYAR, orenNayarEval(m, wo, wi), orenNayarPdf(wo, wi), cosineSampled(m, wo, u), 0u)     \
    MODEL(MAT_EON, eonEval(m, wo, wi), orenNayarPdf(wo, wi), cosineSampled(m, wo, u), 0u)                  \
    MODEL(MAT_MIRROR, vec3(0.0), 0.0, mirrorSample(m, wo), BSDF_DELTA)                                      \
    MODEL(MAT_TRANSMISSION, vec3(0.0), 0.0, transmissionSample(m, wo), BSDF_DELTA | BSDF_TRANSMITS)         \
    MODEL(MAT_DIELECTRIC, vec3(0.0), 0.0, smoothDielectricSample(m, wo, u.z), BSDF_DELTA | BSDF_TRANSMITS)  \
    MODEL(MAT_ROUGH_DIELECTRIC, roughDielectricEval(m, wo, wi), roughDielectricPdf(m, wo, wi),              \
          roughDielectricSample(m, wo, u.z, u.xy), BSDF_TRANSMITS)                                          \
    MODEL(MAT_CONDUCTOR, vec3(0.0), 0.0, smoothConductorSample(m, wo), BSDF_DELTA)                          \
    MODEL(MAT_ROUGH_CONDUCTOR, roughConductorEval(m, wo, wi), roughConductorPdf(m, wo, wi),                 \
          roughConductorSample(m, wo, u.xy), 0u)                                                           \
    MODEL(MAT_SURFACE, surfaceEval(m, wo, wi), surfacePdf(m, wo, wi), surfaceSample(m, wo, u), 0u)         \
    MODEL(MAT_THIN_DIELECTRIC, thinDielectricEval(m, wo, wi), thinDielectricPdf(m, wo, wi),               \
          thinDielectricSample(m, wo, u.z, u.xy), thinIsSmooth(m) ? BSDF_DELTA | BSDF_TRANSMITS : BSDF_TRANSMITS) \
    MODEL(MAT_DIFFUSE_TRANSMISSION, diffuseTransmissionEval(m, wo, wi), diffuseTransmissionPdf(m, wo, wi), \
          diffuseTransmissionSample(m, wo, u), BSDF_TRANSMITS)

#endif
