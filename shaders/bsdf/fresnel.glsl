// Fresnel reflectance of smooth interfaces (unpolarised light: the mean of the s and p terms).
//   fresnelDielectric: real relative IOR eta = n_inside / n_outside, incident cosine measured
//     against the normal that points outside; a negative cosine means the light arrives from
//     inside, and the indices are swapped (eta -> 1/eta). Total internal reflection returns 1.
//   fresnelComplex: a conductor, complex IOR eta + i k per RGB channel (the outside is vacuum/air).
// Reference: Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., sec. 9.3.2 (eqs.
// 9.4-9.6) and 9.3.6 (the same equations with complex arithmetic); Born & Wolf, sec. 1.5.2.
#ifndef BSDF_FRESNEL_GLSL
#define BSDF_FRESNEL_GLSL
#include "../lib/math.glsl"

float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = clamp(cosThetaI, -1.0, 1.0);
    if (cosThetaI < 0.0) {
        eta = 1.0 / eta;
        cosThetaI = -cosThetaI;
    }
    float sin2ThetaI = 1.0 - cosThetaI * cosThetaI;
    float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1.0) return 1.0;  // total internal reflection
    float cosThetaT = safeSqrt(1.0 - sin2ThetaT);
    float rParl = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    float rPerp = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5 * (rParl * rParl + rPerp * rPerp);
}

// Refraction of wi (pointing away from the surface) through the interface with normal n and
// relative IOR eta (inside over outside, n pointing outside). Returns false on total internal
// reflection; etap is the IOR ratio actually crossed (eta entering, 1/eta leaving).
bool refractDir(vec3 wi, vec3 n, float eta, out float etap, out vec3 wt) {
    float cosThetaI = dot(n, wi);
    if (cosThetaI < 0.0) {
        eta = 1.0 / eta;
        cosThetaI = -cosThetaI;
        n = -n;
    }
    etap = eta;
    wt = vec3(0.0);
    float sin2ThetaI = max(0.0, 1.0 - cosThetaI * cosThetaI);
    float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1.0) return false;
    float cosThetaT = safeSqrt(1.0 - sin2ThetaT);
    wt = -wi / eta + (cosThetaI / eta - cosThetaT) * n;
    return true;
}

// Complex numbers as vec2(re, im).
vec2 cmul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 cdiv(vec2 a, vec2 b) {
    float d = dot(b, b);
    return vec2(a.x * b.x + a.y * b.y, a.y * b.x - a.x * b.y) / d;
}
float cnorm(vec2 a) { return dot(a, a); }
// Principal square root (pbrt-v4 pstd::sqrt(complex)).
vec2 csqrt(vec2 z) {
    float n = length(z);
    if (n == 0.0) return vec2(0.0);
    float t1 = sqrt(0.5 * (n + abs(z.x)));
    float t2 = 0.5 * z.y / t1;
    if (z.x >= 0.0) return vec2(t1, t2);
    return vec2(abs(t2), z.y >= 0.0 ? t1 : -t1);
}

float fresnelComplex1(float cosThetaI, vec2 eta) {
    cosThetaI = clamp(cosThetaI, 0.0, 1.0);
    float sin2ThetaI = 1.0 - cosThetaI * cosThetaI;
    vec2 sin2ThetaT = cdiv(vec2(sin2ThetaI, 0.0), cmul(eta, eta));
    vec2 cosThetaT = csqrt(vec2(1.0, 0.0) - sin2ThetaT);
    vec2 ci = vec2(cosThetaI, 0.0);
    vec2 etaCi = eta * cosThetaI;
    vec2 etaCt = cmul(eta, cosThetaT);
    vec2 rParl = cdiv(etaCi - cosThetaT, etaCi + cosThetaT);
    vec2 rPerp = cdiv(ci - etaCt, ci + etaCt);
    return 0.5 * (cnorm(rParl) + cnorm(rPerp));
}

vec3 fresnelComplex(float cosThetaI, vec3 eta, vec3 k) {
    return vec3(fresnelComplex1(cosThetaI, vec2(eta.r, k.r)), fresnelComplex1(cosThetaI, vec2(eta.g, k.g)),
                fresnelComplex1(cosThetaI, vec2(eta.b, k.b)));
}

#endif
