// Sampling warps, in pairs: sampleX(u) and xPdf(...). Solid-angle pdfs unless stated.
// Formulas: Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., ch. A.5.
#ifndef LIB_SAMPLING_GLSL
#define LIB_SAMPLING_GLSL
#include "math.glsl"

// Shirley-Chiu concentric map from [0,1)^2 to the unit disk (area-preserving).
vec2 sampleConcentricDisk(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
    float r, theta;
    if (abs(o.x) > abs(o.y)) { r = o.x; theta = (PI / 4.0) * (o.y / o.x); }
    else { r = o.y; theta = PI / 2.0 - (PI / 4.0) * (o.x / o.y); }
    return r * vec2(cos(theta), sin(theta));
}

// Cosine-weighted hemisphere around +z (Malley's method).
vec3 sampleCosineHemisphere(vec2 u) {
    vec2 d = sampleConcentricDisk(u);
    return vec3(d, safeSqrt(1.0 - dot(d, d)));
}
float cosineHemispherePdf(float cosTheta) { return max(cosTheta, 0.0) * INV_PI; }

vec3 sampleUniformSphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = safeSqrt(1.0 - z * z);
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}
float uniformSpherePdf() { return INV_4PI; }

// Uniform directions in the cone around +z with cos(half-angle) = cosThetaMax.
vec3 sampleUniformCone(vec2 u, float cosThetaMax) {
    float cosTheta = (1.0 - u.x) + u.x * cosThetaMax;
    float sinTheta = safeSqrt(1.0 - cosTheta * cosTheta);
    float phi = 2.0 * PI * u.y;
    return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}
float uniformConePdf(float cosThetaMax) { return 1.0 / (2.0 * PI * (1.0 - cosThetaMax)); }

// Veach's power heuristic with beta = 2 (Veach 1997, eq. 9.13).
float powerHeuristic(float pdfA, float pdfB) {
    float a = pdfA * pdfA, b = pdfB * pdfB;
    if (isinf(a)) return 1.0;
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

#endif
