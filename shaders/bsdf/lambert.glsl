// Lambertian reflection: f = albedo / pi on the upper hemisphere, cosine-weighted sampling.
// JSON: { "type": "diffuse", "albedo": [r, g, b] in [0, 1] }.
// Local frame: +z is the shading normal, wo points to the viewer, wi to the light.
#ifndef BSDF_LAMBERT_GLSL
#define BSDF_LAMBERT_GLSL
#include "common.glsl"
#include "../lib/sampling.glsl"

vec3 lambertEval(vec3 albedo, vec3 wo, vec3 wi) {
    return (wo.z > 0.0 && wi.z > 0.0) ? albedo * INV_PI : vec3(0.0);
}

float lambertPdf(vec3 wo, vec3 wi) {
    return (wo.z > 0.0 && wi.z > 0.0) ? cosineHemispherePdf(wi.z) : 0.0;
}

// Returns wi; the weight f * cos / pdf is exactly the albedo.
vec3 lambertSample(vec3 wo, vec2 u) {
    vec3 wi = sampleCosineHemisphere(u);
    return wi;
}

#endif
