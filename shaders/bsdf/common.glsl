// What every BSDF model file shares: the sample record and its flags, and small local-frame
// helpers. Conventions (docs/materials.md, style.md): local frame with +z the shading normal, wo
// towards the viewer, wi towards the light; xxxEval returns f without the cosine, xxxPdf the
// solid-angle pdf of xxxSample, xxxSample a BsdfSample. Delta lobes return 0 from eval and pdf and
// set BSDF_FLAG_DELTA; their sample's pdf is the discrete probability of the chosen lobe and f is
// the delta's coefficient divided by |cos(wi)|, so f * |cos| / pdf is the weight as for any lobe.
#ifndef BSDF_COMMON_GLSL
#define BSDF_COMMON_GLSL
#include "../lib/math.glsl"
#include "../scene/buffers.glsl"

#define BSDF_FLAG_DELTA 1u
#define BSDF_FLAG_TRANSMISSION 2u

struct BsdfSample {
    vec3 wi;       // local frame
    vec3 f;        // BSDF value (without the cosine)
    float pdf;     // solid-angle pdf; for delta lobes the discrete probability of the lobe
    uint flags;    // BSDF_FLAG_*
};

BsdfSample bsdfInvalidSample() {
    BsdfSample s;
    s.wi = vec3(0.0, 0.0, 1.0);
    s.f = vec3(0.0);
    s.pdf = 0.0;
    s.flags = 0u;
    return s;
}

bool sameHemisphere(vec3 a, vec3 b) { return a.z * b.z > 0.0; }
vec3 reflectLocal(vec3 wo) { return vec3(-wo.x, -wo.y, wo.z); }
// Mirror reflection of wo about the unit vector n.
vec3 reflectAbout(vec3 wo, vec3 n) { return -wo + 2.0 * dot(wo, n) * n; }

#endif
